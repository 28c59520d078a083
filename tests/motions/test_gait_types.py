"""Walks of the robot types with longer legs (motions.authoring.gait_types): the posture that reproduces the
type-0 stance angles, the shipped type files equal the generator's output, and start from and stop in
``stand``'s pose."""

from __future__ import annotations

import math

import pytest

from kinematics.fk import NaoKinematics
from motions import load
from motions.authoring.common import FILES_DIR
from motions.authoring.gait_params import load_gait_params
from motions.authoring.gait_types import TYPES_WITH_OWN_WALKS, WALK_NAMES, type_posture, write_type_gait_files


@pytest.fixture(scope="module")
def table():
    return load_gait_params()


def test_type_zero_posture_is_the_parameter_files_posture(table):
    stand = table["stand"]
    assert type_posture(0, stand) == pytest.approx(
        {"torso_height_m": stand.torso_height_m, "torso_forward_m": stand.torso_forward_m,
         "foot_spacing_m": stand.foot_spacing_m}, abs=2e-4)


def test_longer_legs_stand_higher_and_the_wide_hip_wider(table):
    base, long_legs, wide = (type_posture(t, table["stand"]) for t in (0, 1, 3))
    assert long_legs["torso_height_m"] > base["torso_height_m"] + 0.02
    assert wide["torso_height_m"] > long_legs["torso_height_m"]
    assert wide["foot_spacing_m"] > base["foot_spacing_m"] + 0.03  # hips 7.3 cm off the centre, not 5.5


@pytest.mark.parametrize("robot_type", TYPES_WITH_OWN_WALKS)
def test_type_walks_stand_in_the_shared_stance_pose(robot_type):
    stand = load(FILES_DIR / "stand.xml").keyframes[0]
    for name in WALK_NAMES:
        walk = load(FILES_DIR / f"type{robot_type}" / f"{name}.xml")
        for phase in (walk.phase("stance"), walk.phase("stop_hold")):
            for wire, target in stand.targets.items():
                assert phase.targets[wire].angle_rad == pytest.approx(target.angle_rad, abs=math.radians(0.1)), \
                    (name, phase.name, wire)


@pytest.mark.parametrize("robot_type", TYPES_WITH_OWN_WALKS)
def test_type_cycle_keeps_its_soles_level_on_its_own_legs(robot_type):
    # Solved with the type's kinematics: in every cycle keyframe the stance sole is level under the torso's
    # posture (a type-0 file on these legs would tilt nothing but put the feet elsewhere; the check is that
    # the FK of the type reproduces a level, ground-height pair of soles at double support).
    walk = load(FILES_DIR / f"type{robot_type}" / "walk_forward.xml")
    kinematics = NaoKinematics(robot_type)
    angles = {wire: t.angle_rad for wire, t in walk.phase("stance").targets.items()}
    left, right = kinematics.frame_pose("lsole", angles), kinematics.frame_pose("rsole", angles)
    assert left.position_m[2] == pytest.approx(right.position_m[2], abs=1e-3)
    assert abs(left.position_m[0] - right.position_m[0]) == pytest.approx(
        type_posture(robot_type, load_gait_params()["stand"])["foot_spacing_m"], abs=2e-3)


@pytest.mark.parametrize("robot_type", TYPES_WITH_OWN_WALKS)
def test_shipped_type_files_match_the_generator(tmp_path, robot_type):
    for path in write_type_gait_files(robot_type, out_root=tmp_path):
        fresh, shipped = load(path), load(FILES_DIR / f"type{robot_type}" / path.name)
        assert [k.name for k in fresh.keyframes] == [k.name for k in shipped.keyframes]
        assert fresh.constants == shipped.constants
        for a, b in zip(fresh.keyframes, shipped.keyframes):
            for wire, target in a.targets.items():
                assert b.targets[wire].angle_rad == pytest.approx(target.angle_rad, abs=math.radians(0.05)), \
                    (path.name, a.name, wire)
