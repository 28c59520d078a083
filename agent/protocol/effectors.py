"""Effector commands (agent -> server): typed actions, their exact bytes, and the server-side parser.

Each action class validates itself on construction, so an agent cannot build a command the server would
reject (a too-long say message, a bad team name); numeric values are checked when written, because the
server side must be able to hold and flag the NaN an agent sent. Bytes follow REFERENCE §3.6 and the real
agents' spelling: ``(he1 0.5)``, ``(beam -2.5 0 0)``, ``(init (unum 1)(teamname CapL))`` (no space between
init's two lists), ``(say Hello123)``, ``(syn)``. Floats use :func:`~agent.protocol.numbers.format_agent_float`.

:func:`parse_actions` is what our server runs on each agent message: a syntax error is fatal for the
message (ProtocolError), but an unknown or malformed command only becomes an :class:`UnknownAction` or
:class:`InvalidAction` in the list, since rcssserver3d likewise logs and skips a bad predicate and applies
the rest.
"""

from __future__ import annotations

import math
import re
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass

from agent.protocol.errors import ProtocolError
from agent.protocol.numbers import AGENT_FLOAT_DECIMALS, format_agent_float, parse_float, parse_int
from agent.protocol.sexpr import Atom, Node, ascii_text, read_located

#: Longest say message the server passes on (longer ones are dropped silently; REFERENCE §3.8).
SAY_MAX_CHARS = 20
#: Joint effector names of robot types 0-4 (``lle7``/``rle7`` exist on type 4 only).
JOINT_EFFECTOR = re.compile(r"(?:he[12]|[lr]ae[1-4]|[lr]le[1-7])\Z")
#: Every name JOINT_EFFECTOR matches, for the per-cycle check (a set lookup; the pattern decides the rest).
_JOINT_EFFECTORS = frozenset(["he1", "he2"] + [f"{s}ae{i}" for s in "lr" for i in range(1, 5)]
                             + [f"{s}le{i}" for s in "lr" for i in range(1, 8)])
_ATOM = re.compile(r"[!-'*-~]+\Z")
_SAY_CHAR = re.compile(r"[!-'*-~]")  # printable ASCII without space and parentheses


def _check_atom(value: str, what: str) -> None:
    if _ATOM.match(value) is None:
        raise ProtocolError(f"{what} {value!r} must be printable ASCII without spaces or parentheses", 0,
                            value[:24].encode("latin-1", "replace"))


@dataclass(frozen=True, slots=True)
class Scene:
    """``(scene PATH [TYPE])``: create the robot; send once, first."""

    path: str
    """RSG file, e.g. ``rsg/agent/nao/nao_hetero.rsg``."""
    robot_type: int | None = None
    """Heterogeneous robot type 0-4 (with ``nao_hetero.rsg``); None sends no parameter."""

    def __post_init__(self) -> None:
        _check_atom(self.path, "scene path")

    def to_text(self) -> str:
        """The command's wire text."""
        return f"(scene {self.path})" if self.robot_type is None else f"(scene {self.path} {self.robot_type})"


@dataclass(frozen=True, slots=True)
class Init:
    """``(init (unum N)(teamname NAME))``: join a team; send once, after scene."""

    unum: int
    """Requested uniform number, 0 = next free (<= 11 per team)."""
    team: str
    """Team name; the first name the server sees plays left."""

    def __post_init__(self) -> None:
        _check_atom(self.team, "team name")
        if self.unum < 0:
            raise ProtocolError(f"unum must be >= 0, got {self.unum}", 0, str(self.unum).encode())

    def to_text(self) -> str:
        return f"(init (unum {self.unum})(teamname {self.team}))"


@dataclass(frozen=True, slots=True)
class JointVelocity:
    """``(EFF F)``: target velocity of one hinge, held until the next command."""

    effector: str
    """Effector name, ``he1`` ... ``rle6`` (``lle7``/``rle7`` on type 4)."""
    velocity_rad_s: float
    """Target angular velocity [rad/s] (may be NaN/Inf when parsed from a faulty agent: see ``finite``)."""

    def __post_init__(self) -> None:
        if self.effector not in _JOINT_EFFECTORS and JOINT_EFFECTOR.match(self.effector) is None:
            raise ProtocolError(f"unknown joint effector {self.effector!r}", 0, self.effector[:24].encode())

    @property
    def finite(self) -> bool:
        """False when the value is NaN or Inf (the server must reject the command)."""
        return math.isfinite(self.velocity_rad_s)

    def to_text(self) -> str:
        return f"({self.effector} {format_agent_float(self.velocity_rad_s)})"


@dataclass(frozen=True, slots=True)
class Beam:
    """``(beam X Y ROT)``: place the robot, in the team frame; only before kick-off and after goals."""

    x_m: float
    """Target x [m], team frame (own goal at -x)."""
    y_m: float
    """Target y [m], team frame."""
    rot_deg: float
    """Heading [deg], 0 = facing the opponent goal, 90 = facing +y."""

    @property
    def finite(self) -> bool:
        """False when any value is NaN or Inf (the server rejects the beam)."""
        return math.isfinite(self.x_m) and math.isfinite(self.y_m) and math.isfinite(self.rot_deg)

    def to_text(self) -> str:
        values = " ".join(format_agent_float(v) for v in (self.x_m, self.y_m, self.rot_deg))
        return f"(beam {values})"


