"""Synthetic sense messages for agent tests: REFERENCE §3.5 vision geometry from a known pose, optional noise.

A standing type-0 robot (all joints 0 except the head) at a world pose; the camera pose comes from
``kinematics.fk`` so the geometry is independent of the agent's own projection code. Bytes are written by
``agent.protocol.format_sense`` (the project's one wire writer).
"""

from __future__ import annotations

import math
import random

import numpy as np

from agent.protocol import (Accelerometer, GameState, Gyro, Hear, Polar, See, Sense, TimePerceptor, VisibleLine,
                            VisibleObject, format_sense)
from agent.world.field import FIELD_LINES, LANDMARKS
from kinematics import JOINT_NAMES
from kinematics.fk import NaoKinematics

TORSO_Z_M = 0.385
_KIN = NaoKinematics(0)


def _rz(angle: float) -> np.ndarray:
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def camera_world(x: float, y: float, heading_rad: float, hj1_rad: float = 0.0, hj2_rad: float = 0.0):
    """World rotation and position of the camera of a standing robot at (x, y) facing heading_rad."""
    q = np.zeros(len(JOINT_NAMES))
    q[0], q[1] = hj1_rad, hj2_rad
    cam = _KIN.frame_pose("camera", q)
    torso_rot = _rz(heading_rad - math.pi / 2.0)  # body forward (+y) along the heading
    return torso_rot @ cam.rotation, np.array([x, y, TORSO_Z_M]) + torso_rot @ cam.position_m


def polar_of(point, cam_rot, cam_pos, rng: random.Random | None = None, calib=(0.0, 0.0, 0.0)) -> Polar | None:
    """REFERENCE §3.5: polar coordinates of a world point, None outside the 120° x 120° view."""
    rel = cam_rot.T @ (np.asarray(point, dtype=float) - cam_pos) + np.asarray(calib)
    d = float(np.linalg.norm(rel))
    theta = math.degrees(math.atan2(rel[1], rel[0])) - 90.0
    theta = (theta + 180.0) % 360.0 - 180.0
    phi = math.degrees(math.atan2(rel[2], math.hypot(rel[0], rel[1])))
    if abs(theta) > 60.0 or abs(phi) > 60.0 or d <= 0.1:
        return None
    if rng is not None:
        d += rng.gauss(0.0, 0.0965) * d / 100.0
        theta += rng.gauss(0.0, 0.1480)
        phi += rng.gauss(0.0, 0.1225)
    return Polar(round(d, 2), round(theta, 2), round(phi, 2))


def see(x: float, y: float, heading_rad: float, hj1_rad: float = 0.0, hj2_rad: float = 0.0,
        ball=(0.0, 0.0), rng: random.Random | None = None, lines: bool = True) -> See:
    """The See a standing robot gets at a world pose (landmarks, ball and clipped lines)."""
    cam_rot, cam_pos = camera_world(x, y, heading_rad, hj1_rad, hj2_rad)
    objects = []
    for name, position in LANDMARKS.items():
        polar = polar_of(position, cam_rot, cam_pos, rng)
        if polar is not None:
            objects.append(VisibleObject(name, *polar))
    if ball is not None:
        polar = polar_of((ball[0], ball[1], 0.042), cam_rot, cam_pos, rng)
        if polar is not None:
            objects.append(VisibleObject("B", *polar))
    seen_lines = []
    if lines:
        for (ax, ay), (bx, by) in FIELD_LINES:
            samples = [(ax + (bx - ax) * t, ay + (by - ay) * t, 0.0) for t in np.linspace(0.0, 1.0, 61)]
            visible = [p for p in samples if polar_of(p, cam_rot, cam_pos) is not None]
            if len(visible) >= 2:
                a = polar_of(visible[0], cam_rot, cam_pos, rng)
                b = polar_of(visible[-1], cam_rot, cam_pos, rng)
                if a is not None and b is not None:
                    seen_lines.append(VisibleLine(a, b))
    return See(tuple(objects), (), tuple(seen_lines))


def sense_bytes(now_s: float, *, see_value: See | None = None, play_mode: str = "BeforeKickOff",
                unum: int | None = None, side: str | None = None, hj1_deg: float = 0.0, hj2_deg: float = 0.0,
                hears: tuple[Hear, ...] = (), game_time_s: float = 0.0, gyro=(0.0, 0.0, 0.0)) -> bytes:
    """A whole sense message of a standing robot."""
    joints = {name: 0.0 for name in JOINT_NAMES}
    joints["hj1"], joints["hj2"] = hj1_deg, hj2_deg
    sense = Sense(TimePerceptor(now_s), GameState(unum, side, 0, 0, game_time_s, play_mode),
                  Gyro("torso", gyro), Accelerometer("torso", (0.0, 0.0, 9.81)), joints, {}, hears, see_value)
    return format_sense(sense)
