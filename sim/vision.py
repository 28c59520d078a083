"""SimSpark's RestrictedVisionPerceptor (REFERENCE §3.5): what each robot's camera sees, as polar data.

One call handles every robot that sees this cycle at once (numpy over observers x points), because
vision is the most expensive percept: ~40 objects and 21 lines per frame.

Geometry, per observer: rel = R_headᵀ (p - p_cam) + calibration error (one draw per connection);
d = |rel|; θ = atan2(rel.y, rel.x) - 90° (0 ahead, positive to the left); φ = atan2(rel.z, |rel.xy|).
An object is seen when d > 0.1 m and |θ|, |φ| <= 60°. Lines are clipped to the view pyramid (the four
planes |x| <= tan 60° · y and |z| <= tan 60° · y of the head frame, y ahead) and both endpoints reported.
Noise per reported point: d += N(0, 0.0965) · d / 100, θ += N(0, 0.1480°), φ += N(0, 0.1225°).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import partial

import numpy as np

from agent.protocol.perceptors import Polar, See, VisibleLine, VisibleObject, VisiblePlayer
from sim.field import FIELD_LINES_M, LANDMARK_NAMES, LANDMARK_POSITIONS_M

HALF_FOV_DEG = 60.0
MIN_DISTANCE_M = 0.1
CALIBRATION_ERROR_M = 0.005
SIGMA_DISTANCE_PERCENT = 0.0965
SIGMA_THETA_DEG = 0.1480
SIGMA_PHI_DEG = 0.1225
_TAN_HALF_FOV = math.tan(math.radians(HALF_FOV_DEG))
_SIGMAS = np.array([0.0, SIGMA_THETA_DEG, SIGMA_PHI_DEG])
_PARTS_PER_PLAYER = 5
_new_polar = partial(tuple.__new__, Polar)
_new_object = partial(tuple.__new__, VisibleObject)
_new_line = partial(tuple.__new__, VisibleLine)
_LINE_POINTS = FIELD_LINES_M.reshape(-1, 3)
# Inward normals of the view pyramid's planes in the head frame (x right, y ahead, z up).
_PLANES = np.array([[-1.0, _TAN_HALF_FOV, 0.0], [1.0, _TAN_HALF_FOV, 0.0],
                    [0.0, _TAN_HALF_FOV, -1.0], [0.0, _TAN_HALF_FOV, 1.0]])


@dataclass(frozen=True)
class VisionConfig:
    """Switches of the vision model (defaults = the standard server)."""

    noise: bool = True
    """Per-observation noise on d, θ, φ."""
    calibration: bool = True
    """The per-connection calibration offset (drawn by the caller; this only switches its use)."""
    lines: bool = True
    """Report field lines."""


@dataclass(frozen=True)
class Observer:
    """One camera this cycle.

    position_m: camera (head centre) in the world; rotation: head frame axes as columns (3x3);
    calibration_m: the connection's calibration error (head frame); team: own team name; unum: own number.
    """

    position_m: np.ndarray
    rotation: np.ndarray
    calibration_m: np.ndarray
    team: str
    unum: int


@dataclass(frozen=True)
class PlayerParts:
    """A robot as others see it: team name, number, and its 5 visible parts' world positions (5 x 3)."""

    team: str
    unum: int
    parts_m: np.ndarray
    part_names: tuple[str, ...]


