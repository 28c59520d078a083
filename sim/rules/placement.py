"""Where the referee puts robots: clearing areas, repelling, safe repositioning (REFERENCE §4.4-4.5).

The server moves players one after another and every later check sees the earlier moves, so `Placer` keeps
this cycle's torso positions current while it calls `WorldView.move_robot`. Robots are approximated by a
square footprint of `agent_half_extent_m` around the torso where the server intersects bounding rectangles.
"""

from __future__ import annotations

import math
import random
from collections.abc import Callable

from sim.rules.params import LEFT, RefereeConfig, in_box, opponent
from sim.world_api import RobotState, WorldView

Key = tuple[str, int]

# The halves used for kick-off clearing are oversized by 10 m toward the sides and ends (server comment:
# "so that no opponents sneak up from behind").
_HALF_MARGIN_M = 10.0


def half_box(side: str, config: RefereeConfig) -> tuple[float, float, float, float]:
    """The (oversized) half of the field that belongs to ``side``, as (x_min, x_max, y_min, y_max) [m]."""
    if side == LEFT:
        return (-config.half_length_m - _HALF_MARGIN_M, 0.0, -config.half_width_m - _HALF_MARGIN_M,
                config.half_width_m + _HALF_MARGIN_M)
    return (0.0, config.half_length_m + _HALF_MARGIN_M, -config.half_width_m - _HALF_MARGIN_M,
            config.half_width_m + _HALF_MARGIN_M)


def overlaps_box(box: tuple[float, float, float, float], x: float, y: float, half_extent: float) -> bool:
    """Whether a robot's square footprint of ``half_extent`` [m] around (x, y) touches ``box`` (its x edges in
    either order, as a clearing box may come)."""
    lo_x, hi_x = (box[0], box[1]) if box[0] <= box[1] else (box[1], box[0])
    e = half_extent
    return lo_x <= x + e and x - e <= hi_x and box[2] <= y + e and y - e <= box[3]


def in_opponent_half(robots: list[RobotState], config: RefereeConfig) -> bool:
    """Whether any robot touches the other side's half: the only case where clearing before kick-off moves
    anyone. Asked first because almost no cycle before kick-off moves a robot, and building the `Placer`
    (with its shuffles) every such cycle cost a twentieth of a one-robot simulation's time."""
    e = config.agent_half_extent_m
    return any(overlaps_box(half_box(opponent(r.team), config), r.torso_pos_m[0], r.torso_pos_m[1], e)
               for r in robots)


