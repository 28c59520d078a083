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
import threading
from dataclasses import dataclass
from functools import partial
from typing import NamedTuple

import numpy as np

from agent.protocol.perceptors import Polar, See, VisibleLine, VisibleObject, VisiblePlayer
from agent.protocol.sense_template import (PLAYER_CLOSE_BYTES, PRINTF_NUMBER, SEE_CLOSE_BYTES, SEE_OPEN_BYTES,
                                           SEE_SEPARATOR_BYTES, SPELLED_NUMBER, line_template, object_template,
                                           part_template, player_template)
from sim.field import FIELD_LINES_M, LANDMARK_NAMES, LANDMARK_POSITIONS_M
from sim.fixed2 import SPELL_MIN_VALUES, spell_fixed2

HALF_FOV_DEG = 60.0
MIN_DISTANCE_M = 0.1
CALIBRATION_ERROR_M = 0.005
SIGMA_DISTANCE_PERCENT = 0.0965
SIGMA_THETA_DEG = 0.1480
SIGMA_PHI_DEG = 0.1225
_TAN_HALF_FOV = math.tan(math.radians(HALF_FOV_DEG))
_SIGMAS = np.array([0.0, SIGMA_THETA_DEG, SIGMA_PHI_DEG])
_PARTS_PER_PLAYER = 5
_FIXED_COUNT = len(LANDMARK_NAMES) + 1   # landmarks and the ball
_SEPARATED_LINE = {True: SEE_SEPARATOR_BYTES + line_template(SPELLED_NUMBER),
                   False: SEE_SEPARATOR_BYTES + line_template(PRINTF_NUMBER)}
_SEPARATOR_SIZE = len(SEE_SEPARATOR_BYTES)
# Below this many object points (one observer, a few players) the field-of-view prefilter costs more than it saves.
_PREFILTER_MIN_POINTS = 256
_new_polar = partial(tuple.__new__, Polar)
_new_object = partial(tuple.__new__, VisibleObject)
_new_line = partial(tuple.__new__, VisibleLine)
_LINE_POINTS = FIELD_LINES_M.reshape(-1, 3)
# Inward normals of the view pyramid's planes in the head frame (x right, y ahead, z up).
_PLANES = np.array([[-1.0, _TAN_HALF_FOV, 0.0], [1.0, _TAN_HALF_FOV, 0.0],
                    [0.0, _TAN_HALF_FOV, -1.0], [0.0, _TAN_HALF_FOV, 1.0]])
_PLANES_T = _PLANES.T
# Scalar operands of the per-frame ufuncs as 0-d arrays: numpy converts a Python number operand on every call,
# which costs about as much as the operation itself on one frame's few dozen values (same values and results).
_ZERO = np.array(0.0)
_QUARTER_TURN_DEG = np.array(90.0)
_MINUS_HALF_TURN_DEG = np.array(-180.0)
_FULL_TURN_DEG = np.array(360.0)
_MIN_DISTANCE = np.array(MIN_DISTANCE_M)
_HALF_FOV = np.array(HALF_FOV_DEG)
_ONE = np.array(1.0)
_SIGMA_DISTANCE = np.array(SIGMA_DISTANCE_PERCENT / 100.0)
_FIXED_COUNT_ARRAY = np.array(_FIXED_COUNT, dtype=np.intp)
_PARTS_ARRAY = np.array(_PARTS_PER_PLAYER, dtype=np.intp)
_MINUS_ONE = np.array(-1, dtype=np.intp)
_TWO = np.array(2, dtype=np.intp)
_FOUR = np.array(4, dtype=np.intp)
_PREFILTER_X = np.array(1.75)   # the field-of-view prefilter's slopes (see `observe`)
_PREFILTER_Z = np.array(3.6)


@dataclass(frozen=True)
class VisionConfig:
    """Switches of the vision model (defaults = the standard server)."""

    noise: bool = True
    """Per-observation noise on d, θ, φ."""
    calibration: bool = True
    """The per-connection calibration offset (drawn by the caller; this only switches its use)."""
    lines: bool = True
    """Report field lines."""
    enabled: bool = True
    """Compute vision at all (False: no ``See`` in any message; training environments whose observation has
    no vision skip a third of a cycle's cost)."""


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


