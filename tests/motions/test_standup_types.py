"""Per-type stand-ups: the shipped type-4 files are what the generator makes from today's parameters, their
crouch and rise put the CoM over type 4's own soles, and they end in the shared stand pose."""

import math

import pytest

from kinematics.fk import torso_rotation
from motions import load
from motions.authoring.common import FILES_DIR
from motions.authoring.standup import STANDUPS, SagittalSolver, load_standup_params
from motions.authoring.standup_types import TYPES, build_for_type, type_params_path, write_all


@pytest.mark.parametrize("robot_type", TYPES)
def test_shipped_type_standups_match_the_generator(tmp_path, robot_type):
    for path in write_all(tmp_path, (robot_type,)):
        fresh, shipped = load(path), load(FILES_DIR / f"type{robot_type}" / path.name)
        assert [k.name for k in fresh.keyframes] == [k.name for k in shipped.keyframes], path.name
        for a, b in zip(fresh.keyframes, shipped.keyframes):
            assert a.duration_s == pytest.approx(b.duration_s)
            for wire, target in a.targets.items():
                assert b.targets[wire].angle_rad == pytest.approx(target.angle_rad, abs=math.radians(0.05)), \
                    (path.name, a.name, wire)


def test_type_4_crouch_has_its_com_over_its_own_soles_where_type_0_angles_would_not():
    params = load_standup_params(type_params_path(4))["standup_back"]
    motion = build_for_type(4)["standup_back"]
    crouch = {w: t.angle_rad for w, t in motion.phase("crouch").targets.items()}
    type4, type0 = SagittalSolver(4).kinematics, SagittalSolver(0).kinematics
    rotation = torso_rotation(math.radians(params.crouch_pitch_deg))

    def com_ahead_of_sole(kinematics, angles):
        com = rotation @ kinematics.com(angles)
        sole = rotation @ kinematics.frame_pose("lsole", angles).position_m
        return float(com[1] - sole[1])

    assert com_ahead_of_sole(type4, crouch) == pytest.approx(params.crouch_com_forward_m, abs=2e-4)
    type0_back = build_for_type(0, type_params_path(4))["standup_back"]   # the same parameters solved for type 0
    type0_crouch = {w: t.angle_rad for w, t in type0_back.phase("crouch").targets.items()}
    # Type 0's angles on type 4: the CoM lies ~1.8 cm further ahead of its (shorter, rearward) foot box.
    assert com_ahead_of_sole(type4, type0_crouch) - params.crouch_com_forward_m > 0.01


def test_type_standups_end_in_the_shared_stand_pose():
    stand = load(FILES_DIR / "stand.xml").keyframes[-1]
    motions = build_for_type(4)
    for name in STANDUPS:
        last = motions[name].keyframes[-1]
        for wire, target in last.targets.items():
            assert target.angle_rad == pytest.approx(stand.targets[wire].angle_rad, abs=math.radians(0.02)), wire


def test_type_3_keeps_the_three_phase_roll_to_back_and_the_others_play_the_shared_one():
    """The shared roll is one keyframe since 2026-11-28 (faster on both servers for types 0, 1, 2 and 4); type 3's
    parameter file keeps the three-phase roll of before (with the new one its side lies stood on ours 4 of 10), so
    its folder gets its own roll and the other types' folders none."""
    shared = load(FILES_DIR / "roll_to_back.xml")
    own = build_for_type(3)["roll_to_back"]
    assert [k.name for k in shared.keyframes] == ["roll"]
    assert [k.name for k in own.keyframes] == ["arms_out", "curl", "flat"]
    assert [k.duration_s for k in own.keyframes] == pytest.approx([0.15, 0.15, 0.15])
    for robot_type in (1, 2, 4):
        assert "roll_to_back" not in build_for_type(robot_type)
    assert (FILES_DIR / "type3" / "roll_to_back.xml").is_file()
    assert not (FILES_DIR / "type4" / "roll_to_back.xml").exists()
