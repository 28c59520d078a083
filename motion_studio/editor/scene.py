"""The editor's meshcat scene: the kinematic Nao, IK handles, CoM and support polygon, the simulated Nao.

Commands go to a ``BufferedWindow`` instead of meshcat's own ZMQ server: the web edge sends everything an
edit produced as one binary WebSocket frame, to the tab that made the edit, where meshcat's own viewer
(served from the meshcat package) applies them. Frame layout: repeated (4-byte big-endian length, msgpack
command), the commands exactly as meshcat's server would forward them.
"""

from __future__ import annotations

import math
import struct
from collections.abc import Mapping

import meshcat
import meshcat.geometry as geometry
import meshcat.transformations as transformations
from meshcat.commands import SetTransform
import numpy as np
import umsgpack

from kinematics.meshcat_view import NaoPosePainter, add_ground, add_nao, frame_camera, set_body_poses

from motion_studio.editor.ik_handles import HANDLES, Balance

HANDLE_RADIUS_M = 0.018
HANDLE_COLOURS = {"lfoot": 0xF0A020, "rfoot": 0xF0A020, "lhand": 0x20C0E0, "rhand": 0x20C0E0, "torso": 0xE040C0}
SIM_COLOUR = 0x4A7FE0
COM_COLOUR = 0xE02020
INSIDE_COLOUR = 0x20A040
OUTSIDE_COLOUR = 0xE02020
#: Bars of the support polygon (four sole boxes of a type-4 robot have a hull of at most 16 corners).
MAX_SUPPORT_EDGES = 16
_Y_TO_Z = transformations.rotation_matrix(np.pi / 2, [1, 0, 0])
_PARKED = transformations.translation_matrix([0.0, 0.0, -10.0])  # unused bars, out of sight below the ground


def _rgba(colour: int) -> list[float]:
    return [((colour >> 16) & 0xFF) / 255.0, ((colour >> 8) & 0xFF) / 255.0, (colour & 0xFF) / 255.0, 1.0]


def _msgpack_str(text: str) -> bytes:
    data = text.encode("utf-8")
    if len(data) < 32:
        return bytes([0xA0 | len(data)]) + data
    if len(data) < 256:
        return b"\xd9" + bytes([len(data)]) + data
    return b"\xda" + struct.pack(">H", len(data)) + data


_TRANSFORM_HEAD = b"\x83" + _msgpack_str("type") + _msgpack_str("set_transform") + _msgpack_str("path")
_MATRIX_KEY = _msgpack_str("matrix") + b"\xdc\x00\x10"  # array16 of 16 float64
_MATRIX_FORMAT = struct.Struct(">" + "Bd" * 16)


def pack_set_transform(path: str, matrix: np.ndarray) -> bytes:
    """Exactly ``umsgpack.packb(SetTransform(matrix, path).lower())``, 20x faster (the per-edit hot path)."""
    values = np.asarray(matrix, dtype=float).T.ravel().tolist()
    interleaved = [0xCB] * 32
    interleaved[1::2] = values
    return _TRANSFORM_HEAD + _msgpack_str(path) + _MATRIX_KEY + _MATRIX_FORMAT.pack(*interleaved)


class BufferedWindow:
    """A meshcat "window" that collects commands; ``flush`` returns them as one frame (None if empty)."""

    def __init__(self) -> None:
        self._parts: list[bytes] = []
        self.commands_sent = 0

    def send(self, command: object) -> None:
        if isinstance(command, SetTransform):
            packed = pack_set_transform(command.path.lower(), command.matrix)
        else:
            packed = umsgpack.packb(command.lower())  # type: ignore[attr-defined]
        self._parts.append(struct.pack(">I", len(packed)) + packed)
        self.commands_sent += 1

    def flush(self) -> bytes | None:
        if not self._parts:
            return None
        frame, self._parts = b"".join(self._parts), []
        return frame


def _material(colour: int, opacity: float = 1.0) -> geometry.MeshLambertMaterial:
    return geometry.MeshLambertMaterial(color=colour, opacity=opacity, transparent=opacity < 1.0)


