"""The one declarative spec of the SimSpark Nao (robot types 0-4), transcribed from REFERENCE.md §2.

Everything else (MJCF, URDF, Pinocchio, PlaCo, the simulator's world, the agent's joint tables) is
generated from the values here. Frames follow SimSpark: robot x = right, y = forward, z = up; positions
are body centres in metres; hinge angles are SimSpark-signed radians inside the code (degrees on the wire).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache

from kinematics.errors import SpecError

Vec3 = tuple[float, float, float]

ROBOT_TYPES: tuple[int, ...] = (0, 1, 2, 3, 4)

# REFERENCE §2.2: common to every hinge.
MAX_TORQUE_NM = 10.0
DEFAULT_MAX_SPEED_RAD_S = 6.1395
# REFERENCE §2.1: drag on every body.
LINEAR_DRAG_N_S_PER_M = 0.01
ANGULAR_DRAG_NM_S_PER_RAD = 0.01


@dataclass(frozen=True)
class Shape:
    """A body's geometry in its own frame (centred on the body origin).

    kind: "box" (size = full extents x, y, z in m), "sphere" (size = (radius,)),
    "capsule" (size = (radius, cylinder length); axis along z).
    """

    kind: str
    size: tuple[float, ...]


@dataclass(frozen=True)
class BodySpec:
    """One rigid body of the Nao.

    name: SimSpark body name (ObjectState id for visible parts: head, llowerarm, rlowerarm, lfoot, rfoot).
    parent: parent body name ("" for the torso, the root).
    offset_m: body centre relative to the parent's centre at zero pose, robot frame.
    shape: geometry used for inertia, collision (if collider) and display.
    mass_kg: mass; the inertia is that of the shape at uniform density (as SimSpark's ODE does).
    collider: whether the body has a contact geometry (REFERENCE §2.1 collider column).
    """

    name: str
    parent: str
    offset_m: Vec3
    shape: Shape
    mass_kg: float
    collider: bool


@dataclass(frozen=True)
class JointSpec:
    """One hinge between a child body and its parent.

    perceptor: wire name of the HJ perceptor (``hj1``, ``llj3``...), the project's joint key.
    effector: wire name of the effector (``he1``, ``lle3``...).
    nao_name: conventional Nao name (``HeadYaw``...), used by Webots motion files.
    child / parent: body names; the joint moves the child.
    anchor_in_child_m: anchor relative to the child centre (as the rsg gives it).
    axis: unit axis in the torso frame at zero pose; positive angle = right-handed rotation of the child.
    min_deg / max_deg: stops, SimSpark sign.
    max_speed_rad_s: motor velocity limit; max_torque_nm: motor force limit.
    nao_sign: +1/-1, angle_simspark = nao_sign * angle_real_nao (pitch joints are negated, §2.2).
    """

    perceptor: str
    effector: str
    nao_name: str
    child: str
    parent: str
    anchor_in_child_m: Vec3
    axis: Vec3
    min_deg: float
    max_deg: float
    nao_sign: int
    max_speed_rad_s: float = DEFAULT_MAX_SPEED_RAD_S
    max_torque_nm: float = MAX_TORQUE_NM

    @property
    def min_rad(self) -> float:
        return math.radians(self.min_deg)

    @property
    def max_rad(self) -> float:
        return math.radians(self.max_deg)


@dataclass(frozen=True)
class SensorSpec:
    """A sensor attached to a body: kind in {camera, gyro, accelerometer, force}; pos relative to the body centre."""

    name: str
    kind: str
    body: str
    pos_in_body_m: Vec3 = (0.0, 0.0, 0.0)


@dataclass(frozen=True)
class TypeParameters:
    """The robot-type dependent numbers of REFERENCE §2.5 (rsg template parameters)."""

    hip1_rel_torso_x: float
    hip1_rel_torso_z: float
    thigh_rel_hip2_z: float
    ankle_rel_shank_z: float
    elbow_rel_upperarm_y: float
    ankle_pitch_max_speed_rad_s: float = DEFAULT_MAX_SPEED_RAD_S
    ankle_roll_max_speed_rad_s: float = DEFAULT_MAX_SPEED_RAD_S
    toe_length_m: float = 0.0


TYPE_PARAMETERS: dict[int, TypeParameters] = {
    0: TypeParameters(0.055, -0.115, -0.04, -0.055, 0.07),
    1: TypeParameters(0.055, -0.115, -0.05832, -0.07332, 0.10664),
    2: TypeParameters(0.055, -0.115, -0.04, -0.055, 0.07,
                      ankle_pitch_max_speed_rad_s=8.80667, ankle_roll_max_speed_rad_s=3.47234),
    3: TypeParameters(0.072954143, -0.115, -0.067868424, -0.082868424, 0.125736848),
    4: TypeParameters(0.055, -0.115, -0.04, -0.055, 0.07, toe_length_m=0.035517656),
}

# Type 4 foot/toe split (REFERENCE §2.5): same total mass and span as the type-0 foot.
TOE_FOOT_SIZE_M = (0.08, 0.124482344, 0.02)
TOE_FOOT_MASS_KG = 0.177801465
TOE_FOOT_OFFSET_Y_M = 0.012241172  # foot centre rel. ankle (type 0: 0.03)
TOE_SIZE_M = (0.08, 0.035517656, 0.01)
TOE_MASS_KG = 0.022198535
TOE_OFFSET_IN_FOOT_M = (0.0, 0.08, -0.005)
TOE_ANCHOR_IN_TOE_M = (0.0, -0.017758828, -0.005)

_SQ = 0.7071067811865476  # sqrt(1/2): the hip yaw-pitch axes lie at 45 degrees.


@dataclass(frozen=True)
class RobotSpec:
    """A complete robot type: bodies in tree order (parents first), joints in canonical order, sensors."""

    robot_type: int
    bodies: tuple[BodySpec, ...]
    joints: tuple[JointSpec, ...]
    sensors: tuple[SensorSpec, ...]

    def body(self, name: str) -> BodySpec:
        """The body called ``name``; SpecError listing the known names otherwise."""
        for body in self.bodies:
            if body.name == name:
                return body
        raise SpecError(f"unknown body {name!r} for robot type {self.robot_type}; "
                        f"known: {', '.join(b.name for b in self.bodies)}", field="body")

    def joint(self, name: str) -> JointSpec:
        """The joint with wire perceptor, effector or conventional name ``name``."""
        for joint in self.joints:
            if name in (joint.perceptor, joint.effector, joint.nao_name):
                return joint
        raise SpecError(f"unknown joint {name!r} for robot type {self.robot_type}; known: "
                        f"{', '.join(j.perceptor for j in self.joints)} (or effector / Nao names)",
                        field="joint")

    @property
    def joint_names(self) -> tuple[str, ...]:
        """Wire perceptor names in canonical order (REFERENCE §2.2 rows 1-22, toes after each ankle roll)."""
        return tuple(j.perceptor for j in self.joints)

    @property
    def total_mass_kg(self) -> float:
        return sum(b.mass_kg for b in self.bodies)

    def body_position_m(self, name: str) -> Vec3:
        """Body centre relative to the torso centre at zero pose (sum of offsets up the tree)."""
        x = y = z = 0.0
        body = self.body(name)
        while body.parent:
            x, y, z = x + body.offset_m[0], y + body.offset_m[1], z + body.offset_m[2]
            body = self.body(body.parent)
        return (x, y, z)

    @property
    def sole_z_m(self) -> float:
        """Height of the sole (foot box bottom) relative to the torso centre at zero pose."""
        foot = self.body("rfoot")
        return self.body_position_m("rfoot")[2] - foot.shape.size[2] / 2.0


def _box(x: float, y: float, z: float) -> Shape:
    return Shape("box", (x, y, z))


def _sphere(r: float) -> Shape:
    return Shape("sphere", (r,))


def _arm(side: str, p: TypeParameters) -> tuple[list[BodySpec], list[JointSpec]]:
    """Bodies and joints of one arm; side 'l' (x < 0) or 'r' (x > 0)."""
    s = -1.0 if side == "l" else 1.0
    bodies = [
        BodySpec(f"{side}shoulder", "torso", (s * 0.098, 0.0, 0.075), _sphere(0.01), 0.070, False),
        BodySpec(f"{side}upperarm", f"{side}shoulder", (s * 0.01, 0.02, 0.0), _box(0.07, 0.08, 0.06), 0.150, True),
        BodySpec(f"{side}elbow", f"{side}upperarm", (-s * 0.01, p.elbow_rel_upperarm_y, 0.009), _sphere(0.01),
                 0.035, False),
        BodySpec(f"{side}lowerarm", f"{side}elbow", (0.0, 0.05, 0.0), _box(0.05, 0.11, 0.05), 0.200, True),
    ]
    up = "L" if side == "l" else "R"
    roll_limits = (-1.0, 95.0) if side == "l" else (-95.0, 1.0)
    elbow_roll_limits = (-90.0, 1.0) if side == "l" else (-1.0, 90.0)
    joints = [
        JointSpec(f"{side}aj1", f"{side}ae1", f"{up}ShoulderPitch", f"{side}shoulder", "torso", (0.0, 0.0, 0.0),
                  (1.0, 0.0, 0.0), -120.0, 120.0, -1),
        JointSpec(f"{side}aj2", f"{side}ae2", f"{up}ShoulderRoll", f"{side}upperarm", f"{side}shoulder",
                  (-s * 0.01, -0.02, 0.0), (0.0, 0.0, 1.0), *roll_limits, 1),
        JointSpec(f"{side}aj3", f"{side}ae3", f"{up}ElbowYaw", f"{side}elbow", f"{side}upperarm", (0.0, 0.0, 0.0),
                  (0.0, 1.0, 0.0), -120.0, 120.0, 1),
        JointSpec(f"{side}aj4", f"{side}ae4", f"{up}ElbowRoll", f"{side}lowerarm", f"{side}elbow",
                  (0.0, -0.05, 0.0), (0.0, 0.0, 1.0), *elbow_roll_limits, 1),
    ]
    return bodies, joints


def _leg(side: str, p: TypeParameters) -> tuple[list[BodySpec], list[JointSpec]]:
    """Bodies and joints of one leg; type 4 splits the foot and adds the toe hinge lj7."""
    s = -1.0 if side == "l" else 1.0
    has_toes = p.toe_length_m > 0.0
    foot_shape = _box(*TOE_FOOT_SIZE_M) if has_toes else _box(0.08, 0.16, 0.02)
    foot_mass = TOE_FOOT_MASS_KG if has_toes else 0.200
    foot_offset = (0.0, TOE_FOOT_OFFSET_Y_M if has_toes else 0.03, -0.04)
    bodies = [
        BodySpec(f"{side}hip1", "torso", (s * p.hip1_rel_torso_x, -0.01, p.hip1_rel_torso_z), _sphere(0.01),
                 0.090, False),
        BodySpec(f"{side}hip2", f"{side}hip1", (0.0, 0.0, 0.0), _sphere(0.01), 0.125, False),
        BodySpec(f"{side}thigh", f"{side}hip2", (0.0, 0.01, p.thigh_rel_hip2_z), _box(0.07, 0.07, 0.14), 0.275,
                 True),
        BodySpec(f"{side}shank", f"{side}thigh", (0.0, 0.005, -0.125), _box(0.08, 0.07, 0.11), 0.225, True),
        BodySpec(f"{side}ankle", f"{side}shank", (0.0, -0.01, p.ankle_rel_shank_z), _sphere(0.01), 0.125, False),
        BodySpec(f"{side}foot", f"{side}ankle", foot_offset, foot_shape, foot_mass, True),
    ]
    up = "L" if side == "l" else "R"
    yaw_axis = (-_SQ, 0.0, -_SQ) if side == "l" else (-_SQ, 0.0, _SQ)
    hip_roll_limits = (-25.0, 45.0) if side == "l" else (-45.0, 25.0)
    ankle_roll_limits = (-45.0, 25.0) if side == "l" else (-25.0, 45.0)
    joints = [
        JointSpec(f"{side}lj1", f"{side}le1", f"{up}HipYawPitch", f"{side}hip1", "torso", (0.0, 0.0, 0.0),
                  yaw_axis, -90.0, 1.0, 1),
        JointSpec(f"{side}lj2", f"{side}le2", f"{up}HipRoll", f"{side}hip2", f"{side}hip1", (0.0, 0.0, 0.0),
                  (0.0, 1.0, 0.0), *hip_roll_limits, 1),
        # The hip-pitch anchor is -ThighRelHip2 for every type: the pitch axis always sits at the hip point.
        JointSpec(f"{side}lj3", f"{side}le3", f"{up}HipPitch", f"{side}thigh", f"{side}hip2",
                  (0.0, -0.01, -p.thigh_rel_hip2_z), (1.0, 0.0, 0.0), -25.0, 100.0, -1),
        JointSpec(f"{side}lj4", f"{side}le4", f"{up}KneePitch", f"{side}shank", f"{side}thigh",
                  (0.0, -0.01, 0.045), (1.0, 0.0, 0.0), -130.0, 1.0, -1),
        JointSpec(f"{side}lj5", f"{side}le5", f"{up}AnklePitch", f"{side}ankle", f"{side}shank", (0.0, 0.0, 0.0),
                  (1.0, 0.0, 0.0), -45.0, 75.0, -1, max_speed_rad_s=p.ankle_pitch_max_speed_rad_s),
        # Type 4 quirk: the anchor is relative to the moved foot centre, 1.78 cm behind lj5.
        JointSpec(f"{side}lj6", f"{side}le6", f"{up}AnkleRoll", f"{side}foot", f"{side}ankle", (0.0, -0.03, 0.035),
                  (0.0, 1.0, 0.0), *ankle_roll_limits, 1, max_speed_rad_s=p.ankle_roll_max_speed_rad_s),
    ]
    if has_toes:
        bodies.append(BodySpec(f"{side}toe", f"{side}foot", TOE_OFFSET_IN_FOOT_M, _box(*TOE_SIZE_M), TOE_MASS_KG,
                               True))
        joints.append(JointSpec(f"{side}lj7", f"{side}le7", f"{up}Toe", f"{side}toe", f"{side}foot",
                                TOE_ANCHOR_IN_TOE_M, (1.0, 0.0, 0.0), -1.0, 70.0, -1))
    return bodies, joints


def check_robot_type(robot_type: object) -> int:
    """Validate a robot type number; SpecError naming the allowed values otherwise."""
    if isinstance(robot_type, bool) or not isinstance(robot_type, int) or robot_type not in TYPE_PARAMETERS:
        raise SpecError(f"unknown robot type {robot_type!r}: expected one of {list(ROBOT_TYPES)}",
                        field="robot_type")
    return robot_type


@lru_cache(maxsize=None)
def robot_spec(robot_type: int = 0) -> RobotSpec:
    """The full spec of one robot type (0-4).

    Raises:
        SpecError: robot_type is not 0-4.
    """
    p = TYPE_PARAMETERS[check_robot_type(robot_type)]
    bodies: list[BodySpec] = [
        BodySpec("torso", "", (0.0, 0.0, 0.0), _box(0.10, 0.10, 0.18), 1.2171, True),
        BodySpec("neck", "torso", (0.0, 0.0, 0.09), Shape("capsule", (0.015, 0.08)), 0.050, True),
        BodySpec("head", "neck", (0.0, 0.0, 0.065), _sphere(0.065), 0.350, True),
    ]
    joints: list[JointSpec] = [
        JointSpec("hj1", "he1", "HeadYaw", "neck", "torso", (0.0, 0.0, 0.0), (0.0, 0.0, 1.0), -120.0, 120.0, 1),
        JointSpec("hj2", "he2", "HeadPitch", "head", "neck", (0.0, 0.0, -0.005), (1.0, 0.0, 0.0), -45.0, 45.0, -1),
    ]
    # Canonical order of REFERENCE §2.2: head, left arm, left leg, right leg, right arm.
    for part in (_arm("l", p), _leg("l", p), _leg("r", p), _arm("r", p)):
        bodies.extend(part[0])
        joints.extend(part[1])
    sensors = (
        SensorSpec("camera", "camera", "head"),
        SensorSpec("torso", "gyro", "torso"),
        SensorSpec("torso", "accelerometer", "torso"),
        SensorSpec("lf", "force", "lfoot"),
        SensorSpec("rf", "force", "rfoot"),
    ) + ((SensorSpec("lf1", "force", "ltoe"), SensorSpec("rf1", "force", "rtoe")) if p.toe_length_m > 0 else ())
    return RobotSpec(robot_type, tuple(bodies), tuple(joints), sensors)


# Wire order of the 22 common hinges, the project's joint keys (type 4 adds llj7 and rlj7).
JOINT_NAMES: tuple[str, ...] = tuple(j.perceptor for j in robot_spec(0).joints)
EFFECTOR_NAMES: tuple[str, ...] = tuple(j.effector for j in robot_spec(0).joints)
NAO_NAMES: tuple[str, ...] = tuple(j.nao_name for j in robot_spec(0).joints)
