"""Typed perceptor values of one sense message, with the unit and frame of every field (REFERENCE §3.4-3.5).

Values are exactly what the wire says (degrees, metres, seconds as printed, 2 decimals); converting to
radians or to the field frame is the world model's job. Every class is frozen. Dict fields are not copied on
construction (the parser is on the hot path): treat them as read-only.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field, fields
from typing import Any, NamedTuple, TypeVar

Vector3 = tuple[float, float, float]
_Record = TypeVar("_Record")


class Polar(NamedTuple):
    """A seen point in the camera (head) frame: θ = 0 straight ahead, positive to the left; φ positive up."""

    distance_m: float
    """Distance from the camera [m]."""
    azimuth_deg: float
    """Horizontal angle θ [deg], in (-180, 180]."""
    elevation_deg: float
    """Vertical angle φ [deg]."""


@dataclass(frozen=True, slots=True)
class TimePerceptor:
    """``(time (now F))``: the server's clock, which runs in every play mode."""

    now_s: float
    """Server time [s] (not the game time)."""


@dataclass(frozen=True, slots=True)
class GameState:
    """``(GS [(unum I) (team T)] [(sl I) (sr I)] (t F) (pm MODE))``."""

    unum: int | None
    """Own uniform number; only in the first GS after a successful init, else None."""
    team: str | None
    """Own side, ``left``/``right`` (``none`` before init); present exactly when ``unum`` is."""
    score_left: int | None
    """Goals of the left team; None when the server does not report scores (0.7.3 always does)."""
    score_right: int | None
    """Goals of the right team; None when not reported."""
    game_time_s: float
    """Game time [s]; frozen in BeforeKickOff and GameOver, 300-600 in the second half."""
    play_mode: str
    """Play-mode name as the server spells it (``BeforeKickOff``, ``KickIn_Left``, ...; REFERENCE §4.2)."""


@dataclass(frozen=True, slots=True)
class Gyro:
    """``(GYR (n NAME) (rt F F F))``: angular rate of the named body."""

    name: str
    """Body name (``torso`` on the Nao)."""
    rate_deg_s: Vector3
    """Angular rate about the body's x, y, z axes [deg/s] (robot frame: x right, y forward, z up)."""


@dataclass(frozen=True, slots=True)
class Accelerometer:
    """``(ACC (n NAME) (a F F F))``: proper acceleration of the named body (about +9.81 z when upright)."""

    name: str
    """Body name (``torso``)."""
    acc_m_s2: Vector3
    """Acceleration along the body's x, y, z axes [m/s²]."""


@dataclass(frozen=True, slots=True)
class HingeJoint:
    """``(HJ (n NAME) (ax F))``: one joint angle (:class:`~agent.protocol.sense.Sense` keeps them as a dict)."""

    name: str
    """Wire perceptor name (``hj1``, ``llj4``, ...)."""
    angle_deg: float
    """Joint angle [deg], SimSpark sign convention."""


@dataclass(frozen=True, slots=True)
class ForceResistance:
    """``(FRP (n NAME) (c F F F) (f F F F))``: foot pressure, sent only in cycles with contact."""

    name: str
    """Sensor: ``lf``/``rf`` (feet), ``lf1``/``rf1`` (toes, robot type 4)."""
    contact_m: Vector3
    """Force-weighted mean contact point in foot coordinates, relative to the foot box centre [m]."""
    force_n: Vector3
    """Summed contact force in foot axes [N]."""


@dataclass(frozen=True, slots=True)
class Hear:
    """``(hear [TEAM] F self|F MSG)``: one message heard this cycle."""

    team: str | None
    """Speaker's team name (0.7.3 labels messages); None when the server sends no label."""
    game_time_s: float
    """Game time when the message was said [s]."""
    direction_deg: float | None
    """Direction to the speaker [deg] in the listener's team frame (not head-relative); None = own message
    (``self`` on the wire)."""
    message: str
    """The said text (<= 20 printable characters, no spaces or parentheses)."""

    @property
    def is_self(self) -> bool:
        """True for the agent's own message echoed back."""
        return self.direction_deg is None


class VisibleObject(NamedTuple):
    """``(NAME (pol d θ φ))``: a flag (``F1L`` ...), goal post (``G1L`` ...) or the ball (``B``).

    A NamedTuple rather than a dataclass, like :class:`Polar` and :class:`VisibleLine`: a vision frame holds
    about 25 of these records and building a tuple costs a quarter of a frozen dataclass, which matters on
    the agent's 20 ms cycle. They are just as immutable.
    """

    name: str
    """Object name; names are global, not flipped per team."""
    distance_m: float
    """Distance from the camera [m]."""
    azimuth_deg: float
    """θ [deg], positive to the left, camera frame."""
    elevation_deg: float
    """φ [deg], positive up, camera frame."""

    @property
    def polar(self) -> Polar:
        """The position as a :class:`Polar`."""
        return Polar(self.distance_m, self.azimuth_deg, self.elevation_deg)


@dataclass(frozen=True, slots=True)
class VisiblePlayer:
    """``(P (team NAME) [(id I)] (PART (pol d θ φ))+)``: a robot with its visible parts (own arms/feet too)."""

    team: str
    """Team name as given at init (not left/right)."""
    unum: int | None
    """Uniform number; None when the server has none to send."""
    parts: dict[str, Polar]
    """Visible part name (``head``, ``rlowerarm``, ``llowerarm``, ``rfoot``, ``lfoot``) -> position, in
    wire order."""