class EditorScene:
    """Draws one tab's scene on ``vis`` (a meshcat Visualizer on a BufferedWindow).

    Args:
        vis: the visualizer. robot_type: 0-4. painter: a shared NaoPosePainter (FK) for that type.
    """

    def __init__(self, vis: meshcat.Visualizer, robot_type: int, painter: NaoPosePainter) -> None:
        self.vis = vis
        self.robot_type = robot_type
        self.painter = painter
        self._polygon: np.ndarray | None = None
        self._inside: bool | None = None
        self._handles_visible: bool | None = None
        self._sim_visible: bool | None = None

    def build(self) -> None:
        """Create every object once: ground, camera, robots, handles, CoM marker and support polygon."""
        vis = self.vis
        add_ground(vis, size_m=2.0)
        vis["/Grid"].set_property("visible", False)  # meshcat's 20 m grid; the ground slab is enough
        # Both robots in view: the kinematic one at the origin, the simulated one 0.5 m to its right (+x).
        frame_camera(vis, position_m=(0.8, 0.95, 0.5), target_m=(0.22, 0.0, 0.2))
        add_nao(vis, "nao", self.robot_type)
        add_nao(vis, "sim", self.robot_type, colour=SIM_COLOUR, opacity=0.9)
        self.set_sim_visible(False)
        for handle in HANDLES:
            vis["handles"][handle].set_object(geometry.Sphere(HANDLE_RADIUS_M),
                                              _material(HANDLE_COLOURS[handle], 0.85))
        vis["com"]["ball"].set_object(geometry.Sphere(0.012), _material(COM_COLOUR))
        vis["com"]["line"].set_object(geometry.Cylinder(1.0, 0.002), _material(COM_COLOUR, 0.7))
        vis["com"]["ground"].set_object(geometry.Cylinder(0.002, 0.012), _material(INSIDE_COLOUR))
        # The support polygon is a fixed set of unit-length bars moved onto its edges: per-frame updates are
        # transforms only (a new meshcat object per frame costs the browser tens of ms).
        for edge in range(MAX_SUPPORT_EDGES):
            vis["support"][str(edge)].set_object(geometry.Box([1.0, 0.004, 0.002]), _material(INSIDE_COLOUR))

    def show_pose(self, angles_rad: Mapping[str, float] | np.ndarray, handles: Mapping[str, np.ndarray] | None,
                  balance: Balance) -> None:
        """Place the kinematic robot, its handles (None hides them), the CoM and the support polygon."""
        self.painter.paint(self.vis, "nao", angles_rad)
        self._set_handles_visible(handles is not None)
        if handles is not None:
            for name, pose in handles.items():
                self.vis["handles"][name].set_transform(transformations.translation_matrix(pose[:3, 3]))
        x, y, z = (float(v) for v in balance.com_m)
        self.vis["com"]["ball"].set_transform(transformations.translation_matrix([x, y, z]))
        line = transformations.translation_matrix([x, y, z / 2]) @ np.diag([1.0, 1.0, max(z, 1e-4), 1.0]) @ _Y_TO_Z
        self.vis["com"]["line"].set_transform(line)
        self._show_support(balance)
        self.vis["com"]["ground"].set_transform(transformations.translation_matrix([x, y, 0.001]) @ _Y_TO_Z)

    def _show_support(self, balance: Balance) -> None:
        polygon = balance.support_xy_m
        if self._polygon is None or self._polygon.shape != polygon.shape or \
                not np.allclose(self._polygon, polygon, atol=1e-5):
            self._polygon = polygon.copy()
            edges = list(zip(polygon, np.roll(polygon, -1, axis=0))) if len(polygon) >= 2 else []
            for edge in range(MAX_SUPPORT_EDGES):
                node = self.vis["support"][str(edge)]
                if edge < len(edges):
                    start, end = edges[edge]
                    dx, dy = end - start
                    pose = transformations.translation_matrix([(start[0] + end[0]) / 2, (start[1] + end[1]) / 2,
                                                               0.001])
                    pose = pose @ transformations.rotation_matrix(math.atan2(dy, dx), [0, 0, 1])
                    node.set_transform(pose @ np.diag([max(math.hypot(dx, dy), 1e-4), 1.0, 1.0, 1.0]))
                else:
                    node.set_transform(_PARKED)
        if balance.inside != self._inside:
            self._inside = balance.inside
            colour = _rgba(INSIDE_COLOUR if balance.inside else OUTSIDE_COLOUR)
            self.vis["support"].set_property("color", colour)
            self.vis["com"]["ground"].set_property("color", colour)

    def show_sim(self, body_poses: Mapping[str, np.ndarray] | None) -> None:
        """Place the simulated robot (a physics-preview sample); None hides it."""
        self.set_sim_visible(body_poses is not None)
        if body_poses is not None:
            set_body_poses(self.vis, "sim", body_poses)

    def set_sim_visible(self, visible: bool) -> None:
        if visible != self._sim_visible:
            self.vis["sim"].set_property("visible", visible)
            self._sim_visible = visible

    def _set_handles_visible(self, visible: bool) -> None:
        if visible != self._handles_visible:
            self.vis["handles"].set_property("visible", visible)
            self._handles_visible = visible
