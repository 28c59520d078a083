"""The env's fast path (no effector or sense text) against the text path it stands for.

Same seed and actions: the observations, rewards, ends and the whole physics state must be equal bit for
bit, step by step, through falls and resets, so skipping the text changes nothing a learner sees.
"""

from __future__ import annotations

import numpy as np
import pytest

from nao3d_gym.env import Nao3DEnv


@pytest.mark.parametrize("task, robot_type", [("stand", 0), ("walk", 4)])
def test_fast_path_equals_text_path(task: str, robot_type: int) -> None:
    text = Nao3DEnv(task=task, robot_type=robot_type, text_sense=True)
    fast = Nao3DEnv(task=task, robot_type=robot_type)
    assert fast.text_sense is False and text.text_sense is True
    rng = np.random.default_rng(3)
    high = text.action_space.high
    obs_text, _ = text.reset(seed=7)
    obs_fast, _ = fast.reset(seed=7)
    np.testing.assert_array_equal(obs_fast, obs_text)
    ends, contact_changes = 0, set()
    for step in range(400):
        # Large random velocities: the robot falls within the run, so resets are compared too.
        action = rng.uniform(-high, high).astype(np.float32)
        a = text.step(action)
        b = fast.step(action)
        np.testing.assert_array_equal(b[0], a[0], err_msg=f"observation differs at step {step}")
        assert b[1:4] == a[1:4], step
        contact_changes.add(tuple(a[0][-12:] != 0.0))
        assert np.array_equal(fast._engine.world.data.qpos, text._engine.world.data.qpos), step
        assert np.array_equal(fast._engine.world.data.qvel, text._engine.world.data.qvel), step
        if a[2]:
            ends += 1
            np.testing.assert_array_equal(fast.reset()[0], text.reset()[0])
    assert ends >= 1, "the run should include a fall and a reset"
    assert len(contact_changes) >= 2, "the run should include feet with and without contact"
    assert fast.last_sense == b"" and text.last_sense.startswith(b"(time")


def test_fast_path_sends_no_sense_text() -> None:
    env = Nao3DEnv()
    env.reset(seed=0)
    assert env._engine.step() == {}
    assert Nao3DEnv(vision=True).text_sense is True


@pytest.mark.parametrize("decimals", [2, 4])
def test_fixed_floats_is_the_text_round_trip(decimals: int) -> None:
    """Random values at every scale, exact halves of the last decimal, values a hair off a half, signs, zeros
    (2 decimals: the sense message; 4: the effector message)."""
    from nao3d_gym.observation import fixed_floats
    rng = np.random.default_rng(0)
    halves = (np.arange(-20000, 20000) + 0.5) / 10.0 ** decimals
    values = np.concatenate([
        rng.normal(0.0, 1.0, 50_000), rng.normal(0.0, 300.0, 50_000), rng.uniform(-1e6, 1e6, 10_000),
        halves, np.nextafter(halves, np.inf), np.nextafter(halves, -np.inf),
        [0.0, -0.0, -0.004, 0.005, -0.005, 0.015, 1.005, 2.675, 0.00005, 6.13955, 1e20, -1e20]])
    expected = np.array([float(f"%.{decimals}f" % v) for v in values.tolist()])
    got = fixed_floats(values, decimals)
    np.testing.assert_array_equal(got, expected)
    assert np.array_equal(np.signbit(got), np.signbit(expected))
