"""Forward kinematics with Pinocchio: camera pose and height, CoM, foot and hand frames, support polygon.

Joint angles are SimSpark-signed radians in the spec's canonical order (or a mapping by wire name).
The torso orientation is given separately (from the agent's inertial estimate), so the same call answers
"how high is my camera" for a robot that leans.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np
import pinocchio as pin

from kinematics.errors import SpecError
from kinematics.mjcf import CAMERA_SITE, site_offsets
from kinematics.pinocchio_model import pinocchio_model
from kinematics.spec import robot_spec

FOOT_BODIES = ("lfoot", "rfoot")
CONTACT_TOLERANCE_M = 1e-3  # sole corners within this of the lowest one count as touching the ground


def torso_rotation(pitch_forward_rad: float = 0.0, roll_right_rad: float = 0.0) -> np.ndarray:
    """Torso orientation in a gravity-aligned frame (x right, y forward, z up), 3x3.

    Args:
        pitch_forward_rad: lean forward (positive: the chest goes down toward +y).
        roll_right_rad: lean to the right (positive: the top goes toward +x).
    """
    cp, sp = np.cos(pitch_forward_rad), np.sin(pitch_forward_rad)
    cr, sr = np.cos(roll_right_rad), np.sin(roll_right_rad)
    # Pitch forward = rotation about +x by -pitch; roll right = rotation about +y by +roll (applied after).
    pitch = np.array([[1.0, 0.0, 0.0], [0.0, cp, sp], [0.0, -sp, cp]])
    roll = np.array([[cr, 0.0, sr], [0.0, 1.0, 0.0], [-sr, 0.0, cr]])
    return roll @ pitch


@dataclass(frozen=True)
class FramePose:
    """A frame's pose in the torso frame (or a world frame where stated): position (m) and rotation (3x3)."""

    position_m: np.ndarray
    rotation: np.ndarray


