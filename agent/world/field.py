"""Field geometry in the world (field) frame of REFERENCE §1 and §4.1: landmarks, lines, sizes.

Names are global (not flipped per team); :mod:`agent.world.frames` maps them into a team's own frame.
"""

from __future__ import annotations

import math

FIELD_LENGTH_M = 30.0
FIELD_WIDTH_M = 20.0
HALF_LENGTH_M = FIELD_LENGTH_M / 2.0
HALF_WIDTH_M = FIELD_WIDTH_M / 2.0
GOAL_HALF_WIDTH_M = 1.05
GOAL_HEIGHT_M = 0.8
PENALTY_AREA_X_M = 13.2
PENALTY_AREA_HALF_WIDTH_M = 3.0
CENTRE_CIRCLE_RADIUS_M = 2.0
CENTRE_CIRCLE_CHORDS = 10
BALL_RADIUS_M = 0.042

#: Landmark name -> (x, y, z) in the world frame [m]; goal posts are seen at their top (REFERENCE §4.1).
LANDMARKS: dict[str, tuple[float, float, float]] = {
    "F1L": (-15.0, 10.0, 0.0),
    "F2L": (-15.0, -10.0, 0.0),
    "F1R": (15.0, 10.0, 0.0),
    "F2R": (15.0, -10.0, 0.0),
    "G1L": (-15.0, GOAL_HALF_WIDTH_M, GOAL_HEIGHT_M),
    "G2L": (-15.0, -GOAL_HALF_WIDTH_M, GOAL_HEIGHT_M),
    "G1R": (15.0, GOAL_HALF_WIDTH_M, GOAL_HEIGHT_M),
    "G2R": (15.0, -GOAL_HALF_WIDTH_M, GOAL_HEIGHT_M),
}

Segment = tuple[tuple[float, float], tuple[float, float]]


def _field_lines() -> tuple[Segment, ...]:
    """The 21 field lines of REFERENCE §4.1 (endpoints derived from the dimensions), world frame, z = 0."""
    hx, hy, px, py = HALF_LENGTH_M, HALF_WIDTH_M, PENALTY_AREA_X_M, PENALTY_AREA_HALF_WIDTH_M
    lines: list[Segment] = [
        ((-hx, hy), (hx, hy)), ((-hx, -hy), (hx, -hy)),  # touch lines
        ((-hx, -hy), (-hx, hy)), ((hx, -hy), (hx, hy)),  # goal lines
        ((0.0, -hy), (0.0, hy)),  # halfway line
    ]
    for sign in (-1.0, 1.0):
        lines.append(((sign * px, -py), (sign * px, py)))
        lines.append(((sign * px, py), (sign * hx, py)))
        lines.append(((sign * px, -py), (sign * hx, -py)))
    step = 2.0 * math.pi / CENTRE_CIRCLE_CHORDS
    r = CENTRE_CIRCLE_RADIUS_M
    for i in range(CENTRE_CIRCLE_CHORDS):
        a, b = i * step, (i + 1) * step
        lines.append(((r * math.cos(a), r * math.sin(a)), (r * math.cos(b), r * math.sin(b))))
    return tuple(lines)


FIELD_LINES: tuple[Segment, ...] = _field_lines()
