"""The spec carries REFERENCE.md §2's numbers exactly, and every library sees the same 22 hinges."""

import math

import mujoco
import numpy as np
import pytest

from kinematics import JOINT_NAMES, SpecError, joint_index, nao_name, robot_spec, wire_name
from kinematics.mjcf import robot_mjcf_xml
from kinematics.pinocchio_model import pinocchio_model


def test_type0_total_mass_and_standing_heights():
    spec = robot_spec(0)
    assert spec.total_mass_kg == pytest.approx(4.6071, abs=1e-12)
    assert -spec.sole_z_m == pytest.approx(0.385, abs=1e-12)
    assert spec.body_position_m("head")[2] - spec.sole_z_m == pytest.approx(0.54, abs=1e-12)


@pytest.mark.parametrize("robot_type, thigh_z, ankle_z, sole_z, elbow_y, hip_x", [
    (0, -0.155, -0.335, -0.385, 0.09, 0.055),
    (1, -0.17332, -0.37164, -0.42164, 0.12664, 0.055),
    (2, -0.155, -0.335, -0.385, 0.09, 0.055),
    (3, -0.182868424, -0.390736848, -0.440736848, 0.145736848, 0.072954143),
    (4, -0.155, -0.335, -0.385, 0.09, 0.055),
])
def test_type_overrides_match_reference_table(robot_type, thigh_z, ankle_z, sole_z, elbow_y, hip_x):
    spec = robot_spec(robot_type)
    assert spec.body_position_m("rthigh")[2] == pytest.approx(thigh_z, abs=1e-9)
    assert spec.body_position_m("rankle")[2] == pytest.approx(ankle_z, abs=1e-9)
    assert spec.sole_z_m == pytest.approx(sole_z, abs=1e-9)
    assert spec.body_position_m("relbow")[1] == pytest.approx(elbow_y, abs=1e-9)
    assert spec.body_position_m("rthigh")[0] == pytest.approx(hip_x, abs=1e-12)
    assert spec.body_position_m("lthigh")[0] == pytest.approx(-hip_x, abs=1e-12)
    assert spec.total_mass_kg == pytest.approx(4.6071, abs=1e-9)


def test_type2_ankle_speeds_and_type4_toes():
    assert robot_spec(2).joint("rlj5").max_speed_rad_s == 8.80667
    assert robot_spec(2).joint("llj6").max_speed_rad_s == 3.47234
    assert robot_spec(0).joint("llj5").max_speed_rad_s == 6.1395
    toes = robot_spec(4)
    assert toes.joint_names[-1] == "raj4" and "llj7" in toes.joint_names and "rlj7" in toes.joint_names
    toe = toes.joint("rle7")
    assert (toe.min_deg, toe.max_deg) == (-1.0, 70.0)
    # The toe hinge sits on the foot's front-bottom edge; the ankle roll 1.78 cm behind lj5 (REFERENCE §2.5).
    anchor = np.add(toes.body_position_m("rtoe"), toe.anchor_in_child_m)
    assert anchor == pytest.approx((0.055, 0.069482344, -0.385), abs=1e-9)
    roll = np.add(toes.body_position_m("rfoot"), toes.joint("rlj6").anchor_in_child_m)
    assert roll == pytest.approx((0.055, -0.022758828, -0.34), abs=1e-9)


def test_hinge_anchors_in_torso_frame_match_reference():
    spec = robot_spec(0)
    expected = {"hj2": (0, 0, 0.15), "laj2": (-0.098, 0, 0.075), "laj4": (-0.098, 0.09, 0.084),
                "llj3": (-0.055, -0.01, -0.115), "rlj4": (0.055, -0.005, -0.235), "rlj6": (0.055, -0.005, -0.34)}
    for name, anchor in expected.items():
        joint = spec.joint(name)
        assert np.add(spec.body_position_m(joint.child), joint.anchor_in_child_m) == pytest.approx(anchor, abs=1e-12)


@pytest.mark.parametrize("robot_type", [0, 1, 2, 3, 4])
def test_every_library_has_the_spec_hinges_and_limits(robot_type):
    spec = robot_spec(robot_type)
    model = mujoco.MjModel.from_xml_string(robot_mjcf_xml(robot_type))
    pin_model = pinocchio_model(robot_type)
    hinge_names = [model.joint(i).name for i in range(1, model.njnt)]
    assert hinge_names == list(spec.joint_names) == list(pin_model.names)[2:]
    for i, joint in enumerate(spec.joints):
        assert model.jnt_range[i + 1] == pytest.approx([math.radians(joint.min_deg), math.radians(joint.max_deg)])
        assert pin_model.lowerPositionLimit[7 + i] == pytest.approx(joint.min_rad)
        assert pin_model.upperPositionLimit[7 + i] == pytest.approx(joint.max_rad)
    assert len([j for j in spec.joints if j.perceptor[-1] != "7"]) == 22


def test_name_maps_and_bad_names():
    assert wire_name("LHipPitch") == "llj3" and wire_name("lle3") == "llj3"
    assert nao_name("rlj4") == "RKneePitch"
    assert joint_index("he2") == 1 and JOINT_NAMES[joint_index("raj4")] == "raj4"
    with pytest.raises(SpecError, match="unknown joint 'lle9'") as err:
        wire_name("lle9")
    assert err.value.field == "joint"
    with pytest.raises(SpecError, match="unknown robot type 5"):
        robot_spec(5)
    with pytest.raises(SpecError, match="unknown robot type"):
        robot_spec("0")