def _polar_rows(rel: np.ndarray) -> np.ndarray:
    """`polar` of points (n, 3) as rows (d, θ, φ) of one array: the same arithmetic, written in place."""
    x, y, z = rel[:, 0], rel[:, 1], rel[:, 2]
    out = np.empty(rel.shape)
    planar = x * x + y * y
    np.sqrt(planar + z * z, out=out[:, 0])
    theta = np.degrees(np.arctan2(y, x)) - _QUARTER_TURN_DEG
    theta[theta <= _MINUS_HALF_TURN_DEG] += _FULL_TURN_DEG
    out[:, 1] = theta
    np.degrees(np.arctan2(z, np.sqrt(planar)), out=out[:, 2])
    return out


class Sighting(NamedTuple):
    """What every observer of one cycle sees, as arrays (noise applied); `see` and `SeeWriter` read it.

    Objects: rows (seen_k[i], seen_p[i]) of the point table (landmarks, ball, then 5 parts per player),
    sorted by observer then point; values[i] = (d [m], θ [deg], φ [deg]). Lines: line_k[j] is the observer
    of line j, line_values[2j], line_values[2j + 1] its two ends. object_rows / line_rows: observer k owns
    objects object_rows[k]:object_rows[k + 1] and lines line_rows[k]:line_rows[k + 1].
    """

    seen_k: np.ndarray
    seen_p: np.ndarray
    values: np.ndarray
    line_k: np.ndarray
    line_values: np.ndarray
    object_rows: np.ndarray
    line_rows: np.ndarray


def observe(cams_m: np.ndarray, rotations: np.ndarray, calibration_m: np.ndarray, ball_m: np.ndarray,
            part_points_m: np.ndarray, rng: np.random.Generator, config: VisionConfig = VisionConfig()) -> Sighting:
    """The vision of K observers at once (the numpy core of `see` and the engine's writer).

    Args:
        cams_m: camera positions (K, 3); rotations: head frames (K, 3, 3), axes as columns;
        calibration_m: each connection's calibration error (K, 3), head frame; ball_m: ball centre (3,);
        part_points_m: the visible parts of every robot with a team, connection order, 5 rows each (5N, 3);
        rng: the world's generator (one draw for all observers, objects then lines, so runs are
            reproducible); config: model switches.
    """
    count = cams_m.shape[0]
    # rows: landmarks, ball, players' parts, then the field-line end points (static, kept in a buffer)
    points = _point_table(part_points_m.shape[0], config.lines)
    points[_FIXED_COUNT - 1] = ball_m
    points[_FIXED_COUNT:_FIXED_COUNT + part_points_m.shape[0]] = part_points_m
    rel = (points - cams_m[:, None, :]) @ rotations                              # R_headᵀ (p - c), (K, P, 3)
    if config.calibration:
        rel += calibration_m[:, None, :]
    object_count = _FIXED_COUNT + part_points_m.shape[0]
    flat = rel[:, :object_count].reshape(-1, 3)
    candidates = None
    if flat.shape[0] > _PREFILTER_MIN_POINTS:
        # A cheap superset of the field of view, so the exact test and the polar conversion (arctan2 costs)
        # run on about a third of the points: |θ| <= 60° needs y > 0 and |x| <= tan 60° y < 1.75 y, and then
        # |φ| <= 60° needs |z| <= tan 60° |(x, y)| < 3.6 y. Same result, with margin for rounding.
        x, y = flat[:, 0], flat[:, 1]
        near_view = (y > _ZERO) & (np.abs(x) <= _PREFILTER_X * y) & (np.abs(flat[:, 2]) <= _PREFILTER_Z * y)
        candidates = near_view.nonzero()[0]
        flat = flat[candidates]
    object_rows = flat.shape[0]
    if config.lines:
        clipped, line_visible = _clip_to_pyramid(rel[:, object_count:].reshape(count, -1, 2, 3))
        line_k, line_i = np.nonzero(line_visible)
        flat = np.concatenate((flat, clipped[line_k, line_i].reshape(-1, 3)))   # 2 rows per line
    else:
        line_k = np.zeros(0, dtype=np.intp)
    # One polar conversion for the objects of every observer and the clipped line ends.
    table = _polar_rows(flat)
    objects = table[:object_rows]
    visible = ((objects[:, 0] > _MIN_DISTANCE) & (np.abs(objects[:, 1]) <= _HALF_FOV)
               & (np.abs(objects[:, 2]) <= _HALF_FOV))
    seen = visible.nonzero()[0]   # (np.flatnonzero of a 1-d array, without its Python wrapper)
    seen_k, seen_p = np.divmod(seen if candidates is None else candidates[seen], np.array(object_count, dtype=np.intp))
    chosen = np.concatenate((objects[seen], table[object_rows:]))
    if config.noise:
        chosen = _noisy(chosen, rng)
    if count == 1:   # one observer owns every row
        object_rows, line_rows = np.array((0, seen.size)), np.array((0, line_k.size))
    else:
        bounds = np.arange(count + 1)
        object_rows, line_rows = np.searchsorted(seen_k, bounds), np.searchsorted(line_k, bounds)
    return Sighting(seen_k, seen_p, chosen[:seen.size], line_k, chosen[seen.size:], object_rows, line_rows)