@dataclass(frozen=True, slots=True)
class Say:
    """``(say MSG)``: broadcast up to 20 printable characters (no space, no parentheses) within 50 m."""

    message: str
    """The text; checked on construction against REFERENCE §3.8."""

    def __post_init__(self) -> None:
        check_say_message(self.message)

    def to_text(self) -> str:
        return f"(say {self.message})"


@dataclass(frozen=True, slots=True)
class PassMode:
    """``(pass)``: request pass mode (REFERENCE §4.6)."""

    def to_text(self) -> str:
        return "(pass)"


@dataclass(frozen=True, slots=True)
class Syn:
    """``(syn)``: end of this agent's cycle; required in sync mode, harmless otherwise."""

    def to_text(self) -> str:
        return "(syn)"


@dataclass(frozen=True, slots=True)
class UnknownAction:
    """A predicate the server does not know (it logs and ignores those); kept for counting and logs."""

    name: str
    """The predicate's head, or "" when it had none."""
    offset: int
    """Byte offset of its ``(`` in the message."""


@dataclass(frozen=True, slots=True)
class InvalidAction:
    """A known predicate with bad arguments (e.g. ``(beam 1)``, a 30-character say); the server skips it."""

    name: str
    """The predicate's head."""
    offset: int
    """Byte offset of its ``(`` in the message."""
    reason: str
    """What was wrong."""


Action = Scene | Init | JointVelocity | Beam | Say | PassMode | Syn
ParsedAction = Action | UnknownAction | InvalidAction


def check_say_message(message: str) -> str:
    """Return ``message`` if the server would pass it on, else raise.

    Raises:
        ProtocolError: longer than 20 characters, empty, or a character outside printable ASCII 0x21-0x7E
            or a parenthesis (offset = index of the first bad character, snippet = the message).
    """
    snippet = message.encode("latin-1", "replace")
    if not message:
        raise ProtocolError("say message is empty", 0, snippet)
    for index, char in enumerate(message):
        if _SAY_CHAR.match(char) is None:
            raise ProtocolError(f"say message character {char!r} is not allowed", index, snippet)
    if len(message) > SAY_MAX_CHARS:
        raise ProtocolError(f"say message has {len(message)} characters, max {SAY_MAX_CHARS}", SAY_MAX_CHARS,
                            snippet)
    return message


def format_actions(actions: Sequence[Action]) -> bytes:
    """Concatenated wire bytes of ``actions``, e.g. ``b"(he1 0.5)(syn)"``.

    Raises:
        ProtocolError: a NaN/Inf value (never sent: the server would reject it).
    """
    return "".join([action.to_text() for action in actions]).encode("ascii")


def format_joint_velocities(velocities_rad_s: Mapping[str, float]) -> bytes:
    """``(he1 0.5)(he2 -1.25)...`` for a whole body command, without building one object per joint.

    Args:
        velocities_rad_s: effector name (``he1`` ...) -> target velocity [rad/s].

    Raises:
        ProtocolError: an unknown effector name or a NaN/Inf value.
    """
    parts = []
    for effector, velocity in velocities_rad_s.items():
        if JOINT_EFFECTOR.match(effector) is None:
            raise ProtocolError(f"unknown joint effector {effector!r}", 0, effector[:24].encode())
        parts.append(f"({effector} {format_agent_float(velocity)})")
    return "".join(parts).encode("ascii")


def joint_velocity_template(effectors: Sequence[str]) -> bytes:
    """A printf template of a whole-body command, ``b"(he1 %.4f)(he2 %.4f)..."``, for agents that send the same
    joints every cycle: ``template % tuple(velocities)`` writes them all in one C call.

    Values get 4 fixed decimals (as `format_agent_float`, without trimming the zeros: the server reads both
    spellings alike); keep them finite, since ``%.4f`` would write ``nan``, which the server rejects.

    Raises:
        ProtocolError: an unknown effector name.
    """
    for effector in effectors:
        if JOINT_EFFECTOR.match(effector) is None:
            raise ProtocolError(f"unknown joint effector {effector!r}", 0, effector[:24].encode())
    return "".join(f"({effector} %.{AGENT_FLOAT_DECIMALS}f)" for effector in effectors).encode("ascii")


