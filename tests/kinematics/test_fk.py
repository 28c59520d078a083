"""Forward kinematics against hand computations from REFERENCE.md numbers."""

import math

import numpy as np
import pytest

from kinematics import SpecError
from kinematics.fk import NaoKinematics, torso_rotation


@pytest.fixture(scope="module")
def kin():
    return NaoKinematics(0)


def sagittal_camera_height_m(hip_deg: float, knee_deg: float) -> float:
    """Hand computation: upright torso, feet flat (ankle = -(hip + knee)), REFERENCE §2.1/§2.2 offsets.

    Camera 0.155 above the torso centre, hip axis 0.115 below it; hip->knee (y 0.005, z -0.12), knee->ankle
    (0, -0.10), ankle axis 0.05 above the sole. A rotation th about +x maps (y, z) to z' = y sin th + z cos th.
    """
    h, k = math.radians(hip_deg), math.radians(knee_deg)
    return 0.155 + 0.115 - (0.005 * math.sin(h) - 0.12 * math.cos(h)) + 0.10 * math.cos(h + k) + 0.05


def test_camera_height_zero_pose(kin):
    assert kin.camera_height_m() == pytest.approx(0.54, abs=1e-12)
    assert kin.camera_height_m() == pytest.approx(sagittal_camera_height_m(0, 0), abs=1e-12)


@pytest.mark.parametrize("hip_deg, knee_deg", [(40, -80), (25, -50), (60, -110)])
def test_camera_height_crouch_matches_hand_computation(kin, hip_deg, knee_deg):
    angles = {}
    for side in "lr":
        angles[f"{side}lj3"] = math.radians(hip_deg)
        angles[f"{side}lj4"] = math.radians(knee_deg)
        angles[f"{side}lj5"] = -math.radians(hip_deg + knee_deg)
    assert kin.camera_height_m(angles) == pytest.approx(sagittal_camera_height_m(hip_deg, knee_deg), abs=1e-12)


def test_camera_height_with_leaning_torso(kin):
    # Leaning the whole rigid robot forward about the sole's front edge: the camera drops to
    # the distance of that edge-to-camera vector after rotation.
    pitch = math.radians(10)
    edge = np.array([0.0, 0.105, -0.385])  # sole front edge (y max), torso frame
    camera = np.array([0.0, 0.0, 0.155])
    expected = (torso_rotation(pitch_forward_rad=pitch) @ (camera - edge))[2]
    assert kin.camera_height_m(rotation=torso_rotation(pitch_forward_rad=pitch)) == pytest.approx(expected, abs=1e-12)
    # Backward lean pivots on the heel edge instead.
    back = torso_rotation(pitch_forward_rad=-pitch)
    heel = np.array([0.0, -0.055, -0.385])
    assert kin.camera_height_m(rotation=back) == pytest.approx((back @ (camera - heel))[2], abs=1e-12)


def test_frames_and_com_at_zero_pose(kin):
    assert kin.frame_pose("lsole").position_m == pytest.approx([-0.055, 0.025, -0.385])
    assert kin.frame_pose("rhand").position_m == pytest.approx([0.098, 0.195, 0.084])
    assert kin.com() == pytest.approx([0.0, 0.0163, -0.0788], abs=1e-4)
    polygon = kin.support_polygon()
    assert polygon.min(axis=0) == pytest.approx([-0.095, -0.055]) and polygon.max(axis=0) == pytest.approx([0.095, 0.105])


def test_one_leg_lifted_support_polygon_is_one_foot(kin):
    polygon = kin.support_polygon({"llj3": 0.5, "llj4": -1.0, "llj5": 0.5})
    assert polygon[:, 0].min() == pytest.approx(0.015) and polygon[:, 0].max() == pytest.approx(0.095)


def test_bad_inputs_give_clear_errors(kin):
    with pytest.raises(SpecError, match="non-finite joint angle for llj3"):
        kin.camera_height_m({"llj3": float("nan")})
    with pytest.raises(SpecError, match="unknown joint 'knee'"):
        kin.com({"knee": 0.1})
    with pytest.raises(SpecError, match="expected 22 joint angles"):
        kin.camera_height_m(np.zeros(21))
    with pytest.raises(SpecError, match="unknown frame 'hand'"):
        kin.frame_pose("hand")
