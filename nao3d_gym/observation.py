"""The observation vector of a Nao3D environment, read from a parsed sense message (what a real agent perceives).

Only perceptors the robot has every cycle go in (REFERENCE §2.3, §3.4): hinge angles, gyro, accelerometer and
the two foot pressure sensors. Vision (every third cycle, noisy) and hearing are left out so that every
observation has the same meaning; a user who needs them reads the last raw message from ``env.unwrapped.last_sense``.
"""

from __future__ import annotations

import math

import numpy as np

from agent.protocol.perceptors import Sense
from kinematics.spec import JointSpec

#: Foot pressure sensors of the Nao (REFERENCE §2.3), in observation order.
FOOT_SENSORS = ("lf", "rf")
#: Bounds of the clipped readings: a falling robot's gyro and accelerometer spike far past these, and the
#: clip keeps every observation inside the space the checker and the learners see.
GYRO_LIMIT_RAD_S = 50.0
ACC_LIMIT_M_S2 = 200.0
FOOT_POINT_LIMIT_M = 1.0
FOOT_FORCE_LIMIT_N = 500.0
_DEG = math.pi / 180.0


def observation_names(joints: tuple[JointSpec, ...]) -> list[str]:
    """One name per observation entry, with its unit (``hj1_rad`` ... ``gyr_x_rad_s`` ... ``rf_fz_n``)."""
    names = [f"{j.perceptor}_rad" for j in joints]
    names += [f"gyr_{axis}_rad_s" for axis in "xyz"] + [f"acc_{axis}_m_s2" for axis in "xyz"]
    for sensor in FOOT_SENSORS:
        names += [f"{sensor}_c{axis}_m" for axis in "xyz"] + [f"{sensor}_f{axis}_n" for axis in "xyz"]
    return names


def observation_bounds(joints: tuple[JointSpec, ...]) -> tuple[np.ndarray, np.ndarray]:
    """(low, high) of the observation space: joint limits widened by 5 degrees (the stops give a little),
    then the clip limits of the module constants."""
    margin = 5.0
    low = [math.radians(j.min_deg - margin) for j in joints]
    high = [math.radians(j.max_deg + margin) for j in joints]
    low += [-GYRO_LIMIT_RAD_S] * 3 + [-ACC_LIMIT_M_S2] * 3
    high += [GYRO_LIMIT_RAD_S] * 3 + [ACC_LIMIT_M_S2] * 3
    for _ in FOOT_SENSORS:
        low += [-FOOT_POINT_LIMIT_M] * 3 + [-FOOT_FORCE_LIMIT_N] * 3
        high += [FOOT_POINT_LIMIT_M] * 3 + [FOOT_FORCE_LIMIT_N] * 3
    return np.array(low, dtype=np.float32), np.array(high, dtype=np.float32)


class ObservationReader:
    """Writes a `Sense` into a float32 vector laid out as `observation_names`.

    Args:
        joints: the robot type's hinges (``kinematics.spec.robot_spec(t).joints``), in observation order.
    """

    def __init__(self, joints: tuple[JointSpec, ...]) -> None:
        self.perceptors = tuple(j.perceptor for j in joints)
        self.low, self.high = observation_bounds(joints)
        self.size = self.low.size

    def read(self, sense: Sense) -> np.ndarray:
        """The observation of one sense message (a new array: learners keep references to it)."""
        values: list[float] = [sense.joints.get(name, 0.0) * _DEG for name in self.perceptors]
        gyro, acc = sense.gyro, sense.acc
        values += [v * _DEG for v in gyro.rate_deg_s] if gyro is not None else [0.0, 0.0, 0.0]
        values += list(acc.acc_m_s2) if acc is not None else [0.0, 0.0, 0.0]
        for name in FOOT_SENSORS:
            foot = sense.frp.get(name)
            values += [*foot.contact_m, *foot.force_n] if foot is not None else [0.0] * 6
        return np.clip(np.array(values, dtype=np.float32), self.low, self.high)


