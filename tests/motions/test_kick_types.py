"""Long kicks of the robot types with longer legs (motions.authoring.kick_types): solved with the type's own
kinematics, they start and end in the shared ``stand`` pose, keep the CoM over the support sole of the type's own
legs, the shipped files equal a fresh generation, and the type plays them (no longer withheld)."""

from __future__ import annotations

import math

import pytest

import motions
from agent.motion import default_library
from kinematics.fk import NaoKinematics
from motions.authoring.common import FILES_DIR
from motions.authoring.kick import kick_params
from motions.authoring.kick_types import TYPE_KICKS, build_for_type, type_kick_params, type_overrides
from tests.motions.conftest import assert_shipped_as_generated

TYPES = sorted(TYPE_KICKS)
#: The single-support keyframes whose CoM the IK holds (the strike and follow-through add joint offsets after it).
IK_HELD = ("lift", "windup", "swing", "retract")


def _angles(keyframe) -> dict[str, float]:
    return {wire: target.angle_rad for wire, target in keyframe.targets.items()}


@pytest.fixture(scope="module", params=TYPES)
def typed(request):
    return request.param, build_for_type(request.param)


def test_shipped_type_kicks_equal_a_fresh_generation(typed):
    robot_type, built = typed
    for name, motion in built.items():
        assert_shipped_as_generated(motions.load(FILES_DIR / f"type{robot_type}" / f"{name}.xml"), motion)


def test_type_kicks_start_and_end_in_the_shared_stand_pose(typed):
    robot_type, built = typed
    stand = _angles(motions.load(FILES_DIR / "stand.xml").keyframes[0])
    for name, motion in built.items():
        for phase in ("stance", "recover"):
            angles = _angles(motion.phase(phase))
            assert max(abs(angles[w] - stand[w]) for w in stand) < math.radians(0.1), (name, phase)


def _com_over_support_sole_m(fk: NaoKinematics, keyframe) -> tuple[float, float]:
    """The whole-body CoM in the support (left) sole's frame: (x right, y forward) [m]."""
    angles = _angles(keyframe)
    sole = fk.frame_pose("lsole", angles)
    com = sole.rotation.T @ (fk.com(angles) - sole.position_m)
    return float(com[0]), float(com[1])


def test_type_kicks_hold_the_com_over_the_support_sole_of_the_type_s_legs(typed):
    """While the IK holds it (lift, windup, swing, retract), the type's kick on the type's legs keeps the CoM at the
    type's inset and forward offset over the support sole within 5 mm (the windup's joint offsets move it a little); type 0's file on the type's legs misses its own
    targets by more than a centimetre (the robot fell after every long kick on both servers)."""
    robot_type, built = typed
    fk = NaoKinematics(robot_type)
    params, _, _ = type_kick_params(robot_type, "kick_strong")
    want = (params.com_inset_m, params.com_forward_m)
    shared = kick_params("kick_strong")
    type0 = motions.load(FILES_DIR / "kick_strong.xml")
    worst_type0_file = 0.0
    for phase in IK_HELD:
        keyframe = built["kick_strong"].find_phase(phase)
        if keyframe is None:
            continue
        assert math.dist(_com_over_support_sole_m(fk, keyframe), want) < 0.005, phase
        worst_type0_file = max(worst_type0_file, math.dist(_com_over_support_sole_m(fk, type0.phase(phase)),
                                                           (shared.com_inset_m, shared.com_forward_m)))
    assert worst_type0_file > 0.01   # from its own targets


@pytest.mark.parametrize("robot_type", TYPES)
def test_the_type_plays_its_own_long_kick(robot_type):
    library = default_library(robot_type)
    for name in ("kick_strong", "kick_strong_left"):
        motion = library.get(name)
        assert motion is not None, name
        shipped = motions.load(FILES_DIR / f"type{robot_type}" / f"{name}.xml")
        assert motion.constants == pytest.approx(shipped.constants)


def test_an_unknown_key_in_a_type_s_override_file_names_the_file_and_section(tmp_path):
    path = tmp_path / "kick_type3.toml"
    path.write_text("[kick_strong]\ncom_inset_mm = 0.02\n", encoding="utf-8")
    with pytest.raises(ValueError, match=r"kick_type3.toml \[kick_strong\].*com_inset_mm"):
        type_overrides(3, path)
