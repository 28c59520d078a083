"""The soccer field of REFERENCE §4.1: dimensions, landmarks, the 21 field lines, goal and wall colliders.

Everything here is in the world (field) frame, metres: origin at the centre spot, x toward the right team's
goal, y left, z up. The line list is what vision clips and reports; lines have no collision geometry.
The dimensions, ball and landmarks are agent.protocol.constants' (the agent's too); the walls are sim/'s.
"""

from __future__ import annotations

import math

import mujoco
import numpy as np

from agent.protocol.constants import (AGENT_RADIUS_M, BALL_MASS_KG, BALL_RADIUS_M, CENTRE_CIRCLE_CHORDS,
                                      CENTRE_CIRCLE_RADIUS_M, FIELD_LENGTH_M, FIELD_WIDTH_M, GOAL_DEPTH_M,
                                      GOAL_HEIGHT_M, GOAL_WIDTH_M, HALF_LENGTH_M, HALF_WIDTH_M, LANDMARKS,
                                      PENALTY_DEPTH_M, PENALTY_HALF_WIDTH_M)

# REFERENCE §4.1: collision walls, 1 m thick, centred at x = ±24.99 and y = ±25; height = FieldHeight 40 m.
WALL_X_M = 24.99
WALL_Y_M = 25.0
WALL_THICKNESS_M = 1.0
WALL_HEIGHT_M = 40.0

__all__ = ["AGENT_RADIUS_M", "BALL_MASS_KG", "BALL_RADIUS_M", "CENTRE_CIRCLE_CHORDS", "CENTRE_CIRCLE_RADIUS_M",
           "FIELD_LENGTH_M", "FIELD_LINES_M", "FIELD_WIDTH_M", "GOAL_DEPTH_M", "GOAL_HEIGHT_M", "GOAL_WIDTH_M",
           "HALF_LENGTH_M", "HALF_WIDTH_M", "LANDMARKS", "LANDMARK_NAMES", "LANDMARK_POSITIONS_M", "PENALTY_DEPTH_M",
           "PENALTY_HALF_WIDTH_M", "add_static_geometry", "field_lines", "goal_boxes", "wall_boxes"]

LANDMARK_NAMES: tuple[str, ...] = tuple(LANDMARKS)
LANDMARK_POSITIONS_M = np.array(list(LANDMARKS.values()))


def _centre_circle_chords() -> list[tuple[tuple[float, float], tuple[float, float]]]:
    points = [(CENTRE_CIRCLE_RADIUS_M * math.cos(2 * math.pi * k / CENTRE_CIRCLE_CHORDS),
               CENTRE_CIRCLE_RADIUS_M * math.sin(2 * math.pi * k / CENTRE_CIRCLE_CHORDS))
              for k in range(CENTRE_CIRCLE_CHORDS)]
    return [(points[k], points[(k + 1) % CENTRE_CIRCLE_CHORDS]) for k in range(CENTRE_CIRCLE_CHORDS)]


def field_lines() -> np.ndarray:
    """The 21 field-line segments (REFERENCE §4.1) in the server's order and direction, shape (21, 2, 3).

    Order and endpoint direction were read off the recorded 0.7.3 vision (tests/sim/test_vision.py fits
    the camera pose to the landmarks and matches every reported line): halfway line (y -10 -> 10), goal
    lines x = +15 then x = -15 (y -10 -> 10), touch lines y = +10 then y = -10 (x +15 -> -15), the right
    penalty area (front line y +3 -> -3, then the sides y = +3 and y = -3, from x = 13.2 to the goal line),
    the left one likewise (which area comes first is not in the samples: unverified), then the centre
    circle as 10 chords counter-clockwise from (2, 0). Endpoints are derived from the dimensions.
    """
    hl, hw, px = HALF_LENGTH_M, HALF_WIDTH_M, HALF_LENGTH_M - PENALTY_DEPTH_M
    py = PENALTY_HALF_WIDTH_M
    segments: list[tuple[tuple[float, float], tuple[float, float]]] = [
        ((0.0, -hw), (0.0, hw)),
        ((hl, -hw), (hl, hw)), ((-hl, -hw), (-hl, hw)),
        ((hl, hw), (-hl, hw)), ((hl, -hw), (-hl, -hw)),
        ((px, py), (px, -py)), ((px, py), (hl, py)), ((px, -py), (hl, -py)),
        ((-px, py), (-px, -py)), ((-px, py), (-hl, py)), ((-px, -py), (-hl, -py)),
    ]
    segments += _centre_circle_chords()
    lines = np.zeros((len(segments), 2, 3))
    for i, (a, b) in enumerate(segments):
        lines[i, 0, :2] = a
        lines[i, 1, :2] = b
    return lines


