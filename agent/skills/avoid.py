"""Obstacle avoidance for the walk skills: REFERENCE §7.6's escape angles, from the world model's beliefs.

Why: in matches, robots walking to the same ball or crossing each other's paths collided and fell. The
seed agent (Algorithm 2) walks around every other robot within 2 m: each obstacle i at bearing β_i and
distance d_i blocks the cone β_i ± α_i, α_i = asin(danger / d_i) (100° when nearer than ``danger``); a
target bearing inside the cone of an obstacle nearer than the target is blocked; the cone edges that lie
inside no other cone are the escape angles; the way point along an escape angle at the obstacle's
distance with the least detour (|way point − self| + |way point − target|) wins.

Obstacles are the teammates (their own reports or sightings) and opponents (sightings) no older than
``max_age_s``, placed in the ego frame through the believed pose. A small hysteresis keeps the side of
the previous detour while it stays nearly as short, so the walk does not swing from one side to the other.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from agent.world_model import WorldModel


@dataclass(frozen=True)
class AvoidConfig:
    """Numbers of the escape-angle avoidance (REFERENCE §7.6 unless noted)."""

    danger_m: float = 0.55
    """Clearance kept from another robot's torso centre [m] (§7.6: 0.6; two robots' bodies are ~0.3 m wide)."""
    range_m: float = 2.0
    """Obstacles farther than this are ignored [m]."""
    max_age_s: float = 1.5
    """Sightings and reports older than this are ignored [s] (a robot walks ~0.9 m in that time)."""
    keep_side_m: float = 0.3
    """The previous detour side is kept while its detour is at most this much longer [m]."""


def obstacles_ego(world: WorldModel, config: AvoidConfig) -> list[tuple[float, float]]:
    """Other robots as (forward, left) in the ego frame [m], nearer than ``range_m``."""
    pose = world.pose
    if pose is None:
        return []
    now = world.now_s
    tracked = [t for unum, t in world.teammates.items() if unum != world.unum]
    tracked += list(world.opponents.values())
    out = []
    for item in tracked:
        if item.position is None or item.age_s(now) > config.max_age_s:
            continue
        forward, left = pose.to_ego(*item.position)
        if math.hypot(forward, left) <= config.range_m:
            out.append((forward, left))
    return out


def _wrap(angle_rad: float) -> float:
    return math.remainder(angle_rad, math.tau)


def escape_bearing_deg(target: tuple[float, float], obstacles: list[tuple[float, float]], config: AvoidConfig,
                       previous_deg: float | None = None) -> float | None:
    """Bearing to walk toward [deg, ego, + = left]: the target's own if no nearer obstacle blocks it, else the
    best escape angle; None when every escape angle is blocked (surrounded: stand).

    Args:
        target: (forward, left) of the target [m].
        obstacles: (forward, left) of the obstacles [m].
        previous_deg: the bearing chosen last cycle (hysteresis), or None.
    """
    target_distance = math.hypot(*target)
    target_bearing = math.atan2(target[1], target[0])
    cones = []
    for forward, left in obstacles:
        distance = math.hypot(forward, left)
        if distance >= target_distance or distance > config.range_m:
            continue
        half = math.asin(config.danger_m / distance) if distance > config.danger_m else math.radians(100.0)
        cones.append((math.atan2(left, forward), half, distance))
    if not any(abs(_wrap(target_bearing - bearing)) < half for bearing, half, _ in cones):
        return math.degrees(target_bearing)
    choices = []
    for index, (bearing, half, distance) in enumerate(cones):
        for edge in (bearing + half, bearing - half):
            inside_other = any(abs(_wrap(edge - b)) < h - 1e-9 for j, (b, h, _) in enumerate(cones) if j != index)
            if inside_other:
                continue
            way_point = (distance * math.cos(edge), distance * math.sin(edge))
            detour = distance + math.dist(way_point, target)
            choices.append((detour, _wrap(edge)))
    if not choices:
        return None
    best = min(choices)
    if previous_deg is not None:
        previous = math.radians(previous_deg)
        same_side = [c for c in choices if abs(_wrap(c[1] - previous)) < math.radians(45.0)]
        if same_side and min(same_side)[0] <= best[0] + config.keep_side_m:
            best = min(same_side)
    return math.degrees(best[1])


class Avoider:
    """Per-skill state of the avoidance: the last bearing chosen (for the hysteresis)."""

    def __init__(self, config: AvoidConfig | None = None) -> None:
        self.config = config or AvoidConfig()
        self.previous_deg: float | None = None
        self.detouring = False
        """The last answer was an escape angle, not the target's bearing."""

    def bearing_deg(self, world: WorldModel, target: tuple[float, float]) -> float | None:
        """Bearing to walk toward the ego-frame ``target`` [deg]; None = surrounded, stand."""
        target_deg = math.degrees(math.atan2(target[1], target[0]))
        bearing = escape_bearing_deg(target, obstacles_ego(world, self.config), self.config,
                                     self.previous_deg if self.detouring else None)
        self.detouring = bearing is not None and abs(bearing - target_deg) > 1e-6
        self.previous_deg = bearing
        return bearing


__all__ = ["AvoidConfig", "Avoider", "escape_bearing_deg", "obstacles_ego"]
