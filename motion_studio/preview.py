"""Builds the meshcat preview of one pose: served on loopback, or written as a standalone HTML file."""

from __future__ import annotations

from pathlib import Path

import meshcat

from kinematics.meshcat_server import loopback_visualizer
from kinematics.meshcat_view import NaoPosePainter, add_ground, add_nao, frame_camera
from motion_studio.pose_input import parse_joint_assignments, read_pose_file


def pose_scene(vis: meshcat.Visualizer, robot_type: int, angles_rad: dict[str, float]) -> None:
    add_ground(vis)
    frame_camera(vis)
    add_nao(vis, "nao", robot_type)
    NaoPosePainter(robot_type).paint(vis, "nao", angles_rad)


def preview_pose(robot_type: int, assignments: list[str], pose_file: Path | None, html: Path | None) -> str:
    """Show a pose; returns the viewer URL, or the HTML path when ``html`` is given.

    Raises:
        SpecError: bad robot type, joint name or angle (before anything is started).
    """
    angles = read_pose_file(pose_file, robot_type) if pose_file else {}
    angles.update(parse_joint_assignments(assignments, robot_type))
    vis = loopback_visualizer()  # meshcat's web and ZMQ ports on 127.0.0.1; the child ends with this process
    pose_scene(vis, robot_type, angles)
    if html is None:
        return vis.url()
    try:
        html.write_text(vis.static_html())
    finally:
        vis.close()
    return str(html)