class PerceptorRowReader:
    """The same observation as `ObservationReader` over `parse_sense`, read from a robot's row of
    `sim.world.World.perceptor_rows` (the values the engine's sense message is written from).

    Why: writing the sense message and parsing it back is a fifth of a step's Python work in the env.
    Each value is rounded as the message spells it (``%.2f``, `agent.protocol.numbers.FIXED2`) and
    read back (`fixed2_floats`), so the observation is the parsed perceptors' bit for bit (tests/nao3d_gym check it
    against the text path step by step); a foot without contact reads zeros, as its FRP is then not sent.

    Args:
        joints: the robot type's hinges in observation (spec) order.
        wire_joints: perceptor names in the row's (sense-message) order (`sim.perceptors.wire_joint_order`).
        feet: foot sensor names in the row's order (bit i of the contact mask = ``feet[i]``).
    """

    def __init__(self, joints: tuple[JointSpec, ...], wire_joints: tuple[str, ...], feet: tuple[str, ...]) -> None:
        from agent.protocol.numbers import FIXED2
        self.low, self.high = observation_bounds(joints)
        count = 6 + len(wire_joints) + 6 * len(feet)
        self._count = count
        if FIXED2 != "%.2f":   # fixed2_floats reproduces this spelling only
            raise RuntimeError(f"the sense message's spelling changed to {FIXED2!r}: update fixed2_floats")
        first_foot = 6 + len(wire_joints)
        gather = [6 + wire_joints.index(j.perceptor) for j in joints] + [0, 1, 2, 3, 4, 5]
        scale = [_DEG] * (len(joints) + 3) + [1.0] * 3
        self._feet: list[tuple[int, slice]] = []   # (contact bit, observation entries) per observed foot
        for name in FOOT_SENSORS:
            start = len(gather)
            if name in feet:
                slot = feet.index(name)
                gather += range(first_foot + 6 * slot, first_foot + 6 * slot + 6)
                self._feet.append((1 << slot, slice(start, start + 6)))
            else:   # a robot without this sensor: always zeros
                gather += [count] * 6
            scale += [1.0] * 6
        self._gather = np.array(gather, dtype=np.intp)
        self._scale = np.array(scale)

    def read(self, row: np.ndarray, contact_mask: int) -> np.ndarray:
        """The observation of one robot's perceptor row and foot-contact bits (a new float32 array)."""
        parsed = np.append(fixed2_floats(row[:self._count]), 0.0)
        values = parsed[self._gather] * self._scale
        for bit, entries in self._feet:
            if not contact_mask & bit:
                values[entries] = 0.0
        return np.clip(values.astype(np.float32), self.low, self.high)


#: Scaled values this close to a half unit of the last decimal [relative] are rounded through the text: far
#: above the error of the product ``v * 10**decimals`` (half an ulp, 1.1e-16 relative).
_HALF_TOLERANCE = 1e-12
_EXACT_INTEGERS = 2.0 ** 52


def fixed_floats(values: np.ndarray, decimals: int) -> np.ndarray:
    """``float("%.{decimals}f" % v)`` for every v, vectorised: what a parser reads back from the text.

    ``rint(v * 10**decimals) / 10**decimals`` gives the same double whenever the rint picks the same
    integer d as the text's exact round-half-even (d / 10**decimals is then one correctly rounded division,
    as the parse of the decimal is); the picks can only differ when the scaled value is within its rounding
    error of a half, and those rare values (and huge or non-finite ones) go through the text itself.
    """
    unit = float(10 ** decimals)
    scaled = values * unit
    out = np.rint(scaled) / unit
    magnitude = np.abs(scaled)
    doubtful = np.abs(np.abs(scaled - np.floor(scaled)) - 0.5) <= _HALF_TOLERANCE * np.maximum(magnitude, 1.0)
    doubtful |= ~(magnitude < _EXACT_INTEGERS)
    if doubtful.any():
        spelling = f"%.{decimals}f"
        for i in np.flatnonzero(doubtful).tolist():
            out[i] = float(spelling % values[i])
    return out


def fixed2_floats(values: np.ndarray) -> np.ndarray:
    """``float("%.2f" % v)`` for every v: the sense message's spelling read back (see `fixed_floats`)."""
    return fixed_floats(values, 2)