class VisibleLine(NamedTuple):
    """``(L (pol d θ φ) (pol d θ φ))``: a field-line segment clipped to the view pyramid (a NamedTuple for
    the reason given at :class:`VisibleObject`)."""

    begin: Polar
    """First end point (camera frame)."""
    end: Polar
    """Second end point (camera frame)."""


#: Letters of :attr:`See.order`, one per item of the See predicate.
SEE_OBJECT, SEE_PLAYER, SEE_MYPOS, SEE_LINE = "O", "P", "M", "L"


@dataclass(frozen=True, slots=True)
class See:
    """``(See OBJ* PLAYER* [(mypos x y z)] LINE*)``: one vision frame (every third cycle)."""

    objects: tuple[VisibleObject, ...]
    """Flags, goal posts and ball, in wire order."""
    players: tuple[VisiblePlayer, ...]
    """Robots with at least one visible part, in wire order."""
    lines: tuple[VisibleLine, ...]
    """Field-line segments, in wire order."""
    my_pos_m: Vector3 | None = None
    """Ground-truth torso position in the team frame [m] (``mypos``; off in the standard server)."""
    order: str = field(default="", compare=False)
    """Kinds of the items in wire order, one letter each (``O`` object, ``P`` player, ``M`` mypos, ``L``
    line), so a parsed See is written back byte for byte; "" means objects, players, mypos, lines, which is
    what the server does when it walks static objects before robots. Ignored by ``==``."""


@dataclass(frozen=True, slots=True)
class AgentState:
    """``(AgentState [(pan_tilt I I)] [(battery F)] [(temp F)])``: robot health; never sent for the Nao."""

    temperature: float | None
    """Modelled motor temperature (SimSpark's own unit, 23.00 at start); None when absent."""
    battery: float | None
    """Modelled battery level (SimSpark's own unit, 100.00 at start); None when absent."""
    pan_deg: int | None = None
    """Camera pan [deg] of robots with a pan/tilt camera; None when absent."""
    tilt_deg: int | None = None
    """Camera tilt [deg]; present exactly when ``pan_deg`` is."""


#: Names of the predicates :attr:`Sense.order` may hold.
PREDICATE_NAMES = ("time", "GS", "hear", "GYR", "ACC", "HJ", "FRP", "See", "AgentState")


@dataclass(frozen=True, slots=True)
class Sense:
    """One sense message: every perceptor the server sent in one cycle.

    ``order`` lets :func:`~agent.protocol.sense.format_sense` write a parsed message back byte for byte: it
    lists the predicate names in wire order, and the i-th ``HJ`` (``FRP``, ``hear``) in it is the i-th entry
    of ``joints`` (``frp``, ``hears``). Build a Sense with ``order=()`` to get the server's own order
    (REFERENCE §3.3). ``order`` is ignored by ``==``.
    """

    time: TimePerceptor | None
    """Server clock; None if the message had no ``time``."""
    game_state: GameState | None
    """Play mode, scores, game time; None if absent."""
    gyro: Gyro | None
    """Torso angular rate; None if absent."""
    acc: Accelerometer | None
    """Torso acceleration; None if absent."""
    joints: dict[str, float]
    """Wire perceptor name (``hj1`` ... ``rlj6``) -> joint angle [deg], in wire order."""
    frp: dict[str, ForceResistance] = field(default_factory=dict)
    """Sensor name (``lf``, ``rf``, ...) -> foot pressure, only for sensors with contact this cycle."""
    hears: tuple[Hear, ...] = ()
    """Messages heard this cycle (0-3), in wire order."""
    see: See | None = None
    """Vision, every third cycle; None otherwise."""
    agent_state: AgentState | None = None
    """Robot health; never sent for the Nao."""
    unknown: int = 0
    """Expressions skipped because their name (or a sub-item's key) is not known here."""
    order: tuple[str, ...] = field(default=(), compare=False)
    """Predicate names in wire order (entries of :data:`PREDICATE_NAMES`); () = the server's order."""


def record_builder(cls: type[_Record]) -> Callable[..., _Record]:
    """A function that builds a ``cls`` (a frozen, slotted dataclass of this module) from all its field values in
    order: the same object as ``cls(*values)``, in about half the time.

    Why: the parsers build six to eight of these per sense message, 50 times a second per agent, and a frozen
    dataclass's ``__init__`` sets each field through ``object.__setattr__``, which looks the field up on every
    call; the builder writes each field through its slot directly. None of these classes has a
    ``__post_init__`` or a conversion in ``__init__`` that this would skip (tests compare both ways).
    """
    names = [item.name for item in fields(cls)]   # type: ignore[arg-type]
    if tuple(names) != cls.__slots__:   # type: ignore[attr-defined]
        raise TypeError(f"{cls.__name__}: fields {names} are not its slots")
    scope: dict[str, Any] = {"new": object.__new__, "cls": cls}
    scope.update((f"set_{name}", getattr(cls, name).__set__) for name in names)
    arguments = ", ".join(names)
    body = "".join(f"    set_{name}(record, {name})\n" for name in names)
    exec(f"def build({arguments}):\n    record = new(cls)\n{body}    return record\n", scope)   # noqa: S102
    return scope["build"]   # type: ignore[no-any-return]


#: Builders of the records the parsers make every cycle (see `record_builder`).
new_sense = record_builder(Sense)
new_time = record_builder(TimePerceptor)
new_game_state = record_builder(GameState)
new_gyro = record_builder(Gyro)
new_accelerometer = record_builder(Accelerometer)
new_force_resistance = record_builder(ForceResistance)
new_hear = record_builder(Hear)
new_see = record_builder(See)
new_visible_player = record_builder(VisiblePlayer)
