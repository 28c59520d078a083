"""Left/right mirror of motions, derived from the hinge axes of the spec rather than from a hand-made list.

The mirror is the reflection through the robot's sagittal plane x = 0 (x = robot's right, REFERENCE §1),
M = diag(-1, 1, 1). A rotation axis is a pseudo-vector, so reflecting a rotation by angle q about axis
a = (ax, ay, az) gives a rotation by the same q about M·a·det(M) = (ax, -ay, -az). Each joint therefore
maps to its counterpart on the other side (the head joints to themselves) with

    sign = counterpart.axis · (ax, -ay, -az)   (= +1 or -1)

which gives: pitch joints (axis along x) keep their sign; roll and yaw joints (axis along y or z: HeadYaw,
ShoulderRoll, ElbowYaw, ElbowRoll, HipRoll, AnkleRoll) flip; the hip yaw-pitch joints, whose axes
(-1, 0, ∓1)/√2 are each other's reflection, keep their sign (both have the range -90..1°, as they must).
A rule "only axes with an x-component keep their sign" gives the same except for the hip yaw-pitch, which has
both x and z components; the derivation settles it. ``computed`` names and phase names are kept as they are:
what a run-time value means on the other side is the controller's business.
"""

from __future__ import annotations

import dataclasses
from functools import lru_cache

from kinematics import JointSpec, SpecError, robot_spec

from motions.model import JointTarget, Keyframe, Motion

_SIGN_TOLERANCE = 1e-6


def _counterpart(joint: JointSpec, by_wire: dict[str, JointSpec]) -> JointSpec:
    """The same joint on the other side (``llj3`` <-> ``rlj3``); a joint on the midline is its own."""
    side = joint.perceptor[0]
    if side in "lr":
        other = by_wire.get(("r" if side == "l" else "l") + joint.perceptor[1:])
        if other is not None:
            return other
    return joint


@lru_cache(maxsize=None)
def mirror_table() -> dict[str, tuple[str, int]]:
    """Wire name -> (mirrored wire name, sign), for every hinge of every robot type.

    Raises:
        SpecError: never for the spec as it is; it guards against a spec edit that breaks the symmetry.
    """
    joints = robot_spec(4).joints
    by_wire = {j.perceptor: j for j in joints}
    table: dict[str, tuple[str, int]] = {}
    for joint in joints:
        other = _counterpart(joint, by_wire)
        ax, ay, az = joint.axis
        reflected = (ax, -ay, -az)
        dot = sum(c * r for c, r in zip(other.axis, reflected))
        sign = 1 if dot > 0 else -1
        if abs(abs(dot) - 1.0) > _SIGN_TOLERANCE:
            raise SpecError(f"spec axes of {joint.perceptor} {joint.axis} and {other.perceptor} {other.axis} "
                            "are not mirror images", field="axis")
        table[joint.perceptor] = (other.perceptor, sign)
    return table


def mirrored_pose(pose: dict[str, float | None]) -> dict[str, float | None]:
    """Mirror a wire name -> angle (rad) mapping; unknown names are an error (KeyError names them)."""
    table = mirror_table()
    result: dict[str, float | None] = {}
    for name, angle in pose.items():
        other, sign = table[name]
        result[other] = None if angle is None else sign * angle
    return result


def _mirrored_keyframe(keyframe: Keyframe) -> Keyframe:
    table = mirror_table()
    targets: dict[str, JointTarget] = {}
    for name, target in keyframe.targets.items():
        other, sign = table[name]
        angle = None if target.angle_rad is None else sign * target.angle_rad
        targets[other] = JointTarget(angle, target.computed)
    return dataclasses.replace(keyframe, targets=targets, source=None)


def mirrored_motion(motion: Motion) -> Motion:
    """The left/right mirror image of ``motion``: targets moved to the other side with the derived sign.

    Phase order, names, durations, flags and ``computed`` names are unchanged. File layout details are
    dropped (the values changed), so the writers produce the canonical layout.
    """
    table = mirror_table()
    joint_order = None if motion.joint_order is None else tuple(table[j][0] for j in motion.joint_order)
    return dataclasses.replace(motion, keyframes=[_mirrored_keyframe(k) for k in motion.keyframes],
                               joint_order=joint_order, source=None)
