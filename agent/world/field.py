"""Field geometry in the world (field) frame of REFERENCE §1 and §4.1: landmarks, lines, sizes (the numbers
are agent.protocol.constants', which sim/ uses too; here the agent's views of them).

Names are global (not flipped per team); :mod:`agent.world.frames` maps them into a team's own frame.
"""

from __future__ import annotations

import math

from agent.protocol.constants import (BALL_RADIUS_M, CENTRE_CIRCLE_CHORDS, CENTRE_CIRCLE_RADIUS_M, FIELD_LENGTH_M,
                                      FIELD_WIDTH_M, GOAL_HALF_WIDTH_M, GOAL_HEIGHT_M, HALF_LENGTH_M, HALF_WIDTH_M,
                                      PENALTY_AREA_X_M)
from agent.protocol.constants import LANDMARKS as SERVER_LANDMARKS
from agent.protocol.constants import PENALTY_HALF_WIDTH_M as PENALTY_AREA_HALF_WIDTH_M

#: Landmark name -> (x, y, z) in the world frame [m]; goal posts are seen at their top (REFERENCE §4.1).
#: Flags first, as the agent has always iterated them; positions from agent.protocol.constants (shared with sim/).
LANDMARKS: dict[str, tuple[float, float, float]] = {
    name: SERVER_LANDMARKS[name] for name in ("F1L", "F2L", "F1R", "F2R", "G1L", "G2L", "G1R", "G2R")}

__all__ = ["BALL_RADIUS_M", "CENTRE_CIRCLE_CHORDS", "CENTRE_CIRCLE_RADIUS_M", "FIELD_LENGTH_M", "FIELD_LINES",
           "FIELD_WIDTH_M", "GOAL_HALF_WIDTH_M", "GOAL_HEIGHT_M", "HALF_LENGTH_M", "HALF_WIDTH_M", "LANDMARKS",
           "PENALTY_AREA_HALF_WIDTH_M", "PENALTY_AREA_X_M", "Segment", "goal_kick_drop_m"]

Segment = tuple[tuple[float, float], tuple[float, float]]


def goal_kick_drop_m(kicking_side: str) -> tuple[float, float]:
    """Where the ball of ``kicking_side``'s goal kick (``left`` or ``right``) comes back into play when nobody
    takes it (world frame) [m]: after ``DROP_BALL_TIME_S`` the referee drops it, and a ball inside a penalty
    area moves to the area's front corner on its side of the long axis (the server's SoccerRuleAspect::DropBall;
    REFERENCE §4.3's drop ball leaves the move out). A goal kick's ball lies on the axis, where y = 0 counts as
    the positive side, so it is always the corner at y = +3 m. Measured on the real server (3 v 3 against robots
    that only stand, 2026-11-27): 4 goal kicks in 6 matches, each ball back at (13.2, 3.0)."""
    return (PENALTY_AREA_X_M if kicking_side == "right" else -PENALTY_AREA_X_M), PENALTY_AREA_HALF_WIDTH_M


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
