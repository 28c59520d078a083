"""The turn generator (motions/authoring/turn.py): outward-only hip yaw, the walk's stance at both ends, the
turn and its gain base as Webots files whose gain-scaled poses turn the feet by gain x turn_deg, and the
playback entries (gain bases, timings, provenance) merged into playback.toml."""

from __future__ import annotations

import math
import tomllib
from dataclasses import replace

import numpy as np
import pytest

import motions
from agent.motion.library import default_library
from kinematics.fk import NaoKinematics
from motions.authoring.common import FILES_DIR, KeyframeSolver
from motions.authoring.gait import stance_pose
from motions.authoring.gait_params import load_gait_params
from motions.authoring.turn import (BASE_NAMES, PARAMS_PATH, STANCE_FIELDS, TURN_NAMES, TurnParams, build_all,
                                    load_turn_params, turn_samples, write_files)

PARAMS = TurnParams(turn_deg=40.0, step_cycles=8, double_support_cycles=2, settle_cycles=1)


@pytest.fixture(scope="module")
def built() -> dict[str, motions.Motion]:
    return build_all(PARAMS)


def _yaw_deg(rotation: np.ndarray) -> float:
    return math.degrees(math.atan2(rotation[1, 0], rotation[0, 0]))


def _soles(kinematics: NaoKinematics, angles: dict[str, float]) -> tuple:
    return kinematics.frame_pose("lsole", angles), kinematics.frame_pose("rsole", angles)


def test_feet_never_turn_inward_and_end_rotated_by_the_turn():
    samples = turn_samples(PARAMS)
    assert len(samples) == PARAMS.cycles
    for sample in samples:  # left turn: left foot yaw >= 0 (outward = left), right foot <= 0
        assert sample.left.yaw_rad >= -1e-12 and sample.right.yaw_rad <= 1e-12
        assert sample.left.z_m >= 0.0 and sample.right.z_m >= 0.0
        assert min(sample.left.z_m, sample.right.z_m) == 0.0  # always one foot on the ground
    first, last = samples[0], samples[-1]
    for a, b in ((first.left, last.left), (first.right, last.right)):  # the stance, relative to the torso
        assert (a.x_m, a.y_m, a.z_m, a.yaw_rad) == pytest.approx((b.x_m, b.y_m, b.z_m, b.yaw_rad), abs=1e-12)
    mid = samples[PARAMS.settle_cycles + PARAMS.step_cycles]  # the left foot has landed
    assert math.degrees(mid.left.yaw_rad - mid.right.yaw_rad) == pytest.approx(PARAMS.turn_deg)


def test_hip_yaw_opens_outward_only_and_base_has_none(built):
    for name in (TURN_NAMES["left"], TURN_NAMES["right"]):
        yaws = [k.targets[j].angle_deg for k in built[name].keyframes for j in ("llj1", "rlj1")]
        # Range -90..1 deg: negative opens the foot. Up to a degree above 0 occurs where the tilted yaw-pitch
        # axis helps the hip roll of the sway while the feet are parallel.
        assert max(yaws) <= 1.0 and min(yaws) < -20.0
    for name in BASE_NAMES.values():
        assert all(abs(k.targets[j].angle_deg) < 1.0 for k in built[name].keyframes for j in ("llj1", "rlj1"))


def test_right_turn_mirrors_left(built):
    left, right = built[TURN_NAMES["left"]], built[TURN_NAMES["right"]]
    for kl, kr in zip(left.keyframes, right.keyframes):
        assert kr.targets["rlj1"].angle_deg == pytest.approx(kl.targets["llj1"].angle_deg)
        assert kr.targets["rlj2"].angle_deg == pytest.approx(-kl.targets["llj2"].angle_deg)
        assert kr.targets["rlj3"].angle_deg == pytest.approx(kl.targets["llj3"].angle_deg)


@pytest.mark.parametrize("toe_out_deg", [0.0, 3.0])
def test_starts_and_ends_in_the_walk_stance(toe_out_deg):
    stand = replace(load_gait_params()["stand"], toe_out_deg=toe_out_deg)
    params = replace(PARAMS, **{name: getattr(stand, name) for name in STANCE_FIELDS})
    turn = build_all(params)[TURN_NAMES["left"]]
    stance = stance_pose(stand, KeyframeSolver())
    # Both are IK solutions of the same targets from different warm starts: equal within the solver's
    # convergence (measured up to 0.08 deg with a 3 deg toe-out), far below what a servo resolves.
    for keyframe in (turn.keyframes[0], turn.keyframes[-1]):
        for wire, target in keyframe.targets.items():
            assert target.angle_deg == pytest.approx(math.degrees(stance[wire]), abs=0.15), wire


