"""Torso orientation estimate: gyro integration corrected toward the accelerometer's tilt (complementary filter).

The rotation R maps torso axes (x right, y forward, z up) to a gravity-aligned frame whose yaw origin is
arbitrary (where the filter started); yaw comes from the gyro alone, so it drifts (the gyro has no noise in
0.7.3, so slowly) and localization owns the absolute heading. Roll and pitch are pulled toward the
accelerometer's "up" direction, Mahony style: ω_corrected = ω + k·(up_measured × up_estimated), applied only
when |a| is within ``ACC_GATE`` of g, because walking impacts and beams (|a| = 29.42 on the init cycle in
the real-server sample) are not gravity.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from agent.world import mat3
from agent.protocol.constants import CYCLE_S

GRAVITY_M_S2 = 9.81
#: Accept accelerometer readings with | |a| - g | below this fraction of g.
ACC_GATE = 0.15
#: Correction gain k [1/s]: a tilt error decays with a time constant of about 1/k.
DEFAULT_GAIN_PER_S = 2.0


@dataclass(frozen=True, slots=True)
class Tilt:
    """Roll and pitch of the torso, in the convention of ``kinematics.fk.torso_rotation``."""

    pitch_forward_rad: float
    """Lean forward (positive: the chest goes down toward the robot's forward direction)."""
    roll_right_rad: float
    """Lean to the right (positive: the top goes toward the robot's right)."""


def tilt_from_up(up: mat3.Vector) -> Tilt:
    """Roll/pitch from the up direction in torso axes (the normalised accelerometer at rest)."""
    x, y, z = up
    n = math.sqrt(x * x + y * y + z * z) or 1.0
    return Tilt(math.atan2(-y, z), math.asin(max(-1.0, min(1.0, -x / n))))


def tilt_matrix(tilt: Tilt) -> mat3.Matrix:
    """Torso orientation with zero yaw: same matrix as ``kinematics.fk.torso_rotation(pitch, roll)``."""
    cp, sp = math.cos(tilt.pitch_forward_rad), math.sin(tilt.pitch_forward_rad)
    cr, sr = math.cos(tilt.roll_right_rad), math.sin(tilt.roll_right_rad)
    return ((cr, -sr * sp, sr * cp), (0.0, cp, sp), (-sr, -cr * sp, cr * cp))


class OrientationFilter:
    """Complementary filter over GYR (deg/s) and ACC (m/s²), one update per sense message.

    Args:
        gain_per_s: accelerometer correction gain k [1/s].
    """

    def __init__(self, gain_per_s: float = DEFAULT_GAIN_PER_S) -> None:
        self.gain_per_s = gain_per_s
        self.rotation: mat3.Matrix = mat3.IDENTITY
        """Torso -> gravity-aligned frame (yaw origin arbitrary)."""
        self.initialised = False
        """True once a gravity-like accelerometer reading has set the tilt."""

    def update(self, gyro_deg_s: mat3.Vector | None, acc_m_s2: mat3.Vector | None, dt_s: float = CYCLE_S) -> None:
        """Advance by one cycle.

        Args:
            gyro_deg_s: angular rate about the torso x, y, z axes [deg/s], or None if not sent.
            acc_m_s2: proper acceleration in torso axes [m/s²], or None if not sent.
            dt_s: time since the previous update [s].
        """
        up_meas = None
        if acc_m_s2 is not None:
            norm = math.sqrt(sum(a * a for a in acc_m_s2))
            if abs(norm - GRAVITY_M_S2) < ACC_GATE * GRAVITY_M_S2:
                up_meas = (acc_m_s2[0] / norm, acc_m_s2[1] / norm, acc_m_s2[2] / norm)
        if up_meas is not None and not self.initialised:
            self.rotation = tilt_matrix(tilt_from_up(up_meas))
            self.initialised = True
            up_meas = None  # already exact; the gyro still turns it below
        wx, wy, wz = (math.radians(w) for w in gyro_deg_s) if gyro_deg_s is not None else (0.0, 0.0, 0.0)
        if up_meas is not None:
            up_est = self.rotation[2]  # world z in torso axes = third row of R
            cx, cy, cz = mat3.cross(up_meas, up_est)
            wx, wy, wz = wx + self.gain_per_s * cx, wy + self.gain_per_s * cy, wz + self.gain_per_s * cz
        angle = math.sqrt(wx * wx + wy * wy + wz * wz) * dt_s
        if angle > 0.0:
            step = mat3.rotation((wx * dt_s / angle, wy * dt_s / angle, wz * dt_s / angle), angle)
            self.rotation = mat3.orthonormalize(mat3.matmul(self.rotation, step))

    @property
    def yaw_rad(self) -> float:
        """Integrated yaw of the torso's forward axis [rad] (arbitrary origin, counter-clockwise positive)."""
        r = self.rotation
        return math.atan2(-r[0][1], r[1][1])

    @property
    def tilt(self) -> Tilt:
        """Current roll and pitch."""
        return tilt_from_up(self.rotation[2])

    @property
    def tilt_rotation(self) -> mat3.Matrix:
        """The orientation with the yaw removed (torso -> gravity frame aligned with the robot's heading)."""
        return tilt_matrix(self.tilt)

    @property
    def up_z(self) -> float:
        """z of the torso's up axis in the gravity frame (1 upright, < 0.6 counts as fallen, REFERENCE §8.1)."""
        return self.rotation[2][2]
