"""Dynamic elements of motion playback: walk leaning, walk slowdown and turn gain (REFERENCE §7.2, §7.3).

Each element is a parametrised curve whose numbers live in a TOML file (default
``motions/params/dynamic_elements.toml``), so a tuner can rewrite them without touching code:

* **walk lean**: offset [deg] added to a ``computed`` joint of a walk phase, e.g. ``left_walk_lean_lle3``:
  ``offset = joint_offset_deg[kind] * lean * speed_scale(speed) * phase_scale(phase)``, where ``lean`` in
  [-1, 1] is the request (+ = curve left), the ``left_`` values move only for a left lean and the ``right_``
  values only for a right lean (the seed agent's leaning side makes the shorter step);
* **slowdown**: the k-th phase (k = 0, 1, ...) played after a stop request lasts
  ``1 + stretch * min(1, (k + 1) / ramp_phases)`` times its authored duration;
* **turn gain**: a requested turn [deg] -> gain in [min_gain, 1] that scales a turn motion, and back
  (the turn one motion makes at a gain), for dead reckoning and the turn benchmark's prediction error;
* **kick distance**: a requested ball distance [m] -> a stretch factor (>= 1) of a kick's strike phases: a
  slower swing sends the ball a shorter way (the distance-controlled kick, measured on the real server);
* **walk balance**: gyro feedback in the walks: ``offset = gain_deg_per_deg_s[kind] * rate`` added to the
  targets of both legs' joints of that kind, ``rate`` the torso's measured angular rate [deg/s] about its x
  axis (pitch kinds) or y axis (roll kinds); the walks are otherwise open loop.
"""

from __future__ import annotations

import math
import re
import tomllib
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field, fields
from pathlib import Path

import motions
from motions.authoring.toml_text import toml_value

#: The parameter file shipped with the motions.
DEFAULT_PARAMS_PATH = Path(motions.__file__).resolve().parent / "params" / "dynamic_elements.toml"

_LEAN_NAME = re.compile(r"^(left|right)_walk_lean_([lr])([a-z]e\d+)$")


def piecewise_linear(x: float, points: Sequence[float], values: Sequence[float]) -> float:
    """Linear interpolation of ``values`` over increasing ``points``, constant beyond both ends."""
    if x <= points[0]:
        return float(values[0])
    for i in range(1, len(points)):
        if x <= points[i]:
            span = points[i] - points[i - 1]
            fraction = (x - points[i - 1]) / span if span > 0 else 1.0
            return float(values[i - 1] + fraction * (values[i] - values[i - 1]))
    return float(values[-1])


def _check_curve(name: str, points: Sequence[float], values: Sequence[float]) -> None:
    if len(points) != len(values) or not points:
        raise ValueError(f"{name}: points and values must have the same non-zero length "
                         f"({len(points)} vs {len(values)})")
    if any(b < a for a, b in zip(points, points[1:])):
        raise ValueError(f"{name}: points must increase, got {list(points)}")


@dataclass(frozen=True)
class WalkLean:
    """Walk lean: offsets of the computed walk joints for a lean request (see the module docstring)."""

    joint_offsets_deg: Mapping[str, float] = field(default_factory=lambda: {"le3": 8.0, "le5": -8.0})
    """Joint kind (effector name without the side letter, e.g. ``le3``) -> offset at a full lean [deg]."""
    speed_points_m_s: tuple[float, ...] = (0.0, 1.0)
    """Walk speeds of the speed curve [m/s]."""
    speed_scale: tuple[float, ...] = (1.0, 1.0)
    """Scale of the offsets at those speeds."""
    phase_points: tuple[float, ...] = (0.0, 1.0)
    """Positions in the walk cycle (0..1) of the phase curve."""
    phase_scale: tuple[float, ...] = (1.0, 1.0)
    """Scale of the offsets at those positions."""
    provenance: str = ""
    command_points: tuple[float, ...] = ()
    """Lean request magnitudes (0..1) of the command curve; empty: the offsets grow linearly with the request."""
    command_scale: tuple[float, ...] = ()
    """Share of the full-lean offsets at those magnitudes (the same for both sides: the curve is odd in the
    request). Tuned so the curvature, not the offset, is linear in the request (motion_studio.tune_lean)."""

    def __post_init__(self) -> None:
        _check_curve("walk_lean speed curve", self.speed_points_m_s, self.speed_scale)
        _check_curve("walk_lean phase curve", self.phase_points, self.phase_scale)
        if self.command_points or self.command_scale:
            _check_curve("walk_lean command curve", self.command_points, self.command_scale)

    def offset_deg(self, computed_name: str, lean: float, speed_m_s: float = 0.0, phase: float = 0.0) -> float | None:
        """Offset [deg] for a computed value called ``computed_name``; None if the name is no walk lean.

        Args:
            computed_name: ``{left|right}_walk_lean_{effector}``, e.g. ``left_walk_lean_lle3``.
            lean: request in [-1, 1], + = curve left (values beyond are clipped).
            speed_m_s: the walk's speed (its ``speed_m_s`` constant).
            phase: the phase's position in the walk cycle, 0..1.
        """
        match = _LEAN_NAME.match(computed_name)
        if match is None:
            return None
        side, _, kind = match.groups()
        lean = max(-1.0, min(1.0, lean))
        amount = lean if side == "left" else -lean
        if amount <= 0.0:
            return 0.0
        if self.command_points:
            amount = piecewise_linear(amount, self.command_points, self.command_scale)
        offset = self.joint_offsets_deg.get(kind, 0.0)
        return (offset * amount * piecewise_linear(speed_m_s, self.speed_points_m_s, self.speed_scale)
                * piecewise_linear(phase, self.phase_points, self.phase_scale))