def parse_actions(data: bytes | str) -> list[ParsedAction]:
    """One agent message -> its commands, in order (what the server runs on each received frame).

    NaN/Inf values parse (check ``action.finite``); unknown predicates become :class:`UnknownAction` and
    malformed known ones :class:`InvalidAction`, neither fatal.

    Raises:
        ProtocolError: the message is not a sequence of S-expressions (bad byte, unbalanced parenthesis,
            atom outside a list), with the byte offset.
    """
    text = ascii_text(data)
    fast = split_joint_commands(text)
    if fast is not None:
        names, values, syn = fast
        actions: list[ParsedAction] = list(map(_new_joint, names, values))
        if syn:
            actions.append(_SYN)
        return actions
    nodes, _ = read_located(text)
    actions = []
    for node in nodes:
        head = node[0] if node and isinstance(node[0], Atom) else None
        if head is None or (head not in _PARSERS and JOINT_EFFECTOR.match(head) is None):
            actions.append(UnknownAction(str(head or ""), node.offset))
            continue
        try:
            actions.append(_PARSERS.get(head, _joint)(node, text))
        except ProtocolError as error:
            actions.append(InvalidAction(str(head), node.offset, error.reason))
    return actions


# The usual agent message, joint commands then (syn), in the exact spelling: cut apart without building trees.
# The pattern only admits the shape; names are checked against the effector set and numbers by float().
_JOINT_RUN = re.compile(r"(?:\([a-z1-7]++ -?[0-9.]++\))*+")
_JOINT_EFFECTORS = frozenset(["he1", "he2"] + [f"{side}{limb}{i}" for side in "lr" for limb in ("ae", "le")
                                               for i in range(1, 5 if limb == "ae" else 8)])
_SYN_TEXT = "(syn)"
_SYN = Syn()


def split_joint_commands(text: str) -> tuple[list[str], list[float], bool] | None:
    """The joint commands of the usual agent message, or None for any other message.

    The usual message is only ``(EFF F)`` commands in the exact spelling (``F`` a plain decimal), optionally
    followed by one ``(syn)``. It is checked with one regular expression and cut apart with string
    methods, all in C: the server reads one per robot every 20 ms, and this is its hot path. Other
    messages go to `parse_actions`' general path, which gives the same commands.

    Returns:
        (effector names, velocities [rad/s], whether it ended with ``(syn)``); values are finite.
    """
    syn = text.endswith(_SYN_TEXT)
    body = text[:-len(_SYN_TEXT)] if syn else text
    if _JOINT_RUN.fullmatch(body) is None:
        return None
    if not body:
        return [], [], syn
    # "(he1 0.5)(he2 -1)" -> "he1 0.5 he2 -1": names and values alternate.
    tokens = body[1:-1].replace(")(", " ").split(" ")
    names = tokens[0::2]
    if not _JOINT_EFFECTORS.issuperset(names):
        return None
    try:
        return names, list(map(float, tokens[1::2])), syn
    except ValueError:   # "1.2.3": the general path reports it
        return None


def _new_joint(effector: str, velocity_rad_s: float) -> JointVelocity:
    """A JointVelocity whose name the pattern already checked (so __post_init__'s second check is skipped)."""
    action = object.__new__(JointVelocity)
    object.__setattr__(action, "effector", effector)
    object.__setattr__(action, "velocity_rad_s", velocity_rad_s)
    return action


def _atoms(node: Node, counts: tuple[int, ...], text: str) -> list[Atom]:
    values = node[1:]
    if len(values) not in counts or not all(isinstance(value, Atom) for value in values):
        raise ProtocolError.at(f"({node[0]} ...) takes {' or '.join(map(str, counts))} atom(s)", text,
                               node.offset)
    return values  # type: ignore[return-value]


def _float(atom: Atom, text: str) -> float:
    return parse_float(atom, atom.offset, text)


def _joint(node: Node, text: str) -> JointVelocity:
    (value,) = _atoms(node, (1,), text)
    return JointVelocity(str(node[0]), _float(value, text))


def _scene(node: Node, text: str) -> Scene:
    values = _atoms(node, (1, 2), text)
    robot_type = parse_int(values[1], values[1].offset, text) if len(values) == 2 else None
    return Scene(str(values[0]), robot_type)


def _init(node: Node, text: str) -> Init:
    fields: dict[str, Atom] = {}
    for item in node[1:]:
        if not isinstance(item, Node) or len(item) != 2 or not all(isinstance(v, Atom) for v in item):
            raise ProtocolError.at("init takes (unum N) and (teamname NAME)", text, getattr(item, "offset", 0))
        fields[item[0]] = item[1]
    if set(fields) != {"unum", "teamname"}:
        raise ProtocolError.at("init takes (unum N) and (teamname NAME)", text, node.offset)
    unum = fields["unum"]
    return Init(parse_int(unum, unum.offset, text), str(fields["teamname"]))


def _beam(node: Node, text: str) -> Beam:
    x, y, rot = (_float(atom, text) for atom in _atoms(node, (3,), text))
    return Beam(x, y, rot)


def _say(node: Node, text: str) -> Say:
    (message,) = _atoms(node, (1,), text)
    return Say(str(message))


_PARSERS: dict[str, Callable[[Node, str], Action]] = {
    "scene": _scene,
    "init": _init,
    "beam": _beam,
    "say": _say,
    "pass": lambda node, text: _no_arguments(node, text, PassMode()),
    "syn": lambda node, text: _no_arguments(node, text, Syn()),
}


def _no_arguments(node: Node, text: str, action: Action) -> Action:
    _atoms(node, (0,), text)
    return action