class NaoKinematics:
    """Fixed-torso forward kinematics of one robot type; every pose is relative to the torso centre.

    Why fixed torso: the agent never knows its world pose exactly, while the torso-relative chain is exact;
    callers rotate by the torso orientation (see :func:`torso_rotation`) for gravity-aligned answers.
    """

    def __init__(self, robot_type: int = 0) -> None:
        self.robot_type = robot_type
        self.spec = robot_spec(robot_type)
        self.model = pinocchio_model(robot_type, free=False)
        self.data = self.model.createData()
        self.joint_names = self.spec.joint_names
        self._frame_ids = {f.name: i for i, f in enumerate(self.model.frames)}
        self._camera_id = self.frame_id(CAMERA_SITE)
        self._foot_ids = tuple(self.frame_id(name) for name in self._sole_bodies())
        corners = []
        for body in self._sole_bodies():
            sx, sy, sz = self.spec.body(body).shape.size
            corners.append(np.array([[x * sx / 2, y * sy / 2, -sz / 2] for x in (-1, 1) for y in (-1, 1)]).T)
        self._sole_corners = tuple(corners)  # each 3x4, in its body frame
        self._sole_half_sizes = tuple(tuple(v / 2 for v in self.spec.body(b).shape.size)
                                      for b in self._sole_bodies())
        self._free_model = pinocchio_model(robot_type, free=True)
        self._free_data = self._free_model.createData()
        self._free_torso_id = self._free_model.getFrameId("torso")

    def _sole_bodies(self) -> tuple[str, ...]:
        has_toes = any(b.name == "ltoe" for b in self.spec.bodies)
        return FOOT_BODIES + (("ltoe", "rtoe") if has_toes else ())

    def frame_id(self, name: str) -> int:
        """Pinocchio frame index of a body or site name (``head``, ``lsole``, ``camera``...)."""
        try:
            return self._frame_ids[name]
        except KeyError:
            raise SpecError(f"unknown frame {name!r}; known bodies and sites: "
                            f"{', '.join(sorted(b.name for b in self.spec.bodies))}, "
                            f"{', '.join(sorted(site_offsets(self.spec)))}", field="frame") from None

    def configuration(self, angles_rad: Mapping[str, float] | np.ndarray | None = None) -> np.ndarray:
        """Joint vector in canonical order from an array, a {wire/effector/Nao name: rad} mapping, or None (zero).

        Raises:
            SpecError: unknown joint name, wrong array length, or a non-finite angle.
        """
        n = len(self.joint_names)
        if type(angles_rad) is np.ndarray and angles_rad.shape == (n,) and angles_rad.dtype == np.float64:
            if not np.isfinite(angles_rad).all():
                bad = [self.joint_names[i] for i in np.flatnonzero(~np.isfinite(angles_rad))]
                raise SpecError(f"non-finite joint angle for {', '.join(bad)}", field=bad[0])
            return angles_rad  # hot path: the agent calls this every vision cycle
        if angles_rad is None:
            return np.zeros(n)
        if isinstance(angles_rad, Mapping):
            q = np.zeros(n)
            for name, value in angles_rad.items():
                q[self.spec.joints.index(self.spec.joint(name))] = value
        else:
            q = angles_rad if type(angles_rad) is np.ndarray and angles_rad.dtype == np.float64 \
                else np.asarray(angles_rad, dtype=float)
            if q.shape != (n,):
                raise SpecError(f"expected {n} joint angles for robot type {self.robot_type}, got shape {q.shape}",
                                field="angles_rad")
        if not np.isfinite(q).all():
            bad = [self.joint_names[i] for i in np.flatnonzero(~np.isfinite(q))]
            raise SpecError(f"non-finite joint angle for {', '.join(bad)}", field=bad[0])
        return q

    def update(self, q: np.ndarray) -> None:
        """Run Pinocchio's forward kinematics for joint vector q (canonical order, rad)."""
        pin.forwardKinematics(self.model, self.data, q)

    def frame_pose(self, name: str, angles_rad: Mapping[str, float] | np.ndarray | None = None) -> FramePose:
        """Pose of a body or site in the torso frame at the given joint angles."""
        self.update(self.configuration(angles_rad))
        placement = pin.updateFramePlacement(self.model, self.data, self.frame_id(name))
        return FramePose(placement.translation.copy(), placement.rotation.copy())

    def com(self, angles_rad: Mapping[str, float] | np.ndarray | None = None) -> np.ndarray:
        """Centre of mass in the torso frame (m).

        Uses the free-flyer model at the identity base: with the torso welded to the world, Pinocchio would
        leave the torso's own mass out of the CoM.
        """
        q = np.concatenate(([0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0], self.configuration(angles_rad)))
        com = pin.centerOfMass(self._free_model, self._free_data, q)
        torso = pin.updateFramePlacement(self._free_model, self._free_data, self._free_torso_id)
        return torso.rotation.T @ (com - torso.translation)

    def _lowest_sole_points(self, rotation: np.ndarray) -> np.ndarray:
        """All sole corners in the gravity-aligned torso-centred frame, 3 x (4 * n_feet); needs update()."""
        points = []
        for fid, corners in zip(self._foot_ids, self._sole_corners):
            placement = pin.updateFramePlacement(self.model, self.data, fid)
            points.append(placement.rotation @ corners + placement.translation[:, None])
        return rotation @ np.hstack(points)

    def camera_height_m(self, angles_rad: Mapping[str, float] | np.ndarray | None = None,
                        rotation: np.ndarray | None = None) -> float:
        """Height of the camera (head centre) above the lowest sole corner, gravity-aligned (m).

        The lowest corner of a box is found in closed form (no corner loop): for the gravity-aligned "up"
        row u in the box frame, min over corners of u.c = -|u_x| hx - |u_y| hy - u_z hz. This keeps the call
        near 10 us, since the agent asks it every vision cycle.

        Args:
            angles_rad: joint angles (canonical array or mapping), SimSpark sign.
            rotation: torso orientation (3x3) in a gravity-aligned frame; identity = upright.
        """
        q = self.configuration(angles_rad)
        model, data = self.model, self.data
        pin.forwardKinematics(model, data, q)
        camera = pin.updateFramePlacement(model, data, self._camera_id).homogeneous
        lowest = math.inf
        if rotation is None:  # upright: the up row of each box rotation is its third row
            for fid, (hx, hy, hz) in zip(self._foot_ids, self._sole_half_sizes):
                r0, r1, r2, z = pin.updateFramePlacement(model, data, fid).homogeneous[2].tolist()
                lowest = min(lowest, z - abs(r0) * hx - abs(r1) * hy - r2 * hz)
            return float(camera[2, 3] - lowest)
        up = np.asarray(rotation, dtype=float)[2]
        for fid, (hx, hy, hz) in zip(self._foot_ids, self._sole_half_sizes):
            box = pin.updateFramePlacement(model, data, fid).homogeneous
            r0, r1, r2, z = (up @ box[:3]).tolist()
            lowest = min(lowest, z - abs(r0) * hx - abs(r1) * hy - r2 * hz)
        return float(up @ camera[:3, 3] - lowest)

    def support_polygon(self, angles_rad: Mapping[str, float] | np.ndarray | None = None,
                        rotation: np.ndarray | None = None) -> np.ndarray:
        """Convex hull (counter-clockwise, k x 2, x/y in m) of the sole corners touching the ground.

        Ground contact is geometric: corners within 1 mm of the lowest one, in the gravity-aligned,
        torso-centred frame.
        """
        self.update(self.configuration(angles_rad))
        rot = np.eye(3) if rotation is None else rotation
        points = self._lowest_sole_points(rot)
        touching = points[:, points[2] <= points[2].min() + CONTACT_TOLERANCE_M]
        return convex_hull_2d(touching[:2].T)


def convex_hull_2d(points: np.ndarray) -> np.ndarray:
    """Andrew's monotone chain; returns the hull counter-clockwise without repeating the first point."""
    pts = sorted(map(tuple, np.round(points, 12)))
    if len(pts) <= 2:
        return np.array(pts)

    def cross(o: tuple, a: tuple, b: tuple) -> float:
        return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])

    lower: list[tuple] = []
    for p in pts:
        while len(lower) >= 2 and cross(lower[-2], lower[-1], p) <= 0:
            lower.pop()
        lower.append(p)
    upper: list[tuple] = []
    for p in reversed(pts):
        while len(upper) >= 2 and cross(upper[-2], upper[-1], p) <= 0:
            upper.pop()
        upper.append(p)
    return np.array(lower[:-1] + upper[:-1])
