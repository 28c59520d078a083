"""IK handles: where the feet, hands and torso of a pose are, and the whole pose that puts one of them elsewhere.

Display frame ("ground frame" of the editor): SimSpark axes (x right, y forward, z up), the robot standing
upright with its lowest sole corner on z = 0 and its torso centre above the origin, as
``kinematics.meshcat_view.NaoPosePainter`` draws it. The kinematics room's ``WholeBodyIK`` has its own
ground frame (lowest sole *centre* on z = 0); both are related through the torso pose at the seed, so a
target given in the display frame lands exactly where the user put it.

Moving one handle keeps the others: both feet stay where they are (hard contacts), the torso keeps its
pose unless it is the handle, and arms that are not moved keep their joints (no hand target). Hands take a
position only (a 4-DOF arm cannot take an arbitrary orientation). With ``keep_com`` the CoM's ground
projection stays where it was too.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from kinematics.errors import SpecError
from kinematics.ik import PoseTarget, WholeBodyIK
from kinematics.meshcat_view import NaoPosePainter

#: Handle name -> frame (MJCF site or body) it moves, as the kinematics room's IK names them.
HANDLE_FRAMES: dict[str, str] = {"lfoot": "lsole", "rfoot": "rsole", "lhand": "lhand", "rhand": "rhand",
                                 "torso": "torso"}
HANDLES: tuple[str, ...] = tuple(HANDLE_FRAMES)
#: Handles whose orientation can be set (hands: position only).
ORIENTED_HANDLES = frozenset({"lfoot", "rfoot", "torso"})


@dataclass(frozen=True)
class Balance:
    """Static balance of a pose in the display frame.

    com_m: centre of mass (x, y, z) [m]. support_xy_m: support polygon, counter-clockwise (k x 2) [m] at
    z = 0. inside: whether the CoM's ground projection lies in the polygon. margin_m: signed distance from the
    projection to the polygon's edge (> 0 inside) [m].
    """

    com_m: np.ndarray
    support_xy_m: np.ndarray
    inside: bool
    margin_m: float


def rotation_from_xyz_deg(angles_deg: tuple[float, float, float]) -> np.ndarray:
    """Rotation matrix R = Rz(c) · Ry(b) · Rx(a) for angles (a, b, c) about the x, y, z axes [deg]."""
    a, b, c = (math.radians(v) for v in angles_deg)
    rx = np.array([[1, 0, 0], [0, math.cos(a), -math.sin(a)], [0, math.sin(a), math.cos(a)]])
    ry = np.array([[math.cos(b), 0, math.sin(b)], [0, 1, 0], [-math.sin(b), 0, math.cos(b)]])
    rz = np.array([[math.cos(c), -math.sin(c), 0], [math.sin(c), math.cos(c), 0], [0, 0, 1]])
    return rz @ ry @ rx


def xyz_deg_from_rotation(rotation: np.ndarray) -> tuple[float, float, float]:
    """The (a, b, c) angles [deg] of ``rotation_from_xyz_deg`` (b in [-90, 90])."""
    r = np.asarray(rotation, dtype=float)
    b = math.asin(max(-1.0, min(1.0, -r[2, 0])))
    if abs(r[2, 0]) < 1.0 - 1e-9:
        a = math.atan2(r[2, 1], r[2, 2])
        c = math.atan2(r[1, 0], r[0, 0])
    else:  # gimbal lock: put everything in c
        a = 0.0
        c = math.atan2(-r[0, 1], r[1, 1])
    return (math.degrees(a), math.degrees(b), math.degrees(c))


def _signed_margin(point: np.ndarray, polygon: np.ndarray) -> float:
    """Signed distance [m] from ``point`` to a counter-clockwise convex polygon's boundary (> 0 inside)."""
    if len(polygon) < 3:
        if len(polygon) == 0:
            return -math.inf
        distances = [float(np.linalg.norm(point - p)) for p in polygon]
        return -min(distances)
    margin = math.inf
    for start, end in zip(polygon, np.roll(polygon, -1, axis=0)):
        edge = end - start
        length = float(np.linalg.norm(edge))
        if length == 0.0:
            continue
        # Left of a counter-clockwise edge is inside.
        margin = min(margin, float(edge[0] * (point[1] - start[1]) - edge[1] * (point[0] - start[0])) / length)
    return margin