@pytest.mark.parametrize("gain", [0.3, 0.6, 1.0])
def test_gain_scaled_poses_turn_the_feet_by_gain_times_turn(built, gain):
    """What the controller plays (base + gain x (turn - base)) keeps the soles flat and level with each
    other when both are down, and turns them gain x turn_deg apart."""
    kinematics = NaoKinematics()
    turn, base = built[TURN_NAMES["left"]], built[BASE_NAMES["left"]]
    index = PARAMS.settle_cycles + PARAMS.step_cycles  # both feet down, the left one turned
    angles = {w: b.angle_rad + gain * (t.angle_rad - b.angle_rad)
              for (w, t), b in zip(turn.keyframes[index].targets.items(), base.keyframes[index].targets.values())}
    left, right = _soles(kinematics, angles)
    assert _yaw_deg(right.rotation.T @ left.rotation) == pytest.approx(gain * PARAMS.turn_deg, abs=1.5)
    assert left.position_m[2] == pytest.approx(right.position_m[2], abs=0.004)
    for sole in (left, right):
        torso_up = np.array([0.0, -math.sin(math.radians(PARAMS.torso_pitch_deg)),
                             math.cos(math.radians(PARAMS.torso_pitch_deg))])  # ground normal in torso axes
        assert math.degrees(math.acos(min(1.0, float(sole.rotation[:, 2] @ torso_up)))) < 2.0


def test_files_and_playback_entries(tmp_path):
    (tmp_path / "playback.toml").write_text('[gain_bases]\nother = "other_base"\n\n[webots_timing]\n'
                                            'kick = { duration_cycles = 3 }\n')
    paths = write_files(PARAMS, tmp_path)
    assert sorted(p.name for p in paths) == sorted(f"{n}.motion" for n in (*TURN_NAMES.values(), *BASE_NAMES.values()))
    for path in paths:
        motion = motions.load(path)
        assert len(motion.keyframes) == PARAMS.cycles
        assert len(motion.joints()) == 22
    settings = tomllib.loads((tmp_path / "playback.toml").read_text())
    assert settings["gain_bases"] == {"other": "other_base", "turn_left": "turn_left_base",
                                      "turn_right": "turn_right_base"}
    assert settings["webots_timing"]["kick"] == {"duration_cycles": 3}
    assert "motions.authoring.turn" in settings["provenance"]["turn_left"]
    library = default_library(folder=tmp_path)
    assert library.gain_bases["turn_left"] == "turn_left_base"
    assert library.timing("turn_right").use_file_times


def test_shipped_parameters_load_with_the_walk_stance():
    params = load_turn_params(PARAMS_PATH)
    stand = load_gait_params()["stand"]
    assert params.torso_height_m == stand.torso_height_m and params.foot_spacing_m == stand.foot_spacing_m


def test_bad_parameters_are_named(tmp_path):
    path = tmp_path / "turn.toml"
    path.write_text("[turn]\nturn_degs = 30\n")
    with pytest.raises(ValueError, match="turn_degs"):
        load_turn_params(path)
    path.write_text('[turn]\nstance_section = "nowhere"\n')
    with pytest.raises(ValueError, match="nowhere"):
        load_turn_params(path)
    path.write_text("[turn]\nstep_cycles = 4\ndouble_support_cycles = 4\n")
    with pytest.raises(ValueError, match="double_support_cycles"):
        load_turn_params(path)


def test_shipped_turn_files_match_their_parameters():
    """The files in motions/files are what the generator makes of the current parameters (including the
    walk's [stand] stance); if not: python -m motions.authoring.turn, then python -m motion_studio.tune_turn
    --write (the gain curve belongs to the files)."""
    expected = build_all(load_turn_params())
    for name, motion in expected.items():
        shipped = motions.load(FILES_DIR / f"{name}.motion")
        assert len(shipped.keyframes) == len(motion.keyframes), f"{name}: regenerate the turn files"
        for want, have in zip(motion.keyframes, shipped.keyframes):
            for wire, target in want.targets.items():
                assert have.targets[wire].angle_deg == pytest.approx(target.angle_deg, abs=0.011), \
                    f"{name} {want.name} {wire}: regenerate the turn files (python -m motions.authoring.turn)"
