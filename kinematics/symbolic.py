"""A symbolic Nao: CasADi functions for every body and site pose and the centre of mass of each robot type,
generated from the spec (the same tree the MJCF and Pinocchio models are made from).

Why symbolic: keyframe optimisation (kick strikes, stand-up poses) wants exact derivatives of frame poses
and the CoM with respect to the joint angles inside an NLP; Pinocchio's CasADi bindings are not in the
pinned wheel, and the Nao's tree is simple enough to write once: every body frame sits at its body centre,
axis-aligned with the torso at zero pose (``kinematics.mjcf``), and each hinge turns its child about
``axis`` through the anchor. A test holds it to Pinocchio within 1e-9 m.

Functions (inputs and outputs named as in pinocchio's casadi examples): ``pose_<frame>(q) -> (position_m,
rotation)`` in the torso frame, ``com(q) -> com_m`` in the torso frame, with ``q`` the joint angles [rad,
SimSpark signs] in the spec's canonical order.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

import casadi

from kinematics.errors import SpecError
from kinematics.mjcf import site_offsets
from kinematics.spec import RobotSpec, robot_spec


def axis_rotation(axis: tuple[float, float, float], angle: casadi.SX) -> casadi.SX:
    """Rotation by ``angle`` [rad] about the unit ``axis`` (Rodrigues), 3x3."""
    k = casadi.DM(axis)
    skew = casadi.skew(k)
    return casadi.DM.eye(3) + casadi.sin(angle) * skew + (1 - casadi.cos(angle)) * (skew @ skew)


@dataclass(frozen=True)
class SymbolicNao:
    """The CasADi functions of one robot type (see the module docstring)."""

    robot_type: int
    joint_names: tuple[str, ...]
    frames: tuple[str, ...]
    poses: dict[str, casadi.Function]
    com: casadi.Function

    def pose(self, frame: str) -> casadi.Function:
        """``pose_<frame>``: q -> (position_m, rotation).

        Raises:
            SpecError: an unknown frame (the message lists the known ones).
        """
        try:
            return self.poses[frame]
        except KeyError:
            raise SpecError(f"unknown frame {frame!r}; known: {', '.join(self.frames)}", field="frame") from None


def build(spec: RobotSpec) -> SymbolicNao:
    """Walk the spec's tree (parents first) and name a Function per body, per site, and for the CoM."""
    q = casadi.SX.sym("q", len(spec.joints))
    joints = {joint.child: (index, joint) for index, joint in enumerate(spec.joints)}
    positions: dict[str, casadi.SX] = {}
    rotations: dict[str, casadi.SX] = {}
    for body in spec.bodies:
        if not body.parent:
            positions[body.name], rotations[body.name] = casadi.SX.zeros(3), casadi.SX.eye(3)
            continue
        parent_p, parent_r = positions[body.parent], rotations[body.parent]
        offset = casadi.DM(body.offset_m)
        if body.name in joints:
            index, joint = joints[body.name]
            turn = axis_rotation(joint.axis, q[index])
            anchor = casadi.DM(joint.anchor_in_child_m)
            # the child's centre turns about the anchor (offset + anchor in the parent frame)
            local = offset + anchor - turn @ anchor
            rotations[body.name] = parent_r @ turn
        else:
            local = offset
            rotations[body.name] = parent_r
        positions[body.name] = parent_p + parent_r @ local
    poses = {name: casadi.Function(f"pose_{name}", [q], [positions[name], rotations[name]], ["q"],
                                   ["position_m", "rotation"]) for name in positions}
    for site, (body, offset) in site_offsets(spec).items():
        position = positions[body] + rotations[body] @ casadi.DM(offset)
        poses[site] = casadi.Function(f"pose_{site}", [q], [position, rotations[body]], ["q"], ["position_m", "rotation"])
    total = sum(body.mass_kg for body in spec.bodies)
    com = sum((body.mass_kg * positions[body.name] for body in spec.bodies), casadi.SX.zeros(3)) / total
    return SymbolicNao(spec.robot_type, spec.joint_names, tuple(poses),
                       poses, casadi.Function("com", [q], [com], ["q"], ["com_m"]))


@lru_cache(maxsize=None)
def symbolic_nao(robot_type: int = 0) -> SymbolicNao:
    """The symbolic Nao of ``robot_type`` (built once per process)."""
    return build(robot_spec(robot_type))


def pinocchio_max_diff_m(robot_type: int = 0, samples: int = 10, seed: int = 0) -> float:
    """Largest difference between the symbolic Nao and Pinocchio (``kinematics.fk``) over ``samples`` random
    joint vectors within the stops: frame positions [m], rotation entries and the CoM [m]."""
    import numpy as np

    from kinematics.fk import NaoKinematics

    rng = np.random.default_rng(seed)
    symbolic, pinocchio = symbolic_nao(robot_type), NaoKinematics(robot_type)
    frames = [name for name in symbolic.frames if name in pinocchio._frame_ids]
    worst = 0.0
    for _ in range(samples):
        q = np.array([rng.uniform(j.min_rad, j.max_rad) for j in pinocchio.spec.joints])
        for name in frames:
            position, rotation = symbolic.pose(name)(q)
            reference = pinocchio.frame_pose(name, q)
            worst = max(worst, float(np.max(np.abs(np.array(position).ravel() - reference.position_m))),
                        float(np.max(np.abs(np.array(rotation) - reference.rotation))))
        worst = max(worst, float(np.max(np.abs(np.array(symbolic.com(q)).ravel() - pinocchio.com(q)))))
    return worst


__all__ = ["SymbolicNao", "axis_rotation", "build", "pinocchio_max_diff_m", "symbolic_nao"]