_POINT_TABLES = threading.local()   # per thread: engines may run in several (the TCP server has its own)


def _point_table(part_count: int, lines: bool) -> np.ndarray:
    """The point table of `observe` for ``part_count`` player parts: landmarks and (with ``lines``) the field-line
    ends filled in; the ball and part rows are the caller's to write. One buffer per shape and thread, reused
    (cheaper than concatenating the static rows every cycle)."""
    tables = getattr(_POINT_TABLES, "tables", None)
    if tables is None:
        tables = _POINT_TABLES.tables = {}
    table = tables.get((part_count, lines))
    if table is None:
        table = tables[(part_count, lines)] = np.concatenate(
            (LANDMARK_POSITIONS_M, np.zeros((1 + part_count, 3))) + ((_LINE_POINTS,) if lines else ()))
    return table


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
    part_points = np.vstack([p.parts_m for p in players]) if players else np.zeros((0, 3))
    sighting = observe(np.stack([o.position_m for o in observers]), np.stack([o.rotation for o in observers]),
                       np.stack([o.calibration_m for o in observers]), ball_m, part_points, rng, config)
    names = LANDMARK_NAMES + ("B",)
    object_rows, line_rows = sighting.object_rows, sighting.line_rows
    seen_list, value_list = sighting.seen_p.tolist(), sighting.values.tolist()
    line_list = sighting.line_values.tolist()
    return [_frame(seen_list[object_rows[k]:object_rows[k + 1]], value_list[object_rows[k]:object_rows[k + 1]],
                   line_list[2 * line_rows[k]:2 * line_rows[k + 1]], names, players) for k in range(len(observers))]