@dataclass(frozen=True)
class Slowdown:
    """Walk slowdown: phases after a stop request are stretched (see the module docstring)."""

    stretch: float = 0.35
    """Extra duration at full effect (0.35 = 35 % longer)."""
    ramp_phases: int = 1
    """Phases over which the stretch grows to full effect."""
    provenance: str = ""

    def __post_init__(self) -> None:
        if not (self.stretch > -1.0 and math.isfinite(self.stretch)):
            raise ValueError(f"slowdown stretch must be > -1, got {self.stretch!r}")
        if self.ramp_phases < 1:
            raise ValueError(f"slowdown ramp_phases must be >= 1, got {self.ramp_phases!r}")

    def factor(self, phases_since_stop: int) -> float:
        """Duration factor of the phase ``phases_since_stop`` (0 = the first one) after a stop request."""
        return 1.0 + self.stretch * min(1.0, (phases_since_stop + 1) / self.ramp_phases)


@dataclass(frozen=True)
class TurnGain:
    """Turn gain: requested turn [deg] -> gain, and the turn one turn motion makes at a gain."""

    min_gain: float = 0.3
    """Smallest gain."""
    offset_deg: float = 3.0
    """Requested turn below which the smallest gain is used [deg]."""
    span_deg: float = 37.0
    """Requested turn range over which the gain rises to 1 [deg]."""
    predicted_base_deg: float = 3.0
    """Turn of one motion at the smallest gain [deg]."""
    predicted_slope_deg: float = 46.0
    """Extra turn from the smallest gain to gain 1 [deg]."""
    provenance: str = ""
    request_points_deg: tuple[float, ...] = ()
    """Requested turns of one motion [deg] of a tuned monotone curve (with ``curve_gains``); empty: the line
    of ``offset_deg`` and ``span_deg`` above. Beyond the last point the gain stays at the last one, and the
    last point is the largest turn one motion is asked for (motion_studio.tune_turn)."""
    curve_gains: tuple[float, ...] = ()
    """Gain at each of ``request_points_deg``, strictly increasing (so the curve inverts: the prediction)."""

    def __post_init__(self) -> None:
        if not 0.0 < self.min_gain <= 1.0 or self.span_deg <= 0.0:
            raise ValueError(f"turn gain needs 0 < min_gain <= 1 and span_deg > 0, got {self.min_gain}, {self.span_deg}")
        if self.request_points_deg or self.curve_gains:
            _check_curve("turn_gain curve", self.request_points_deg, self.curve_gains)
            if len(self.curve_gains) < 2 or any(b <= a for a, b in zip(self.curve_gains, self.curve_gains[1:])):
                raise ValueError(f"turn_gain curve_gains must increase strictly, got {list(self.curve_gains)}")
            if not (0.0 < self.curve_gains[0] and self.curve_gains[-1] <= 1.0):
                raise ValueError(f"turn_gain curve_gains must lie in (0, 1], got {list(self.curve_gains)}")
            if self.min_gain != self.curve_gains[0]:
                # the turn skills take the smallest turn from min_gain
                raise ValueError(f"turn_gain min_gain {self.min_gain} must be the curve's first gain "
                                 f"{self.curve_gains[0]}")

    def gain(self, turn_deg: float) -> float:
        """Gain for a requested turn of ``turn_deg`` (sign ignored: the motion's side gives the direction).

        Below ``offset_deg`` the smallest gain is used, as documented; the 2012 code's ``|turn - 3|`` would
        raise the gain again for smaller requests (a 1 deg request got the gain of 5 deg).
        """
        if self.request_points_deg:
            return piecewise_linear(abs(turn_deg), self.request_points_deg, self.curve_gains)
        excess = min(self.span_deg, max(0.0, abs(turn_deg) - self.offset_deg))
        return self.min_gain + (1.0 - self.min_gain) * excess / self.span_deg

    def predicted_turn_deg(self, gain: float) -> float:
        """Turn [deg] one turn motion makes at ``gain`` (dead reckoning)."""
        if self.request_points_deg:
            return piecewise_linear(gain, self.curve_gains, self.request_points_deg)
        if self.min_gain >= 1.0:
            return self.predicted_base_deg + self.predicted_slope_deg
        return self.predicted_base_deg + self.predicted_slope_deg * (gain - self.min_gain) / (1.0 - self.min_gain)


