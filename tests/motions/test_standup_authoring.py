"""The stand-up generator: both motions within the joint limits, flags, the walk stance at the end, the crouch
and rise keyframes with the CoM inside the support polygon (checked with forward kinematics), left-right
symmetry, the sagittal IK, parameter file errors, and the shipped files equal a fresh generation."""

from __future__ import annotations

import math

import numpy as np
import pytest

import motions
from kinematics.fk import NaoKinematics, torso_rotation
from motions.authoring.common import KeyframeSolver
from motions.authoring.gait import STANCE_FLAG, stance_pose
from motions.authoring.standup import (FILES_DIR, PARAMS_PATH, STANDUPS, SagittalSolver, build_all, key_poses,
                                       load_standup_params, parse_standup_params, stance_params,
                                       symmetric_angles_rad)


@pytest.fixture(scope="module")
def generated():
    return build_all()


@pytest.fixture(scope="module")
def standups(generated):
    return {name: motion for name, motion in generated.items() if name in STANDUPS}


def _angles(keyframe) -> dict[str, float]:
    return {wire: target.angle_rad for wire, target in keyframe.targets.items()}


def test_both_standups_with_valid_angles_and_flags(standups):
    assert set(standups) == set(STANDUPS)
    for name, motion in standups.items():
        assert motion.name == name
        motion.validate()  # joint limits, durations, phase names
        first, last = motion.keyframes[0], motion.keyframes[-1]
        assert motion.first_phase == first.name
        assert first.set_flag_false == STANCE_FLAG  # a fallen robot is not in the walk stance
        assert last.set_flag_true == STANCE_FLAG and last.is_final and last.next is None
        chain = [motion.start_phase().name]
        while motion.find_phase(motion.find_phase(chain[-1]).next) is not None:
            chain.append(motion.find_phase(chain[-1]).next)
        assert chain == [k.name for k in motion.keyframes]  # played in file order, once, no loop
        assert all(len(k.targets) == 20 for k in motion.keyframes)  # legs and arms in every phase


def test_standups_end_in_the_walk_stance(standups):
    solver = KeyframeSolver()
    stand = stance_pose(stance_params(), solver)
    for motion in standups.values():
        last = _angles(motion.keyframes[-1])
        assert max(abs(math.degrees(last[j] - stand[j])) for j in last) < 0.01


def test_crouch_and_rise_keep_the_com_inside_the_feet(standups):
    fk = NaoKinematics(0)
    params = load_standup_params()
    stance = stance_params()
    for name, side in STANDUPS.items():
        poses = {p.name: p for p in key_poses(params[name], side, stance)}
        for key in ("crouch", "rise", "stance"):
            assert poses[key].com_margin_m is not None and poses[key].com_margin_m > 0.01, (name, key)
        # independent check of the crouch: soles flat and level, CoM over them, from FK alone
        crouch = poses["crouch"].angles_rad
        rotation = torso_rotation(math.radians(params[name].crouch_pitch_deg))
        left, right = (fk.frame_pose(f, crouch) for f in ("lsole", "rsole"))
        for sole in (left, right):
            assert (rotation @ sole.rotation)[2, 2] > math.cos(math.radians(0.5))  # flat
        assert abs((rotation @ left.position_m)[2] + params[name].crouch_height_m) < 1e-3
        com_y = (rotation @ (fk.com(crouch) - left.position_m))[1]
        assert com_y == pytest.approx(params[name].crouch_com_forward_m, abs=1e-3)


def test_ground_phases_of_the_front_standup_push_up_with_the_arms():
    params = load_standup_params()["standup_front"]
    poses = key_poses(params, "front", stance_params())
    # some ground keyframe props the chest up on the hands (hand tips well below the chest plane)
    assert max(p.prop_depths_m.get("hands", 0.0) for p in poses) > 0.05