FIELD_LINES_M = field_lines()


def goal_boxes(side: int) -> list[tuple[str, tuple[float, float, float], tuple[float, float, float]]]:
    """Collision boxes of one goal (REFERENCE §4.1): (name, centre, full size), world frame.

    Args:
        side: -1 for the left goal (x < 0), +1 for the right goal. The goal's local x points into the field,
            so the back wall (local x -0.28) lies behind the goal line on both sides.
    """
    cx, cz = side * (HALF_LENGTH_M + 0.3), 0.4
    tag = "left" if side < 0 else "right"
    back_x = cx + side * 0.28
    return [
        (f"goal_{tag}_post1", (cx, 1.07, cz), (0.6, 0.04, 0.8)),
        (f"goal_{tag}_post2", (cx, -1.07, cz), (0.6, 0.04, 0.8)),
        (f"goal_{tag}_back", (back_x, 0.0, cz), (0.04, 2.1, 0.8)),
        (f"goal_{tag}_roof", (cx, 0.0, cz + 0.42), (0.6, 2.18, 0.04)),
    ]


def wall_boxes() -> list[tuple[str, tuple[float, float, float], tuple[float, float, float]]]:
    """The four collision walls around the field (REFERENCE §4.1): (name, centre, full size)."""
    h = WALL_HEIGHT_M
    long_side = 2 * WALL_Y_M + WALL_THICKNESS_M
    short_side = 2 * WALL_X_M + WALL_THICKNESS_M
    return [
        ("wall_x_neg", (-WALL_X_M, 0.0, h / 2), (WALL_THICKNESS_M, long_side, h)),
        ("wall_x_pos", (WALL_X_M, 0.0, h / 2), (WALL_THICKNESS_M, long_side, h)),
        ("wall_y_neg", (0.0, -WALL_Y_M, h / 2), (short_side, WALL_THICKNESS_M, h)),
        ("wall_y_pos", (0.0, WALL_Y_M, h / 2), (short_side, WALL_THICKNESS_M, h)),
    ]


def add_static_geometry(spec: mujoco.MjSpec) -> list[mujoco.MjsGeom]:
    """Add the ground plane, goals and walls to ``spec``'s world body; returns the geoms (for contact setup).

    The plane is infinite for contacts (ODE's field plane is a plane too); its size only sets the display.
    """
    world = spec.worldbody
    geoms = [world.add_geom(name="field", type=mujoco.mjtGeom.mjGEOM_PLANE,
                            size=[WALL_X_M, WALL_Y_M, 0.1], rgba=[0.2, 0.6, 0.2, 1.0])]
    boxes = goal_boxes(-1) + goal_boxes(1) + wall_boxes()
    for name, centre, size in boxes:
        rgba = [0.9, 0.9, 0.9, 1.0] if name.startswith("goal") else [0.5, 0.5, 0.5, 0.0]
        geoms.append(world.add_geom(name=name, type=mujoco.mjtGeom.mjGEOM_BOX, pos=list(centre),
                                    size=[s / 2.0 for s in size], rgba=rgba))
    return geoms