@dataclass(frozen=True)
class KickDistance:
    """Kick distance: requested ball distance [m] -> stretch of the strike phases' durations.

    Why the timing: the swing and strike phases are shorter than the joints can follow (they run at their
    speed limits through the contact), so stretching them lowers the foot's speed at the contact, and the ball
    rolls about 0.68 m per m/s it is launched with (measured on the real server, issue 12); the kick's poses, and with
    them its line-up and balance, stay the same. The table is measured: each stretch with the distance it
    gave (``distance_points_m`` increasing, ``stretch`` not increasing: a longer way needs a faster swing). A
    request gets the stretch of the nearest measured distance, never one in between: the phases last whole
    cycles, so an interpolated stretch would round to cycle counts nobody measured.
    """

    motions: tuple[str, ...] = ()
    """The kick motions the table applies to (a mirrored kick shares it)."""
    phases: tuple[str, ...] = ("swing", "strike")
    """The phases whose durations are stretched."""
    distance_points_m: tuple[float, ...] = (1.0,)
    """Measured ball distances [m], increasing."""
    stretch: tuple[float, ...] = (1.0,)
    """The duration factor that gave each distance (1 = as authored: the kick's full distance)."""
    provenance: str = ""

    def __post_init__(self) -> None:
        _check_curve("kick_distance table", self.distance_points_m, self.stretch)
        if any(b <= a for a, b in zip(self.distance_points_m, self.distance_points_m[1:])):
            raise ValueError(f"kick_distance distance_points_m must increase strictly, got "
                             f"{list(self.distance_points_m)}")
        if any(not (f >= 1.0 and math.isfinite(f)) for f in self.stretch):
            raise ValueError(f"kick_distance stretch factors must be >= 1, got {list(self.stretch)}")
        if any(b > a for a, b in zip(self.stretch, self.stretch[1:])):
            raise ValueError(f"kick_distance stretch must not increase with the distance, got {list(self.stretch)}")

    def applies(self, motion: str, phase: str) -> bool:
        return motion in self.motions and phase in self.phases

    def _nearest(self, distance_m: float) -> int:
        """Index of the measured distance nearest to ``distance_m`` (the shorter one on a tie)."""
        return min(range(len(self.distance_points_m)), key=lambda i: abs(self.distance_points_m[i] - distance_m))

    def stretch_for(self, distance_m: float) -> float:
        """Duration factor of the strike phases for a ball distance of ``distance_m`` [m]."""
        return self.stretch[self._nearest(distance_m)]

    def expected_distance_m(self, distance_m: float) -> float:
        """The measured distance [m] the kick is expected to reach for a request of ``distance_m`` [m]."""
        return self.distance_points_m[self._nearest(distance_m)]