def test_front_standup_pushes_up_on_the_hands():
    """The front stand-up first pushes the lying torso up on the hands (they reach more than 5 cm below the
    torso's ground face), checked with forward kinematics. (Since both stand-ups were tuned on the real
    rcssserver3d, where lying parts cannot slide, they pass their frog squats between keyframes, so no
    keyframe of either is a squat on flat feet.)"""
    poses = key_poses(load_standup_params()["standup_front"], "front", stance_params())
    assert any(p.prop_depths_m.get("hands", 0.0) > 0.05 for p in poses[:3])


def test_standups_are_left_right_symmetric(standups):
    for motion in standups.values():
        mirrored = motion.mirrored()
        for a, b in zip(motion.keyframes, mirrored.keyframes):
            assert max(abs(a.targets[j].angle_rad - b.targets[j].angle_rad) for j in a.targets) < 1e-6


def test_symmetric_angles_mirror_like_the_mirror_table():
    table = motions.mirror_table()
    angles = symmetric_angles_rad(-20.0, 10.0, 40.0, -60.0, 30.0, 5.0, -30.0, 20.0, 45.0, 30.0)
    for wire, value in angles.items():
        other, sign = table[wire]
        assert angles[other] == pytest.approx(sign * value)


def test_sagittal_solver_puts_a_flat_foot_under_the_com():
    solver = SagittalSolver()
    arms = {k: v for k, v in symmetric_angles_rad(shoulder_pitch_deg=-60.0).items() if k.startswith(("la", "ra"))}
    angles = solver.com_over_soles(20.0, 0.28, 0.01, arms)
    fk = solver.kinematics
    rotation = torso_rotation(math.radians(20.0))
    sole = fk.frame_pose("lsole", angles)
    assert (rotation @ sole.rotation)[2, 2] > math.cos(math.radians(0.5))
    assert (rotation @ (fk.com(angles) - sole.position_m))[1] == pytest.approx(0.01, abs=2e-4)
    assert solver.com_margin_m(angles, 20.0) > 0.05


def test_unreachable_crouch_is_an_error():
    solver = SagittalSolver()
    with pytest.raises(ValueError, match="no flat-footed crouch"):
        solver.com_over_soles(10.0, 0.15, 0.0, {})


def test_parameter_file_errors_name_the_place():
    with pytest.raises(ValueError, match=r"x.toml \[standup_front\]: unknown keys \['speed'\]"):
        parse_standup_params("[standup_front]\nspeed = 1\n", "x.toml")
    with pytest.raises(ValueError, match=r"ground\[0\]: needs 'name' and 'duration_ms'"):
        parse_standup_params("[standup_front]\n[[standup_front.ground]]\nknee_deg = -30\n", "x.toml")
    with pytest.raises(ValueError, match=r"ground\[0\]: unknown keys \['knee'\]"):
        parse_standup_params("[standup_front]\n[[standup_front.ground]]\nname = 'a'\nduration_ms = 100\n"
                             "knee = -30\n", "x.toml")


def test_roll_to_back_is_a_short_ground_motion(generated):
    roll = generated["roll_to_back"]
    roll.validate()
    assert roll.keyframes[-1].is_final and roll.keyframes[-1].next is None
    assert roll.duration_s <= 1.0
    assert all(k.set_flag_true is None and k.set_flag_false is None for k in roll.keyframes)


def test_shipped_files_match_the_generator(generated):
    for name, motion in generated.items():
        path = FILES_DIR / f"{name}.xml"
        shipped = motions.load(path)
        assert shipped.name == name
        assert [k.name for k in shipped.keyframes] == [k.name for k in motion.keyframes]
        for a, b in zip(shipped.keyframes, motion.keyframes):
            assert a.duration_s == pytest.approx(b.duration_s)
            assert a.set_flag_true == b.set_flag_true and a.set_flag_false == b.set_flag_false
            assert max(abs(a.targets[j].angle_rad - b.targets[j].angle_rad) for j in b.targets) < 1e-6, \
                f"{path} is stale: run python -m motions.authoring.standup"
        assert any(str(PARAMS_PATH.name) in line for line in shipped.header_comments)