def polar(rel: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Head-frame points (..., 3) -> (d [m], θ [deg], φ [deg]) with θ in (-180, 180]."""
    x, y, z = rel[..., 0], rel[..., 1], rel[..., 2]
    distance = np.sqrt(x * x + y * y + z * z)
    theta = np.degrees(np.arctan2(y, x)) - 90.0
    theta = np.where(theta <= -180.0, theta + 360.0, theta)
    phi = np.degrees(np.arctan2(z, np.sqrt(x * x + y * y)))
    return distance, theta, phi


def see(observers: list[Observer], ball_m: np.ndarray, players: list[PlayerParts],
        rng: np.random.Generator, config: VisionConfig = VisionConfig()) -> list[See]:
    """The vision frame of each observer (same order), players and lines in the server's order.

    Args:
        observers: the cameras that see this cycle.
        ball_m: ball centre in the world.
        players: every robot with a team, in connection order (an observer's own entry shows its own
            arms and feet; its own head is dropped by the 0.1 m rule).
        rng: the world's generator (one draw for all observers, in order, so runs are reproducible).
        config: model switches.
    """
    if not observers:
        return []
    count = len(observers)
    part_points = np.vstack([p.parts_m for p in players]) if players else np.zeros((0, 3))
    # rows: landmarks, ball, players' parts, then the field-line end points (static, cached)
    points = np.vstack([LANDMARK_POSITIONS_M, ball_m[None, :], part_points] + ([_LINE_POINTS] if config.lines else []))
    cams = np.stack([o.position_m for o in observers])                          # (K, 3)
    rots = np.stack([o.rotation for o in observers])                            # (K, 3, 3)
    rel = (points[None, :, :] - cams[:, None, :]) @ rots                        # R_headᵀ (p - c), (K, P, 3)
    if config.calibration:
        rel += np.stack([o.calibration_m for o in observers])[:, None, :]
    object_count = LANDMARK_POSITIONS_M.shape[0] + 1 + part_points.shape[0]
    rel_objects = rel[:, :object_count]
    distance, theta, phi = polar(rel_objects)
    visible = (distance > MIN_DISTANCE_M) & (np.abs(theta) <= HALF_FOV_DEG) & (np.abs(phi) <= HALF_FOV_DEG)
    seen_k, seen_p = np.nonzero(visible)
    values = np.stack([distance[seen_k, seen_p], theta[seen_k, seen_p], phi[seen_k, seen_p]], axis=1)
    if config.lines:
        clipped, line_visible = _clip_to_pyramid(rel[:, object_count:].reshape(count, -1, 2, 3))
        line_k, line_i = np.nonzero(line_visible)
        ends = clipped[line_k, line_i].reshape(-1, 3)                           # 2 rows per line
        line_values = np.stack(polar(ends), axis=1)
    else:
        line_k = np.zeros(0, dtype=np.intp)
        line_values = np.zeros((0, 3))
    if config.noise:
        values = _noisy(values, rng)
        line_values = _noisy(line_values, rng)
    names = LANDMARK_NAMES + ("B",)
    object_rows = np.searchsorted(seen_k, np.arange(count + 1))
    line_rows = np.searchsorted(line_k, np.arange(count + 1))
    seen_list, value_list, line_list = seen_p.tolist(), values.tolist(), line_values.tolist()
    return [_frame(seen_list[object_rows[k]:object_rows[k + 1]], value_list[object_rows[k]:object_rows[k + 1]],
                   line_list[2 * line_rows[k]:2 * line_rows[k + 1]], names, players) for k in range(count)]


def _noisy(values: np.ndarray, rng: np.random.Generator) -> np.ndarray:
    """Per-point noise on (d, θ, φ) rows (REFERENCE §3.5)."""
    draws = rng.standard_normal(values.shape)
    out = values + draws * _SIGMAS
    out[:, 0] = values[:, 0] * (1.0 + draws[:, 0] * (SIGMA_DISTANCE_PERCENT / 100.0))
    return out


def _clip_to_pyramid(segments: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Clip head-frame segments (K, L, 2, 3) to the view pyramid; returns the clipped ends and a mask."""
    start, end = segments[..., 0, :], segments[..., 1, :]
    direction = end - start
    at_start = start @ _PLANES.T                     # (K, L, 4): signed distance of the start to each plane
    along = direction @ _PLANES.T                    # rate of change along the segment
    low = np.zeros(at_start.shape[:2])
    high = np.ones(at_start.shape[:2])
    with np.errstate(divide="ignore", invalid="ignore"):
        t_cross = -at_start / along
    entering = along > 0
    leaving = along < 0
    low = np.maximum(low, np.where(entering, t_cross, -np.inf).max(axis=2))
    high = np.minimum(high, np.where(leaving, t_cross, np.inf).min(axis=2))
    parallel_out = ((along == 0) & (at_start < 0)).any(axis=2)
    visible = (low < high) & ~parallel_out
    clipped = np.stack([start + low[..., None] * direction, start + high[..., None] * direction], axis=2)
    return clipped, visible


def _frame(seen: list[int], values: list[list[float]], line_values: list[list[float]],
           names: tuple[str, ...], players: list[PlayerParts]) -> See:
    fixed_count = len(names)
    objects = []
    parts: dict[int, dict[str, Polar]] = {}
    new_polar, new_object = _new_polar, _new_object
    for point, value in zip(seen, values):
        if point < fixed_count:
            objects.append(new_object((names[point], *value)))
        else:
            owner, part = divmod(point - fixed_count, _PARTS_PER_PLAYER)
            parts.setdefault(owner, {})[players[owner].part_names[part]] = new_polar(value)
    seen_players = tuple(VisiblePlayer(players[owner].team, players[owner].unum, parts[owner])
                         for owner in sorted(parts))
    ends = list(map(new_polar, line_values))
    lines = tuple(map(_new_line, zip(ends[0::2], ends[1::2])))
    return See(tuple(objects), seen_players, lines)
