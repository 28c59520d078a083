"""The strike keyframe NLP on the symbolic Nao: IPOPT's solution keeps the joint speed limit, the CoM over the
support sole and the toe at the ball, and its toe velocity is what Pinocchio's kinematics give by finite
differences of the pose."""

from __future__ import annotations

import numpy as np
import pytest

from kinematics.fk import NaoKinematics
from kinematics.spec import robot_spec
from motion_studio.strike_keyframe import COM_MARGIN_M, SWING, TOE_HEIGHT_M, optimise_strike


def _toe_in_support_sole(kinematics: NaoKinematics, angles_rad: dict[str, float]) -> np.ndarray:
    foot = kinematics.frame_pose("lfoot", angles_rad)
    sole = kinematics.frame_pose("rsole", angles_rad)
    size = kinematics.spec.body("lfoot").shape.size
    toe = foot.position_m + foot.rotation @ np.array([0.0, size[1] / 2, -size[2] / 2])
    return sole.rotation.T @ (toe - sole.position_m)


def test_the_strike_is_fast_within_the_limits_and_its_toe_velocity_matches_pinocchio():
    strike = optimise_strike(0)
    spec = robot_spec(0)
    assert strike.solver_status == "Solve_Succeeded"
    assert all(abs(v) <= spec.joint(name).max_speed_rad_s + 1e-6 for name, v in strike.speeds_rad_s.items())
    half_x, half_y = (v / 2 for v in spec.body("rfoot").shape.size[:2])
    assert abs(strike.com_m[0]) <= half_x - COM_MARGIN_M + 1e-6 and abs(strike.com_m[1]) <= half_y - COM_MARGIN_M + 1e-6
    assert TOE_HEIGHT_M[0] - 1e-6 <= strike.toe_position_m[2] <= TOE_HEIGHT_M[1] + 1e-6
    assert strike.toe_speed_m_s > 2.5  # faster than the real server's measured kick foot (2.51 m/s)
    kinematics = NaoKinematics(0)
    angles = {name: np.radians(value) for name, value in strike.angles_deg.items()}
    step_s = 1e-6
    moved = {name: value + step_s * strike.speeds_rad_s.get(name, 0.0) for name, value in angles.items()}
    numeric = (_toe_in_support_sole(kinematics, moved) - _toe_in_support_sole(kinematics, angles)) / step_s
    assert numeric == pytest.approx(np.array(strike.toe_velocity_m_s), abs=1e-4)
    # the reported angles are rounded to 0.001 deg
    assert np.allclose(_toe_in_support_sole(kinematics, angles), strike.toe_position_m, atol=1e-4)
    assert set(strike.speeds_rad_s) == set(SWING)
