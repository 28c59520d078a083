"""kinematics: the one model of the SimSpark Nao (spec, generated MJCF/URDF, Pinocchio FK, PlaCo IK).

Only the light spec and name maps are imported here, so the agent can use joint tables without loading
Pinocchio; import ``kinematics.fk``, ``kinematics.ik`` or ``kinematics.mjcf`` for the heavy parts.
"""

from kinematics.errors import IKError, SpecError, ToolkitError
from kinematics.names import (effector_name, joint_index, joint_spec, nao_name, nao_rad_to_simspark_rad,
                              simspark_rad_to_nao_rad, wire_name)
from kinematics.spec import (EFFECTOR_NAMES, JOINT_NAMES, NAO_NAMES, ROBOT_TYPES, BodySpec, JointSpec, RobotSpec,
                             SensorSpec, Shape, robot_spec)

__all__ = [
    "BodySpec", "EFFECTOR_NAMES", "IKError", "JOINT_NAMES", "JointSpec", "NAO_NAMES", "ROBOT_TYPES", "RobotSpec",
    "SensorSpec", "Shape", "SpecError", "ToolkitError", "effector_name", "joint_index", "joint_spec", "nao_name",
    "nao_rad_to_simspark_rad", "robot_spec", "simspark_rad_to_nao_rad", "wire_name",
]
