"""Where to play the ball: the point of the opponent goal mouth with the clearest path from the ball.

Why: against robots that only stand, our dribbles on the real server brought the ball to 1 m from the goal
line and stopped there: the target was the goal centre, where the opponent goalkeeper stands. The goal is
2.1 m wide (REFERENCE §4); of a few aim points across it, the most central one whose path from the ball keeps
clear of every opponent seen lately wins (``goal_target``).
"""

from __future__ import annotations

import math

from agent.world_model import WorldModel

#: Opponent goal line x [m] and the aim points across its mouth (y) [m]: inside the posts (±1.05) by a ball
#: and a margin for the kick's or the push's direction error, tried from the centre outward. (With ±0.6 and
#: ±0.85, 9 of 27 real attacks that reached x = 12 m rolled out beside the post: a goal kick, 15 s lost.)
GOAL_LINE_X_M = 15.0
AIM_YS_M = (0.0, -0.45, 0.45, -0.65, 0.65)
#: An aim is taken when its path from the ball passes this far from every opponent [m] (a ball, a keeper's
#: feet either side of its centre and the push's direction error).
CLEAR_M = 0.4
#: Aim this far behind the goal line [m], so the ball is played over the line, not to it.
BEYOND_LINE_M = 0.5
#: ``over_the_line`` aims the ball's crossing of the goal line from this far before the line on [m].
CROSSING_FROM_M = 1.0
#: Opponent sightings older than this are not used [s].
OPPONENT_FRESH_S = 4.0


def _distance_to_segment(point: tuple[float, float], start: tuple[float, float], end: tuple[float, float]) -> float:
    sx, sy = end[0] - start[0], end[1] - start[1]
    length_sq = sx * sx + sy * sy
    t = 0.0 if length_sq < 1e-12 else max(0.0, min(1.0, ((point[0] - start[0]) * sx + (point[1] - start[1]) * sy)
                                                    / length_sq))
    return math.hypot(point[0] - start[0] - t * sx, point[1] - start[1] - t * sy)


def goal_target(ball: tuple[float, float], opponents: list[tuple[float, float]],
                previous_y_m: float | None = None) -> tuple[float, float]:
    """The aim point behind the opponent goal line (team frame, metres): the one the play already aims at
    (``previous_y_m``) while its path stays ``CLEAR_M`` clear of the ``opponents``, else the most central one
    that is that clear (the ball's side first), else the clearest.

    Why not "the centre unless a side is clearly clearer": as the ball came within 0.3 m of a keeper standing
    in its goal mouth, every path from the ball passed within 0.2 m of it, the centre won the tie, and the
    dribbler pushed the ball into the keeper's feet and stayed there for up to 50 s (3 v 3 against robots that
    only stand, on our simulator)."""
    def clearance(y: float) -> float:
        return min((_distance_to_segment(o, ball, (GOAL_LINE_X_M, y)) for o in opponents), default=math.inf)

    if previous_y_m is not None and previous_y_m in AIM_YS_M and clearance(previous_y_m) >= CLEAR_M:
        return GOAL_LINE_X_M + BEYOND_LINE_M, previous_y_m
    ball_side = 1.0 if ball[1] >= 0.0 else -1.0
    ordered = sorted(AIM_YS_M, key=lambda y: (abs(y), -y * ball_side))
    clearances = {y: clearance(y) for y in ordered}
    best = next((y for y in ordered if clearances[y] >= CLEAR_M), None)
    if best is None:
        best = max(ordered, key=lambda y: clearances[y])
    return GOAL_LINE_X_M + BEYOND_LINE_M, best


def over_the_line(ball: tuple[float, float], aim: tuple[float, float]) -> tuple[float, float]:
    """Where to play the ball for ``aim`` (a ``goal_target`` point) [m, team frame]: ``BEYOND_LINE_M`` past the
    goal line on the line from ``ball`` through the aim's goal-line point (``GOAL_LINE_X_M``, aim y), so the ball
    crosses the line at the aim's y from any angle. Why: the aim straight behind the line moved the crossing of
    an oblique line toward the near post: from (13.3, 1.9) toward (15.5, 0.45) it crosses at y = 0.78, 0.27 m
    inside the post, and real pushes from wide spots went 9-16 deg shallower than aimed (the walk's heading lags
    the line), out beside the post: a goal kick (real server, 3 v 3 against robots that only stand: 4 in 6
    matches). A ball nearer the line than ``CROSSING_FROM_M`` keeps ``aim``: there the line through the aim's
    goal-line point turns sideways (a ball 4 cm before the line and 0.6 m beside the aim was pushed along the line,
    not over it)."""
    dx, dy = GOAL_LINE_X_M - ball[0], aim[1] - ball[1]
    if dx < CROSSING_FROM_M:
        return aim
    distance = math.hypot(dx, dy)
    return GOAL_LINE_X_M + BEYOND_LINE_M * dx / distance, aim[1] + BEYOND_LINE_M * dy / distance


#: A set-piece kick aims at the goal, or this many degrees to either side of it, whichever path stays
#: clearest of the opponents over the kick's first ``KICK_PATH_M`` (a kick-off straight ahead on our
#: simulator stopped between the two opponents the referee had moved to x = 2.5, and stayed there 70 s).
SET_PIECE_ANGLES_DEG = (0.0, 35.0, -35.0)
KICK_PATH_M = 4.0
#: The goal direction is kept while its path is this clear [m]. (1.0 turned the kick-off of ours against ours
#: 35 deg aside: the other side's supporters wait 0.99 m from the straight path, and the line-up for the
#: turned aim circled the ball until the 15 s ran out; a robot 0.6 m beside the path does not stop a kick.)
CLEAR_PATH_M = 0.6


def set_piece_target(ball: tuple[float, float], opponents: list[tuple[float, float]]) -> tuple[float, float]:
    """Where a set-piece kick aims (team frame) [m]: toward the goal centre, or turned by one of
    ``SET_PIECE_ANGLES_DEG`` when that path is clearer of the ``opponents``."""
    to_goal = math.atan2(-ball[1], GOAL_LINE_X_M - ball[0])
    best, best_clearance = None, -1.0
    for angle_deg in SET_PIECE_ANGLES_DEG:
        heading = to_goal + math.radians(angle_deg)
        end = (ball[0] + KICK_PATH_M * math.cos(heading), ball[1] + KICK_PATH_M * math.sin(heading))
        if abs(end[1]) > 9.0:
            continue  # out over the touch line
        clearance = min((_distance_to_segment(o, ball, end) for o in opponents), default=math.inf)
        if best is None or (best_clearance < CLEAR_PATH_M and clearance > best_clearance):
            best, best_clearance = end, clearance
    return best if best is not None else (GOAL_LINE_X_M, 0.0)


def seen_opponents(world: WorldModel) -> list[tuple[float, float]]:
    """Team-frame positions of the opponents seen within ``OPPONENT_FRESH_S``."""
    now = world.now_s
    return [o.position for o in world.opponents.values()
            if o.position is not None and o.age_s(now) <= OPPONENT_FRESH_S]


__all__ = ["goal_target", "over_the_line", "seen_opponents", "set_piece_target"]
