"""Joint name maps: wire perceptor (``llj3``) <-> effector (``lle3``) <-> conventional Nao (``LHipPitch``) <-> index.

The wire perceptor name is the project's key for a joint. Webots files use conventional names and real-Nao
signs; SimSpark negates the pitch joints (REFERENCE §2.2 sign column), so conversions go through here.
"""

from __future__ import annotations

import math

from kinematics.errors import SpecError
from kinematics.spec import JointSpec, robot_spec


def joint_spec(name: str, robot_type: int = 0) -> JointSpec:
    """The joint called ``name`` (perceptor, effector or Nao name, exact case).

    Raises:
        SpecError: unknown name (the message lists the known wire names).
    """
    return robot_spec(robot_type).joint(name)


def wire_name(name: str, robot_type: int = 0) -> str:
    """Any alias of a joint -> its wire perceptor name (``LHipPitch`` -> ``llj3``, ``lle3`` -> ``llj3``)."""
    return joint_spec(name, robot_type).perceptor


def effector_name(name: str, robot_type: int = 0) -> str:
    """Any alias of a joint -> its effector name (``llj3`` -> ``lle3``)."""
    return joint_spec(name, robot_type).effector


def nao_name(name: str, robot_type: int = 0) -> str:
    """Any alias of a joint -> its conventional Nao name (``llj3`` -> ``LHipPitch``)."""
    return joint_spec(name, robot_type).nao_name


def joint_index(name: str, robot_type: int = 0) -> int:
    """Position of the joint in the canonical order (= its index in the generated models' joint vector)."""
    spec = robot_spec(robot_type)
    return spec.joints.index(spec.joint(name))


def nao_rad_to_simspark_rad(name: str, angle_rad: float, robot_type: int = 0) -> float:
    """A real-Nao-signed angle (Webots files) -> SimSpark sign (pitch joints negated)."""
    return joint_spec(name, robot_type).nao_sign * angle_rad


def simspark_rad_to_nao_rad(name: str, angle_rad: float, robot_type: int = 0) -> float:
    """A SimSpark-signed angle -> real-Nao sign; the map is its own inverse (signs are +-1)."""
    return joint_spec(name, robot_type).nao_sign * angle_rad


def check_angle_rad(name: str, angle_rad: float) -> float:
    """Reject NaN/Inf angles with an error naming the joint (a NaN would silently poison FK and physics)."""
    if not math.isfinite(angle_rad):
        raise SpecError(f"joint {name}: angle must be finite, got {angle_rad!r}", field=name)
    return angle_rad