class Placer:
    """Moves robots for one referee cycle.

    Args:
        world: the world to move robots in.
        robots: this cycle's robot states.
        ball_xy: ball position [m] used by the avoid-ball test.
        config: rule parameters.
        rng: the referee's random source (the server shuffles players before clearing).
        on_move: called with (team, unum) whenever a robot is moved (charging immunity).
    """

    def __init__(self, world: WorldView, robots: list[RobotState], ball_xy: tuple[float, float],
                 config: RefereeConfig, rng: random.Random, on_move: Callable[[str, int], None]) -> None:
        self.world = world
        self.config = config
        self.rng = rng
        self.ball_xy = ball_xy
        self.on_move = on_move
        self.pos: dict[Key, tuple[float, float]] = {(r.team, r.unum): (r.torso_pos_m[0], r.torso_pos_m[1])
                                                    for r in robots}
        self._inside_own_area: set[Key] | None = None

    def inside_own_area(self) -> set[Key]:
        """Players inside their own penalty area at the start of the cycle (worked out on the first move,
        before it changes a position: most cycles move nobody)."""
        if self._inside_own_area is None:
            config = self.config
            self._inside_own_area = {key for key, (x, y) in self.pos.items()
                                     if in_box(x, y, config.penalty_area(key[0]))}
        return self._inside_own_area

    # ---- queries -------------------------------------------------------------------------------------
    def team(self, side: str) -> list[Key]:
        """Keys of one side's robots in random order (the server shuffles before each pass)."""
        keys = [key for key in self.pos if key[0] == side]
        self.rng.shuffle(keys)
        return keys

    def rect(self, key: Key) -> tuple[float, float, float, float]:
        x, y = self.pos[key]
        e = self.config.agent_half_extent_m
        return (x - e, x + e, y - e, y + e)

    # ---- moves ---------------------------------------------------------------------------------------
    def move(self, key: Key, x: float, y: float, *, safe: bool = True, avoid_ball: bool = True,
             z_m: float | None = None) -> tuple[float, float]:
        """Move a robot, first searching a free spot when ``safe``; returns the spot. Without ``z_m`` the robot
        is translated as it stands (SimSpark's MoveAgent: posture, orientation and height kept); with it, put
        upright at that height (heading kept)."""
        self.inside_own_area()
        if safe:
            x, y = self.safe_position(key, x, y, avoid_ball)
        if z_m is None:
            self.world.shift_robot(key[0], key[1], x, y)
        else:
            self.world.move_robot(key[0], key[1], x, y, None, z_m)
        self.pos[key] = (x, y)
        self.on_move(*key)
        return (x, y)

    def clear_circle(self, centre: tuple[float, float], radius: float, side: str) -> None:
        """Players of ``side`` whose footprint touches the circle go FreeKickMoveDist toward their own goal."""
        dist = self.config.free_kick_move_dist_m
        half = self.config.half_length_m
        for key in self.team(side):
            if not _circle_hits_rect(centre, radius, self.rect(key)):
                continue
            x, y = self.pos[key]
            if side == LEFT:
                if centre[0] - dist < -half:
                    y = centre[1] + dist if centre[1] < 0 else centre[1] - dist
                else:
                    x = centre[0] - dist
            else:
                if centre[0] + dist > half:
                    y = centre[1] + dist if centre[1] < 0 else centre[1] - dist
                else:
                    x = centre[0] + dist
            self.move(key, x, y)

    def clear_box(self, box: tuple[float, float, float, float], side: str) -> None:
        """Players of ``side`` overlapping ``box`` go FreeKickMoveDist beyond its edge toward their goal."""
        dist = self.config.free_kick_move_dist_m
        e = self.config.agent_half_extent_m
        pos = self.pos
        for key in self.team(side):
            x, y = pos[key]
            if not overlaps_box(box, x, y, e):
                continue
            x = box[0] - dist if side == LEFT else box[1] + dist
            self.move(key, x, y)

    def half(self, side: str) -> tuple[float, float, float, float]:
        """The (oversized) half of the field that belongs to ``side``."""
        return half_box(side, self.config)

    def clear_before_kick_off(self, kicking: str) -> None:
        """KickOff/Goal clearing: opponents out of the kicking half and the circle, kickers into their half
        unless wholly inside the centre circle (REFERENCE §4.4)."""
        c = self.config
        other = opponent(kicking)
        self.clear_box(self.half(kicking), other)
        self.clear_circle((0.0, 0.0), c.free_kick_distance_m, other)
        box = self.half(other)
        r2 = c.free_kick_distance_m ** 2
        for key in self.team(kicking):
            rect = self.rect(key)
            if not _rects_overlap(box, rect):
                continue
            corners = ((rect[0], rect[2]), (rect[1], rect[3]), (rect[0], rect[3]), (rect[1], rect[2]))
            if all(cx * cx + cy * cy < r2 for cx, cy in corners):
                continue
            x, y = self.pos[key]
            x = box[0] - c.free_kick_move_dist_m if kicking == LEFT else box[1] + c.free_kick_move_dist_m
            self.move(key, x, y)

    def repel(self, centre: tuple[float, float], radius: float, side: str, pad: float,
              avoid_ball: bool = True) -> None:
        """Players of ``side`` closer than ``radius`` to ``centre`` are pushed radially to radius + pad."""
        for key in self.team(side):
            x, y = self.pos[key]
            dx, dy = x - centre[0], y - centre[1]
            dist = math.hypot(dx, dy)
            if dist >= radius:
                continue
            if dist < 1e-9:
                dx, dy, dist = 1.0, 0.0, 1.0
            scale = (radius + pad) / dist
            self.move(key, centre[0] + dx * scale, centre[1] + dy * scale, avoid_ball=avoid_ball)

    # ---- safe reposition -----------------------------------------------------------------------------
    def safe_position(self, key: Key, x: float, y: float, avoid_ball: bool) -> tuple[float, float]:
        """A spot near (x, y) clear of goals, other robots and (optionally) the ball.

        Candidates step AgentRadius away in x and y, nearest to the robot's current position first, at most
        MaxNumSafeRepositionAttempts; if none is clear the requested spot is used (as the server does).
        """
        c = self.config
        current = self.pos[key]
        target = self._keep_out_of_full_area(key, current, (x, y))
        queue: list[tuple[float, float]] = [target]
        seen: set[tuple[int, int]] = set()
        for _ in range(max(1, c.max_safe_reposition_attempts)):
            if not queue:
                break
            candidate = queue.pop(0)
            if self._is_safe(key, candidate, avoid_ball):
                return candidate
            for dx, dy in ((c.agent_radius_m, 0.0), (-c.agent_radius_m, 0.0), (0.0, c.agent_radius_m),
                           (0.0, -c.agent_radius_m)):
                nxt = (candidate[0] + dx, candidate[1] + dy)
                cell = (round(nxt[0] / (c.agent_radius_m / 2.0)), round(nxt[1] / (c.agent_radius_m / 2.0)))
                if cell in seen or abs(nxt[0]) > c.half_length_m + 1.0 or abs(nxt[1]) > c.half_width_m + 1.0:
                    continue
                seen.add(cell)
                nxt = self._keep_out_of_full_area(key, current, nxt)
                queue.append(nxt)
            queue.sort(key=lambda p: math.hypot(p[0] - current[0], p[1] - current[1]))
        return (x, y)

    def _is_safe(self, key: Key, spot: tuple[float, float], avoid_ball: bool) -> bool:
        c = self.config
        if abs(spot[0]) > c.half_length_m and abs(spot[1]) < c.goal_width_m / 2.0 + c.agent_radius_m:
            return False
        if avoid_ball and math.hypot(spot[0] - self.ball_xy[0], spot[1] - self.ball_xy[1]) < max(
                2.0 * c.agent_radius_m, c.pass_mode_min_opp_ball_dist_m):
            return False
        return not any(other != key and _circle_hits_rect(spot, c.agent_radius_m, self.rect(other))
                       for other in self.pos)

    def _keep_out_of_full_area(self, key: Key, current: tuple[float, float],
                               spot: tuple[float, float]) -> tuple[float, float]:
        """Do not move a player into its own penalty area when that area already holds the maximum."""
        c = self.config
        side = key[0]
        area = c.penalty_area(side)
        inside = sum(1 for other, (ox, oy) in self.pos.items()
                     if other[0] == side and in_box(ox, oy, area))
        if key in self.inside_own_area() or inside < c.max_players_inside_own_area:
            return spot
        pad = c.agent_radius_m
        x, y = spot
        if not (area[0] - pad < x < area[1] + pad and area[2] - pad < y < area[3] + pad):
            return spot
        toward_field = (x > current[0]) if side == LEFT else (x < current[0])
        if toward_field:
            return (area[1] + pad, y) if side == LEFT else (area[0] - pad, y)
        if y > current[1] or (y == current[1] and y < 0):
            return (x, area[3] + pad)
        return (x, area[2] - pad)