class SeeWriter:
    """Writes the See predicate of each observer of a `Sighting` straight to bytes (no `See` objects).

    The item spellings come from agent.protocol.sense_template; the items of every point of the table (an
    object, or a part opening and/or closing its player) are built once per set of players and picked per
    cycle by index; the numbers of all frames are spelled at once (`sim.fixed2`), or with few numbers (one
    observer) left to printf templates, and each frame is one ``bytes % tuple``.

    Args:
        part_names: the 5 visible parts of a robot in the point table's order (sim.world.VISIBLE_PARTS).
    """

    def __init__(self, part_names: tuple[str, ...]) -> None:
        self.part_names = part_names
        self._players: tuple[tuple[str, int | None], ...] | None = None
        self._owner_stride = np.array(_FIXED_COUNT + 1, dtype=np.intp)
        # Item tables for spelled numbers (True) and for printf (False), built for `_players`.
        self._items = {True: np.zeros(0, dtype=object), False: np.zeros(0, dtype=object)}

    def frames(self, sighting: Sighting, players: tuple[tuple[str, int | None], ...]) -> list[bytes]:
        """One ``(See ...)`` per observer of ``sighting``.

        Args:
            players: (team name, unum) of the robots whose parts are in the point table, in its order.
        """
        if players != self._players:
            self._items = {spelled: _item_table(players, self.part_names, spelled) for spelled in (True, False)}
            self._players = players
            # An owner id per (observer, landmark or player): the point table has this many of them per observer.
            self._owner_stride = np.array(len(players) + _FIXED_COUNT + 1, dtype=np.intp)
        seen_k, seen_p = sighting.seen_k, sighting.seen_p
        # A part opens its player when the previous seen point is not the same player's (or another
        # observer's), and closes it when the next one is not.
        owner = seen_k * self._owner_stride + np.maximum(seen_p - _FIXED_COUNT_ARRAY, _MINUS_ONE) // _PARTS_ARRAY
        change = np.empty(owner.size + 1, dtype=bool)
        change[0] = change[-1] = True
        np.not_equal(owner[1:], owner[:-1], out=change[1:-1])
        object_numbers = sighting.values.size
        spelled = object_numbers + sighting.line_values.size >= SPELL_MIN_VALUES
        items = self._items[spelled][seen_p * _FOUR + change[:-1] * _TWO + change[1:]].tolist()
        # Every number of every frame in one list, objects then lines (spelled at once: one call, not two).
        numbers = np.concatenate((sighting.values.ravel(), sighting.line_values.ravel()))
        numbers = (spell_fixed2(numbers) if spelled else numbers).tolist()
        values, line_values = numbers[:object_numbers], numbers[object_numbers:]
        separated_line = _SEPARATED_LINE[spelled]
        object_rows, line_rows = sighting.object_rows.tolist(), sighting.line_rows.tolist()
        out = []
        for k in range(len(object_rows) - 1):
            a, b, c, d = object_rows[k], object_rows[k + 1], line_rows[k], line_rows[k + 1]
            body = b"".join(items[a:b]) + separated_line * (d - c)
            out.append((SEE_OPEN_BYTES + body[_SEPARATOR_SIZE:] + SEE_CLOSE_BYTES)
                       % (*values[3 * a:3 * b], *line_values[6 * c:6 * d]))
        return out


def _item_table(players: tuple[tuple[str, int | None], ...], part_names: tuple[str, ...],
                spelled: bool = True) -> np.ndarray:
    """Item template per (point, opens its player, closes its player), flattened as point * 4 + 2 open + close;
    numbers as spellings (``spelled``) or floats."""
    number = SPELLED_NUMBER if spelled else PRINTF_NUMBER
    rows = [[SEE_SEPARATOR_BYTES + object_template(name, number)] * 4 for name in LANDMARK_NAMES + ("B",)]
    for team, unum in players:
        opening = SEE_SEPARATOR_BYTES + player_template(team, unum)
        for part in part_names:
            item = part_template(part, number)
            rows.append([item, item + PLAYER_CLOSE_BYTES, opening + item, opening + item + PLAYER_CLOSE_BYTES])
    table = np.empty(4 * len(rows), dtype=object)
    table[:] = [item for row in rows for item in row]
    return table


def _noisy(values: np.ndarray, rng: np.random.Generator) -> np.ndarray:
    """Per-point noise on (d, θ, φ) rows (REFERENCE §3.5)."""
    draws = rng.standard_normal(values.shape)
    out = values + draws * _SIGMAS
    out[:, 0] = values[:, 0] * (_ONE + draws[:, 0] * _SIGMA_DISTANCE)
    return out


def _clip_to_pyramid(segments: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Clip head-frame segments (K, L, 2, 3) to the view pyramid; returns the clipped ends and a mask."""
    start, end = segments[..., 0, :], segments[..., 1, :]
    direction = end - start
    at_start = start @ _PLANES_T                     # (K, L, 4): signed distance of the start to each plane
    along = direction @ _PLANES_T                    # rate of change along the segment
    entering, leaving = along > _ZERO, along < _ZERO
    # Each bound is a masked reduction starting at 0 (resp. 1), in one ufunc call: a segment parallel to a
    # plane has no crossing, so its division is skipped instead of run under np.errstate (which costs more).
    t_cross = np.divide(-at_start, along, where=entering | leaving)
    low = np.maximum.reduce(t_cross, axis=2, where=entering, initial=0.0)
    high = np.minimum.reduce(t_cross, axis=2, where=leaving, initial=1.0)
    visible = (low < high) & ~np.logical_or.reduce((along == _ZERO) & (at_start < _ZERO), axis=2)
    clipped = np.empty(segments.shape)
    np.add(start, low[..., None] * direction, out=clipped[..., 0, :])
    np.add(start, high[..., None] * direction, out=clipped[..., 1, :])
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
