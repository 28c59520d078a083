"""Torso orientation estimate: gyro integration corrected toward the accelerometer's tilt (complementary filter).

The rotation R maps torso axes (x right, y forward, z up) to a gravity-aligned frame whose yaw origin is
arbitrary (where the filter started); yaw comes from the gyro alone, so it drifts (the gyro has no noise in
0.7.3, so slowly) and localization owns the absolute heading. Roll and pitch are pulled toward the
accelerometer's "up" direction, Mahony style: ω_corrected = ω + k·(up_measured × up_estimated), applied only
when |a| is within ``ACC_GATE`` of g, because walking impacts and beams (|a| = 29.42 on the init cycle in
the real-server sample) are not gravity.

A single gravity-sized reading is not trusted to set the tilt: a robot dropped by a trainer move bounces, and
one bounce can read g the wrong way up. On the real rcssserver3d a type-3 robot moved to a torso height of
0.40 m (its legs are longer: it stands at 0.44 m) read 29.42, 49.16, 0.03, 19.55, 0.03, -0.03 and then
(0.00, 0.02, -9.88) m/s²; the filter took that for its start, believed the robot upside down, and since the
correction ``up_measured × up_estimated`` vanishes for opposite vectors, stayed so: the agent played a stand-up
from standing and fell (``motion-studio transfer --type 3``, the 20 m walks, 2026-11-30). So the tilt is set from
``SETTLE_READINGS`` consecutive gated readings that agree within ``AGREE_DEG``, and re-anchored to such readings
whenever the estimate is more than ``REANCHOR_DEG`` off them while the gyro is quiet (at rest the accelerometer
is gravity; the gyro-only estimate can be wrong by any angle).
"""

from __future__ import annotations

import math
from collections import deque
from dataclasses import dataclass

from agent.world import mat3
from agent.protocol.constants import CYCLE_S

GRAVITY_M_S2 = 9.81
#: Accept accelerometer readings with | |a| - g | below this fraction of g.
ACC_GATE = 0.15
#: Correction gain k [1/s]: a tilt error decays with a time constant of about 1/k.
DEFAULT_GAIN_PER_S = 2.0
#: Consecutive gated readings that must agree before they set (or re-anchor) the tilt: 0.1 s at one per cycle.
SETTLE_READINGS = 5
#: ... within this angle of their mean direction [deg].
AGREE_DEG = 10.0
#: ... with the gyro below this on every one of them [deg/s] (re-anchoring only).
QUIET_GYRO_DEG_S = 30.0
#: The estimate is re-anchored to agreeing readings that are this far from its up direction [deg].
REANCHOR_DEG = 45.0
#: Cosine of REANCHOR_DEG - AGREE_DEG: a newest reading nearer the estimate than that cannot start a re-anchoring.
_FAR_COS = math.cos(math.radians(REANCHOR_DEG - AGREE_DEG))


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
        """True once ``SETTLE_READINGS`` agreeing gravity-like accelerometer readings have set the tilt."""
        self._streak: deque[tuple[mat3.Vector, bool]] = deque(maxlen=SETTLE_READINGS)
        """The last consecutive gated readings (unit up direction, gyro quiet), newest last."""

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
        quiet = gyro_deg_s is None or math.sqrt(sum(w * w for w in gyro_deg_s)) < QUIET_GYRO_DEG_S
        self._remember(up_meas, quiet)
        # Initialised, readings that agree within AGREE_DEG of a mean more than REANCHOR_DEG off the estimate put
        # the newest one more than REANCHOR_DEG - AGREE_DEG off: below that, no mean is worth computing (this
        # runs every cycle of every agent).
        far = up_meas is not None and _dot(up_meas, self.rotation[2]) < _FAR_COS
        settled = self._settled() if not self.initialised or far else None
        if settled is not None and (not self.initialised or _angle_deg(settled, self.rotation[2]) > REANCHOR_DEG):
            self.rotation = mat3.matmul(mat3.rotation((0.0, 0.0, 1.0), self.yaw_rad),
                                        tilt_matrix(tilt_from_up(settled)))
            self.initialised = True
        wx, wy, wz = (math.radians(w) for w in gyro_deg_s) if gyro_deg_s is not None else (0.0, 0.0, 0.0)
        if up_meas is not None and self.initialised:  # before that, single readings are not trusted
            up_est = self.rotation[2]  # world z in torso axes = third row of R
            cx, cy, cz = mat3.cross(up_meas, up_est)
            wx, wy, wz = wx + self.gain_per_s * cx, wy + self.gain_per_s * cy, wz + self.gain_per_s * cz
        angle = math.sqrt(wx * wx + wy * wy + wz * wz) * dt_s
        if angle > 0.0:
            step = mat3.rotation((wx * dt_s / angle, wy * dt_s / angle, wz * dt_s / angle), angle)
            self.rotation = mat3.orthonormalize(mat3.matmul(self.rotation, step))

    def _remember(self, up_meas: mat3.Vector | None, quiet: bool) -> None:
        """Keep the last ``SETTLE_READINGS`` consecutive gated readings (a reading out of the gate ends them)."""
        if up_meas is None:
            self._streak.clear()
        else:
            self._streak.append((up_meas, quiet))

    def _settled(self) -> mat3.Vector | None:
        """The mean up direction of the remembered readings when there are ``SETTLE_READINGS`` of them and they
        agree within ``AGREE_DEG`` (and, once initialised, the gyro was quiet on each), else None."""
        if len(self._streak) < SETTLE_READINGS or (self.initialised and not all(q for _, q in self._streak)):
            return None
        mean = tuple(sum(up[i] for up, _ in self._streak) for i in range(3))
        norm = math.sqrt(sum(c * c for c in mean)) or 1.0
        mean = (mean[0] / norm, mean[1] / norm, mean[2] / norm)
        if any(_angle_deg(up, mean) > AGREE_DEG for up, _ in self._streak):
            return None
        return mean

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


def _dot(a: mat3.Vector, b: mat3.Vector) -> float:
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def _angle_deg(a: mat3.Vector, b: mat3.Vector) -> float:
    """Angle between two unit vectors [deg]."""
    return math.degrees(math.acos(max(-1.0, min(1.0, _dot(a, b)))))