@dataclass(frozen=True)
class WalkBalance:
    """Walk balance: gyro feedback on the leg joints of the walks (see the module docstring).

    Why: the walks are played open loop, so a gait fast enough for the real server falls on ours (and the
    other way round) wherever the two servers' feet land differently; a joint offset against the torso's
    angular rate moves the centre of pressure against the tipping before it becomes a fall.
    """

    pitch_gains_deg_per_deg_s: Mapping[str, float] = field(default_factory=dict)
    """Joint kind (``le5``, ``le3``, ...) -> target offset [deg] per torso rate about x (pitch) [deg/s]."""
    roll_gains_deg_per_deg_s: Mapping[str, float] = field(default_factory=dict)
    """Joint kind (``le6``, ``le2``, ...) -> target offset [deg] per torso rate about y (roll) [deg/s]."""
    motions: tuple[str, ...] = ()
    """The walks it applies to; empty: every motion with a ``speed_m_s`` constant."""
    max_offset_deg: float = 10.0
    """Bound of each joint's offset [deg]: a blow-up of the rate must not throw the legs."""
    provenance: str = ""

    def __post_init__(self) -> None:
        for name, gains in (("pitch", self.pitch_gains_deg_per_deg_s), ("roll", self.roll_gains_deg_per_deg_s)):
            for kind, gain in gains.items():
                if not math.isfinite(gain):
                    raise ValueError(f"walk_balance {name} gain of {kind} must be finite, got {gain!r}")
        if not (self.max_offset_deg >= 0.0 and math.isfinite(self.max_offset_deg)):
            raise ValueError(f"walk_balance max_offset_deg must be >= 0, got {self.max_offset_deg!r}")

    @property
    def active(self) -> bool:
        return bool(self.pitch_gains_deg_per_deg_s or self.roll_gains_deg_per_deg_s)

    def applies(self, motion: str, is_walk: bool) -> bool:
        return self.active and (motion in self.motions if self.motions else is_walk)

    def offset_deg(self, kind: str, gyro_deg_s: tuple[float, float, float]) -> float:
        """Offset [deg] of a joint of ``kind`` (effector name without its side letter) for the torso rates
        ``gyro_deg_s`` (x, y, z) [deg/s]."""
        offset = (self.pitch_gains_deg_per_deg_s.get(kind, 0.0) * gyro_deg_s[0]
                  + self.roll_gains_deg_per_deg_s.get(kind, 0.0) * gyro_deg_s[1])
        return max(-self.max_offset_deg, min(self.max_offset_deg, offset))


@dataclass(frozen=True)
class DynamicParams:
    """All dynamic elements; ``source`` is the file they were read from (None: defaults)."""

    walk_lean: WalkLean = field(default_factory=WalkLean)
    slowdown: Slowdown = field(default_factory=Slowdown)
    turn_gain: TurnGain = field(default_factory=TurnGain)
    kick_distance: KickDistance = field(default_factory=KickDistance)
    walk_balance: WalkBalance = field(default_factory=WalkBalance)
    source: str | None = None


def _section(cls: type, table: Mapping[str, object], path: str, name: str) -> object:
    known = {f.name for f in fields(cls)}
    unknown = set(table) - known
    if unknown:
        raise ValueError(f"{path}: [{name}] has unknown keys {sorted(unknown)}; known: {sorted(known)}")
    values = {key: tuple(value) if isinstance(value, list) else value for key, value in table.items()}
    try:
        return cls(**values)
    except (TypeError, ValueError) as error:
        raise ValueError(f"{path}: [{name}]: {error}") from None


def load_dynamic_params(path: str | Path | None = None) -> DynamicParams:
    """Read the dynamic elements from a TOML file (default: DEFAULT_PARAMS_PATH); missing sections keep
    their defaults.

    Raises:
        ValueError: a bad TOML file, an unknown key or a bad value (message names the file and section).
        OSError: the file cannot be read.
    """
    path = Path(path) if path is not None else DEFAULT_PARAMS_PATH
    try:
        data = tomllib.loads(path.read_text(encoding="utf-8"))
    except tomllib.TOMLDecodeError as error:
        raise ValueError(f"{path}: {error}") from None
    sections = {"walk_lean": WalkLean, "slowdown": Slowdown, "turn_gain": TurnGain, "kick_distance": KickDistance,
                "walk_balance": WalkBalance}
    unknown = set(data) - set(sections)
    if unknown:
        raise ValueError(f"{path}: unknown sections {sorted(unknown)}; known: {sorted(sections)}")
    built = {name: _section(cls, data.get(name, {}), str(path), name) for name, cls in sections.items()}
    return DynamicParams(**built, source=str(path))  # type: ignore[arg-type]


def dumps_dynamic_params(params: DynamicParams, header: str) -> str:
    """TOML text of ``params`` with ``header`` (lines written as ``#`` comments) on top."""
    lines = [f"# {line}".rstrip() for line in header.splitlines()]
    for name in ("walk_lean", "slowdown", "turn_gain", "kick_distance", "walk_balance"):
        section = getattr(params, name)
        lines += ["", f"[{name}]"]
        lines += [f"{f.name} = {toml_value(getattr(section, f.name))}" for f in fields(section)]
    return "\n".join(lines) + "\n"


def save_dynamic_params(params: DynamicParams, path: str | Path, header: str) -> None:
    """Write ``params`` to ``path`` (the tuner's way to change a curve); ``header`` says how they were made."""
    Path(path).write_text(dumps_dynamic_params(params, header), encoding="utf-8")
