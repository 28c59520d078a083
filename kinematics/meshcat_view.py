"""Draws the Nao with its real SimSpark shapes in a meshcat scene; used by the viewer, the editor and replays.

Meshcat's Cylinder is along its local y axis; the neck capsule (axis z in SimSpark) is drawn as a cylinder
rotated onto z plus two end spheres. Body poses come from Pinocchio FK (fixed torso) or from a simulator.
"""

from __future__ import annotations

from collections.abc import Mapping

import meshcat
import meshcat.geometry as geometry
import meshcat.transformations as transformations
import numpy as np
import pinocchio as pin

from kinematics.fk import NaoKinematics
from kinematics.spec import BodySpec, robot_spec

DEFAULT_COLOURS = {"body": 0xB8BCC8, "joint": 0x404048, "highlight": 0x3070E0}
_Y_TO_Z = transformations.rotation_matrix(np.pi / 2, [1, 0, 0])


def _material(colour: int, opacity: float) -> geometry.MeshLambertMaterial:
    return geometry.MeshLambertMaterial(color=colour, opacity=opacity, transparent=opacity < 1.0)


def _add_body_geometry(vis: meshcat.Visualizer, path: str, body: BodySpec, colour: int, opacity: float) -> None:
    shape, material = body.shape, _material(colour, opacity)
    if shape.kind == "box":
        vis[path]["shape"].set_object(geometry.Box(list(shape.size)), material)
    elif shape.kind == "sphere":
        vis[path]["shape"].set_object(geometry.Sphere(shape.size[0]), material)
    else:
        radius, length = shape.size
        vis[path]["shape"].set_object(geometry.Cylinder(length, radius), material)
        vis[path]["shape"].set_transform(_Y_TO_Z)
        for end, z in (("top", length / 2), ("bottom", -length / 2)):
            vis[path][end].set_object(geometry.Sphere(radius), material)
            vis[path][end].set_transform(transformations.translation_matrix([0, 0, z]))


def add_nao(vis: meshcat.Visualizer, name: str = "nao", robot_type: int = 0, colour: int | None = None,
            opacity: float = 1.0) -> None:
    """Create the robot's geometry under ``vis[name]``, one node per body (``vis[name][body]``)."""
    spec = robot_spec(robot_type)
    for body in spec.bodies:
        small = not body.collider
        body_colour = colour if colour is not None else DEFAULT_COLOURS["joint" if small else "body"]
        _add_body_geometry(vis, f"{name}/{body.name}", body, body_colour, opacity)


def set_body_poses(vis: meshcat.Visualizer, name: str, poses: Mapping[str, np.ndarray]) -> None:
    """Place each body: ``poses[body]`` is a 4x4 world transform of the body centre."""
    for body, pose in poses.items():
        vis[f"{name}/{body}"].set_transform(pose)


class NaoPosePainter:
    """Computes body poses from joint angles (Pinocchio FK) and sends them to meshcat.

    The robot stands with its lower sole on z = 0 (torso upright) unless a torso pose is given.
    """

    def __init__(self, robot_type: int = 0) -> None:
        self.kinematics = NaoKinematics(robot_type)
        self.bodies = [b.name for b in self.kinematics.spec.bodies]
        self._ids = [self.kinematics.frame_id(b) for b in self.bodies]

    def body_poses(self, angles_rad: Mapping[str, float] | np.ndarray | None = None,
                   torso_pose: np.ndarray | None = None) -> dict[str, np.ndarray]:
        """Body name -> 4x4 pose in the world (torso frame placed by ``torso_pose``, default: standing)."""
        kin = self.kinematics
        q = kin.configuration(angles_rad)
        pin.framesForwardKinematics(kin.model, kin.data, q)
        local = {b: kin.data.oMf[i].homogeneous.copy() for b, i in zip(self.bodies, self._ids)}
        if torso_pose is None:
            torso_pose = np.eye(4)
            torso_pose[2, 3] = kin.camera_height_m(q) - local["head"][2, 3]
        return {b: torso_pose @ m for b, m in local.items()}

    def paint(self, vis: meshcat.Visualizer, name: str, angles_rad: Mapping[str, float] | np.ndarray | None = None,
              torso_pose: np.ndarray | None = None) -> dict[str, np.ndarray]:
        poses = self.body_poses(angles_rad, torso_pose)
        set_body_poses(vis, name, poses)
        return poses


def add_ground(vis: meshcat.Visualizer, size_m: float = 1.0) -> None:
    """A thin grey slab under z = 0 so the standing height reads at a glance."""
    vis["ground"].set_object(geometry.Box([size_m, size_m, 0.002]), _material(0x70A070, 0.6))
    vis["ground"].set_transform(transformations.translation_matrix([0, 0, -0.001]))


def frame_camera(vis: meshcat.Visualizer, position_m: tuple[float, float, float] = (0.9, 0.9, 0.55),
                 target_m: tuple[float, float, float] = (0.0, 0.0, 0.25)) -> None:
    """Put meshcat's camera near the robot (its default sits metres away, where a Nao is a few pixels).

    Meshcat's camera node is y-up; ``/Cameras/default`` is translated to the target and the camera object
    offset from it, converted from our z-up frame.
    """
    vis["/Cameras/default"].set_transform(transformations.translation_matrix(list(target_m)))
    dx, dy, dz = (p - t for p, t in zip(position_m, target_m))
    vis["/Cameras/default/rotated/<object>"].set_property("position", [dx, dz, -dy])
