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
    """A robot as others see it: team name, number, and its visible parts' world positions (5 x 3)."""

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
        rng: the world's generator (noise is drawn per observer in order, so runs are reproducible).
        config: model switches.
    """
    if not observers:
        return []
    count = len(observers)
    fixed = np.vstack([LANDMARK_POSITIONS_M, ball_m[None, :]])
    part_points = np.vstack([p.parts_m for p in players]) if players else np.zeros((0, 3))
    points = np.vstack([fixed, part_points])                                    # (P, 3)
    cams = np.stack([o.position_m for o in observers])                          # (K, 3)
    rots = np.stack([o.rotation for o in observers])                            # (K, 3, 3)
    calib = np.stack([o.calibration_m for o in observers]) if config.calibration else np.zeros((count, 3))
    rel = np.einsum("kji,kpj->kpi", rots, points[None, :, :] - cams[:, None, :]) + calib[:, None, :]
    distance, theta, phi = polar(rel)
    visible = (distance > MIN_DISTANCE_M) & (np.abs(theta) <= HALF_FOV_DEG) & (np.abs(phi) <= HALF_FOV_DEG)
    if config.lines:
        segments = FIELD_LINES_M.reshape(-1, 3)
        line_rel = np.einsum("kji,kpj->kpi", rots, segments[None, :, :] - cams[:, None, :]) + calib[:, None, :]
        line_rel = line_rel.reshape(count, -1, 2, 3)
        clipped, line_visible = _clip_to_pyramid(line_rel)
    names = LANDMARK_NAMES + ("B",)
    frames = []
    for k, observer in enumerate(observers):
        seen = np.nonzero(visible[k])[0]
        d, t, p = distance[k, seen], theta[k, seen], phi[k, seen]
        line_index = np.nonzero(line_visible[k])[0] if config.lines else np.zeros(0, dtype=np.intp)
        ld, lt, lp = polar(clipped[k, line_index]) if config.lines else (np.zeros((0, 2)),) * 3
        if config.noise:
            d, t, p = _noisy(d, t, p, rng)
            ld, lt, lp = _noisy(ld, lt, lp, rng)
        frames.append(_frame(seen, d, t, p, ld, lt, lp, names, players))
    return frames


def _noisy(d: np.ndarray, t: np.ndarray, p: np.ndarray,
           rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    draws = rng.standard_normal((3,) + d.shape)
    return (d + d * draws[0] * (SIGMA_DISTANCE_PERCENT / 100.0), t + draws[1] * SIGMA_THETA_DEG,
            p + draws[2] * SIGMA_PHI_DEG)


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


def _frame(seen: np.ndarray, d: np.ndarray, t: np.ndarray, p: np.ndarray, ld: np.ndarray, lt: np.ndarray,
           lp: np.ndarray, names: tuple[str, ...], players: list[PlayerParts]) -> See:
    fixed_count = len(names)
    objects: list[VisibleObject] = []
    parts: dict[int, dict[str, Polar]] = {}
    d_list, t_list, p_list = d.tolist(), t.tolist(), p.tolist()
    for i, point in enumerate(seen.tolist()):
        if point < fixed_count:
            objects.append(VisibleObject(names[point], d_list[i], t_list[i], p_list[i]))
        else:
            owner, part = divmod(point - fixed_count, len(players[0].part_names))
            parts.setdefault(owner, {})[players[owner].part_names[part]] = Polar(d_list[i], t_list[i], p_list[i])
    seen_players = tuple(VisiblePlayer(players[owner].team, players[owner].unum, parts[owner])
                         for owner in sorted(parts))
    lines = tuple(VisibleLine(Polar(a, b, c), Polar(e, f, g))
                  for (a, e), (b, f), (c, g) in zip(ld.tolist(), lt.tolist(), lp.tolist()))
    return See(tuple(objects), seen_players, lines)
