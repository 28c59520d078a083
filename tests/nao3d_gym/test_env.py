"""The Nao3D Gymnasium environments: registration, gymnasium's checker, observations from the wire, clipping,
seeding, termination, rewards and vectorised envs."""

from __future__ import annotations

import math
import warnings

import gymnasium
import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env

import nao3d_gym
from agent.protocol.sense import parse_sense
from kinematics.spec import robot_spec
from nao3d_gym.tasks import WALK_ALIVE_BONUS, StepState, stand_reward, walk_reward

IDS = sorted(nao3d_gym.ENVIRONMENTS)


def test_importing_the_toolkit_registers_nao3d_ids() -> None:
    registered = [env_id for env_id in gymnasium.registry if env_id.startswith("Nao3D")]
    assert sorted(registered) == IDS == ["Nao3D-Stand-v0", "Nao3D-Walk-v0"]
    assert gymnasium.spec("Nao3D-Walk-v0").max_episode_steps == 1000


@pytest.mark.parametrize("env_id", IDS)
def test_gymnasiums_checker_passes(env_id: str) -> None:
    env = gymnasium.make(env_id)
    with warnings.catch_warnings():
        # The action space is in rad/s as the issue asks, not normalised to [-1, 1]: the one expected warning.
        warnings.simplefilter("error")
        warnings.filterwarnings("ignore", message=".*symmetric and normalized space.*")
        check_env(env.unwrapped, skip_render_check=True)
    env.close()


def test_observation_is_the_parsed_sense_message() -> None:
    # The text path (test_fast_path.py ties the default fast path to it bit for bit).
    env = gymnasium.make("Nao3D-Stand-v0", text_sense=True).unwrapped
    obs, _ = env.reset(seed=3)
    obs, *_ = env.step(np.zeros(22, dtype=np.float32))
    sense = parse_sense(env.last_sense)
    joints = robot_spec(0).joints
    assert obs.shape == (40,) and obs.dtype == np.float32
    assert obs[:22] == pytest.approx([math.radians(sense.joints[j.perceptor]) for j in joints], abs=1e-6)
    assert obs[22:25] == pytest.approx([math.radians(v) for v in sense.gyro.rate_deg_s], abs=1e-6)
    assert obs[25:28] == pytest.approx(sense.acc.acc_m_s2, abs=1e-5)
    assert obs[27] == pytest.approx(9.81, abs=0.5)   # standing still: gravity on the accelerometer's z
    assert obs[33] + obs[39] == pytest.approx(robot_spec(0).total_mass_kg * 9.81, rel=0.15)  # feet carry it


def test_actions_are_clipped_to_the_joint_speed_limit() -> None:
    """A command far past the limit moves the head exactly as the limit itself does."""
    env = gymnasium.make("Nao3D-Stand-v0").unwrapped
    limit = env.action_space.high[0]
    assert limit == pytest.approx(6.1395, abs=1e-4)
    finals = []
    for value in (100.0, float(limit)):
        env.reset(seed=5)
        action = np.zeros(22, dtype=np.float32)
        action[0] = value
        for _ in range(6):
            obs, *_ = env.step(action)
        finals.append(obs[0])
    assert finals[0] == finals[1] and finals[0] > 0.1  # he1 turned, at the limit speed either way


def test_a_seed_fixes_the_episode_and_another_seed_changes_it() -> None:
    env = gymnasium.make("Nao3D-Walk-v0")
    rng = np.random.default_rng(0)
    actions = rng.uniform(-1, 1, (30, 22)).astype(np.float32)

    def rollout(seed: int) -> np.ndarray:
        obs, _ = env.reset(seed=seed)
        trace = [obs]
        for action in actions:
            trace.append(env.step(action)[0])
        return np.array(trace)

    first, again, other = rollout(11), rollout(11), rollout(12)
    assert np.array_equal(first, again)
    assert not np.allclose(first[0], other[0])


def test_standing_still_pays_and_a_fall_ends_the_episode() -> None:
    env = gymnasium.make("Nao3D-Stand-v0")
    env.reset(seed=0)
    rewards = [env.step(np.zeros(22, dtype=np.float32))[1] for _ in range(50)]
    assert min(rewards) > 0.95
    # Both hip pitches (llj3, rlj3) driven forward at full speed: the robot folds and falls.
    action = np.zeros(22, dtype=np.float32)
    names = [j.perceptor for j in robot_spec(0).joints]
    for name in ("llj3", "rlj3", "llj4", "rlj4"):
        action[names.index(name)] = -6.0 if name.endswith("3") else 6.0
    for step in range(200):
        _, _, terminated, truncated, info = env.step(action)
        if terminated:
            break
    assert terminated and not truncated and info["torso_position_m"][2] < 0.25


def test_rewards() -> None:
    still = np.zeros(22)
    upright = StepState(np.array([0.0, 0, 0.38]), np.array([0.0, 0, 0.38]), 1.0, 0.02, still)
    assert stand_reward(upright) == 1.0
    flailing = StepState(upright.torso_before_m, upright.torso_after_m, 1.0, 0.02, np.ones(22))
    assert stand_reward(flailing) == pytest.approx(0.99)
    forward = StepState(np.array([0.0, 0, 0.38]), np.array([0.01, 0.002, 0.38]), 1.0, 0.02, still)
    assert walk_reward(forward) == pytest.approx(0.5 - 0.1 + WALK_ALIVE_BONUS)


@pytest.mark.parametrize("mode", ["sync", "async"])
def test_vectorised_envs_step_like_single_envs(mode: str) -> None:
    envs = gymnasium.make_vec("Nao3D-Stand-v0", num_envs=2, vectorization_mode=mode)
    try:
        obs, _ = envs.reset(seed=[21, 22])
        assert obs.shape == (2, 40)
        action = np.zeros((2, 22), dtype=np.float32)
        action[:, 0] = 1.0
        obs, rewards, terminated, truncated, _ = envs.step(action)
    finally:
        envs.close()
    single = gymnasium.make("Nao3D-Stand-v0")
    single.reset(seed=22)
    expected = single.step(action[1])[0]
    assert np.array_equal(obs[1], expected)
    assert rewards.shape == (2,) and not terminated.any() and not truncated.any()


def test_bad_arguments_name_the_argument() -> None:
    with pytest.raises(ValueError, match="task must be one of"):
        gymnasium.make("Nao3D-Stand-v0", task="dance")
    with pytest.raises(ValueError, match="robot_type"):
        gymnasium.make("Nao3D-Stand-v0", robot_type=7)