class HandleSolver:
    """Handle poses, balance and IK for one robot type (keeps one FK model and one PlaCo solver).

    Args:
        robot_type: 0-4.
    """

    def __init__(self, robot_type: int = 0) -> None:
        self.painter = NaoPosePainter(robot_type)
        self.kinematics = self.painter.kinematics
        self.ik = WholeBodyIK(robot_type)
        self.joint_names = self.kinematics.joint_names
        self._cache: tuple[bytes, dict[str, np.ndarray], Balance] | None = None

    def vector(self, angles_rad: Mapping[str, float] | np.ndarray) -> np.ndarray:
        """Joint angles in the spec's canonical order (rad); missing joints are 0."""
        if isinstance(angles_rad, np.ndarray):
            return np.asarray(angles_rad, dtype=np.float64)
        return np.array([float(angles_rad.get(name, 0.0)) for name in self.joint_names], dtype=np.float64)

    def torso_pose(self, angles_rad: Mapping[str, float] | np.ndarray) -> np.ndarray:
        """4x4 torso placement in the display frame (upright, lowest sole corner on z = 0)."""
        q = self.vector(angles_rad)
        torso = np.eye(4)
        torso[2, 3] = self.kinematics.camera_height_m(q) - self.kinematics.frame_pose("head", q).position_m[2]
        return torso

    def handle_poses(self, angles_rad: Mapping[str, float] | np.ndarray) -> dict[str, np.ndarray]:
        """Handle name -> 4x4 pose of its frame in the display frame."""
        return {name: pose.copy() for name, pose in self._analysis(self.vector(angles_rad))[0].items()}

    def balance(self, angles_rad: Mapping[str, float] | np.ndarray) -> Balance:
        """CoM, support polygon and whether the CoM projects inside it, in the display frame."""
        return self._analysis(self.vector(angles_rad))[1]

    def _analysis(self, q: np.ndarray) -> tuple[dict[str, np.ndarray], Balance]:
        """Handles and balance of one pose; the last pose's answer is kept (the panel asks twice per edit)."""
        key = q.tobytes()
        if self._cache is not None and self._cache[0] == key:
            return self._cache[1], self._cache[2]
        torso = self.torso_pose(q)
        handles = {}
        for handle, frame in HANDLE_FRAMES.items():
            local = self.kinematics.frame_pose(frame, q)
            pose = np.eye(4)
            pose[:3, :3], pose[:3, 3] = local.rotation, local.position_m
            handles[handle] = torso @ pose
        com = torso[:3, :3] @ self.kinematics.com(q) + torso[:3, 3]
        polygon = self.kinematics.support_polygon(q) + torso[:2, 3]
        margin = _signed_margin(com[:2], polygon)
        balance = Balance(com, polygon, margin > 0.0, margin)
        self._cache = (key, handles, balance)
        return handles, balance

    def solve(self, angles_rad: Mapping[str, float], handle: str, position_m: tuple[float, float, float] | None = None,
              rotation: np.ndarray | None = None, keep_com: bool = False) -> dict[str, float]:
        """The whole pose that puts ``handle`` at the target while the other handles stay.

        Args:
            angles_rad: the current pose, wire name -> rad (SimSpark sign), every joint of the robot type.
            handle: lfoot, rfoot, lhand, rhand or torso.
            position_m: target position in the display frame [m]; None keeps the current one.
            rotation: target 3x3 orientation in the display frame; None keeps the current one (ignored for
                hands).
            keep_com: also keep the CoM's ground projection.

        Returns:
            wire name -> angle [rad] for every joint, within the joint limits.

        Raises:
            SpecError: unknown handle or non-finite target. IKError: the target cannot be reached (the
                message names the task and its residual); the caller's pose is untouched.
        """
        if handle not in HANDLE_FRAMES:
            raise SpecError(f"unknown IK handle {handle!r}; known: {', '.join(HANDLES)}", field="handle")
        seed = self._clamped(angles_rad)
        display_poses = self.handle_poses(seed)
        self.ik.reset(seed)
        ik_torso = self.ik.robot.get_T_world_frame("torso").copy()
        # Display frame -> IK ground frame, through the torso pose both frames agree on at the seed.
        to_ik = ik_torso @ np.linalg.inv(self.torso_pose(seed))
        target = display_poses[handle].copy()
        if position_m is not None:
            target[:3, 3] = np.asarray(position_m, dtype=float)
        if rotation is not None and handle in ORIENTED_HANDLES:
            target[:3, :3] = np.asarray(rotation, dtype=float)
        if not np.isfinite(target).all():
            raise SpecError(f"IK handle {handle!r}: target must be finite", field="handle")
        targets: dict[str, PoseTarget] = {}
        for name in ("lfoot", "rfoot", "torso"):
            pose = to_ik @ (target if name == handle else display_poses[name])
            targets[name] = PoseTarget(pose[:3, 3], pose[:3, :3])
        if handle in ("lhand", "rhand"):
            targets[handle] = PoseTarget((to_ik @ target)[:3, 3])
        com_xy = None
        if keep_com:
            com = self.ik.robot.com_world()
            com_xy = (float(com[0]), float(com[1]))
        result = self.ik.solve(targets, com_xy_m=com_xy, seed_rad=seed)
        return dict(result.angles_rad)

    def _clamped(self, angles_rad: Mapping[str, float]) -> dict[str, float]:
        """The pose with every joint inside its limits (a file may hold values just outside them)."""
        spec = self.kinematics.spec
        pose = {}
        for name in self.joint_names:
            joint = spec.joint(name)
            pose[name] = min(max(float(angles_rad.get(name, 0.0)), joint.min_rad), joint.max_rad)
        return pose
