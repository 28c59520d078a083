"""Where the ball is for the rules: on the field, in a goal (REFERENCE §4.1)."""

from __future__ import annotations

import math

from sim.rules.params import LEFT, RIGHT, RefereeConfig

Vec3 = tuple[float, float, float]

# The goal's recorder box behind the line (REFERENCE §4.1: 0.516 x 2.016 x 0.8) [m].
GOAL_RECORDER_DEPTH_M = 0.516
GOAL_RECORDER_HALF_WIDTH_M = 1.008


def ball_on_field(position: Vec3, config: RefereeConfig) -> bool:
    """The server's test: |x| < 15.043 and |y| < 10.043 (half size + ball radius + 1 mm)."""
    c = config
    return (abs(position[0]) < c.half_length_m + c.ball_radius_m + 0.001
            and abs(position[1]) < c.half_width_m + c.ball_radius_m + 0.001)


def goal_of(position: Vec3, velocity: Vec3, config: RefereeConfig) -> str | None:
    """Whose goal holds the ball ("left"/"right"), or None.

    First the goal's recorder box behind the line (touched by the ball sphere), then the server's analytic
    fallback: the ball is wholly behind the line, was inside the field a second ago (|x - vx| <= 15.042),
    and its path crosses the line between the posts and below the bar. (The server extrapolates the left
    goal's crossing forward by mistake; it is traced back here for both goals, a sub-centimetre change.)
    """
    c = config
    x, y, z = position
    r = c.ball_radius_m
    near_x, far_x = c.goal_ball_line_x_m, c.goal_ball_line_x_m + GOAL_RECORDER_DEPTH_M
    dx = max(near_x - abs(x), 0.0, abs(x) - far_x)
    dy = max(abs(y) - GOAL_RECORDER_HALF_WIDTH_M, 0.0)
    dz = max(-z, 0.0, z - c.goal_height_m)
    if dx * dx + dy * dy + dz * dz <= r * r:
        return LEFT if x < 0 else RIGHT
    beyond = abs(x) - c.goal_ball_line_x_m
    if beyond < 0:
        return None
    vx, vy, vz = velocity
    if abs(x - vx) > c.goal_ball_line_x_m:
        return None
    speed = math.sqrt(vx * vx + vy * vy + vz * vz)
    if speed <= 0.0 or abs(vx) < 1e-9:
        return None
    back = beyond / abs(vx / speed)
    cross_y = y - vy / speed * back
    cross_z = z - vz / speed * back
    if abs(cross_y) < c.goal_width_m / 2.0 and cross_z < c.goal_height_m:
        return LEFT if x < 0 else RIGHT
    return None