def outside_position(side: str, unum: int, ball_y: float, config: RefereeConfig) -> tuple[float, float]:
    """Incapable/charging enforcement spot: (-+0.6*(7-unum), +-(FieldWidth/2 + 0.5)) away from the ball."""
    x_factor = -0.6 if side == LEFT else 0.6
    y_sign = 1.0 if ball_y < 0 else -1.0
    return (x_factor * (7 - unum), (config.half_width_m + 0.5) * y_sign)


def illegal_defence_position(side: str, x: float, y: float, config: RefereeConfig) -> tuple[float, float]:
    """Move just outside the nearest edge of the own penalty area (+AgentRadius), never into the goal."""
    area = config.penalty_area(side)
    pad = config.agent_radius_m
    target_x = area[0] - pad if abs(area[0] - x) < abs(area[1] - x) else area[1] + pad
    target_y = area[2] - pad if abs(area[2] - y) < abs(area[3] - y) else area[3] + pad
    if abs(target_y - y) < abs(target_x - x):
        y = target_y
    else:
        x = target_x
    if abs(x) > config.half_length_m and abs(y) < config.goal_width_m / 2.0 + pad:
        y = (config.goal_width_m / 2.0 + pad + 0.001) * (-1.0 if y < 0 else 1.0)
    return (x, y)


def _circle_hits_rect(centre: tuple[float, float], radius: float, rect: tuple[float, float, float, float]) -> bool:
    nearest_x = min(max(centre[0], rect[0]), rect[1])
    nearest_y = min(max(centre[1], rect[2]), rect[3])
    return (nearest_x - centre[0]) ** 2 + (nearest_y - centre[1]) ** 2 <= radius * radius


def _rects_overlap(a: tuple[float, float, float, float], b: tuple[float, float, float, float]) -> bool:
    lo_x, hi_x = min(a[0], a[1]), max(a[0], a[1])
    return lo_x <= b[1] and b[0] <= hi_x and a[2] <= b[3] and b[2] <= a[3]
