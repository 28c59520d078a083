"""Walk balance (gyro feedback on the walks' leg joints): the offsets, where they apply, how they reach the
commands, and the TOML section that carries them."""

from __future__ import annotations

import dataclasses
import math

import pytest

from agent.motion import DynamicParams, MotionController, MotionLibrary, WalkBalance, load_dynamic_params
from agent.motion.controller import ControllerConfig
from agent.motion.dynamic import dumps_dynamic_params
from motions import XML, JointTarget, Keyframe, Motion


def test_the_offset_adds_pitch_and_roll_terms_and_stays_within_its_bound():
    balance = WalkBalance({"le3": 0.02, "le5": -0.01}, {"le6": 0.03}, max_offset_deg=4.0)
    gyro = (50.0, -20.0, 300.0)  # deg/s about x (pitch), y (roll), z (yaw: never used)
    assert balance.offset_deg("le3", gyro) == pytest.approx(1.0)
    assert balance.offset_deg("le5", gyro) == pytest.approx(-0.5)
    assert balance.offset_deg("le6", gyro) == pytest.approx(-0.6)
    assert balance.offset_deg("le1", gyro) == 0.0
    assert balance.offset_deg("le3", (400.0, 0.0, 0.0)) == 4.0  # 8 deg asked, bounded
    assert balance.offset_deg("le3", (-400.0, 0.0, 0.0)) == -4.0


def test_it_applies_to_walks_or_to_the_named_motions_and_only_with_gains():
    assert not WalkBalance().applies("walk_forward", is_walk=True)
    on = WalkBalance({"le3": 0.01})
    assert on.applies("walk_forward", is_walk=True) and not on.applies("stand", is_walk=False)
    named = WalkBalance({"le3": 0.01}, motions=("walk_fast",))
    assert named.applies("walk_fast", is_walk=True) and not named.applies("walk_forward", is_walk=True)


def test_a_bad_gain_is_refused_with_the_file_and_section(tmp_path):
    with pytest.raises(ValueError, match="finite"):
        WalkBalance({"le3": math.nan})
    with pytest.raises(ValueError, match="max_offset_deg"):
        WalkBalance(max_offset_deg=-1.0)
    path = tmp_path / "dynamic.toml"
    path.write_text("[walk_balance]\npitch_gains_deg_per_deg_s = { le3 = 0.01 }\nroll_gain = 1\n", encoding="utf-8")
    with pytest.raises(ValueError, match=r"dynamic\.toml: \[walk_balance\] has unknown keys \['roll_gain'\]"):
        load_dynamic_params(path)


def test_the_section_survives_a_write_and_a_read(tmp_path):
    balance = WalkBalance({"le3": 0.01}, {"le6": 0.02, "le2": -0.005}, ("walk_fast",), 6.0, "scan of 2026-11-29")
    path = tmp_path / "dynamic.toml"
    path.write_text(dumps_dynamic_params(DynamicParams(walk_balance=balance), "test"), encoding="utf-8")
    assert load_dynamic_params(path).walk_balance == balance


def test_the_shipped_walks_play_without_feedback():
    """The matches, benchmarks and transfer figures were measured open loop: the feedback is the users' to
    switch on (the shipped file documents what it did for a fast gait)."""
    assert not load_dynamic_params().walk_balance.active


def _controller(balance: WalkBalance) -> MotionController:
    phases = [Keyframe("a", 0.1, {"llj3": JointTarget.from_deg(10.0), "rlj3": JointTarget.from_deg(10.0),
                                  "llj5": JointTarget.from_deg(-5.0)})]
    walk = Motion("walk", phases, source_format=XML, first_phase="a", constants={"speed_m_s": 0.5})
    stand = Motion("stand", phases, source_format=XML, first_phase="a")
    library = MotionLibrary({"walk": walk, "stand": stand})
    return MotionController(library, DynamicParams(walk_balance=balance),
                            config=ControllerConfig(blend_speed_rad_s=1e3))


@pytest.mark.parametrize("motion", ["walk", "stand"])
def test_the_gyro_moves_the_walks_targets_and_nothing_else(motion):
    """First cycle of a 100 ms phase: the command is (target + offset - angle) / 0.1 s; both legs get the
    offset of their kind; the torso pitching at 100 deg/s with 0.02 deg per deg/s on le3 moves its target 2 deg."""
    angles = {"llj3": 0.0, "rlj3": 0.0, "llj5": 0.0}
    open_loop = _controller(WalkBalance({"le3": 0.02}))
    open_loop.request(motion)
    plain = open_loop.update(angles, gyro_deg_s=None)
    fed = _controller(WalkBalance({"le3": 0.02}))
    fed.request(motion)
    out = fed.update(angles, gyro_deg_s=(100.0, 0.0, 0.0))
    assert plain["lle3"] == pytest.approx(math.radians(10.0) / 0.1)
    shift = math.radians(2.0) / 0.1 if motion == "walk" else 0.0
    assert out["lle3"] == pytest.approx(plain["lle3"] + shift)
    assert out["rle3"] == pytest.approx(plain["rle3"] + shift)
    assert out["lle5"] == pytest.approx(plain["lle5"])


def test_the_agent_feeds_its_gyro_to_the_walk_on_our_simulator():
    """End to end on MuJoCo: SkillBehavior hands the GYR perceptor to the controller, so gains change the walk
    (a strong hip-pitch gain makes walk_forward go elsewhere within 2 s); without gains it is the open-loop walk."""
    from agent.motion import default_library
    from motion_studio.walk_rollout import run_walk

    library = default_library()
    shipped = load_dynamic_params()
    open_loop = run_walk(library, "walk_forward", 2.0, stop_s=0.0, dynamic=shipped)
    zero_gains = run_walk(library, "walk_forward", 2.0, stop_s=0.0,
                          dynamic=dataclasses.replace(shipped, walk_balance=WalkBalance({"le3": 0.0})))
    fed = run_walk(library, "walk_forward", 2.0, stop_s=0.0,
                   dynamic=dataclasses.replace(shipped, walk_balance=WalkBalance({"le3": 0.05})))
    assert zero_gains.truths[-1].torso_m == open_loop.truths[-1].torso_m
    assert math.dist(fed.truths[-1].torso_m, open_loop.truths[-1].torso_m) > 0.01
