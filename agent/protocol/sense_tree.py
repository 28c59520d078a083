"""The general path of sense parsing: located S-expression trees -> typed perceptors -> Sense.

:func:`~agent.protocol.sense.parse_sense` first tries compiled patterns for the server's exact spelling;
every message they do not fully recognise comes here: unknown predicates, foreign spacing, extra sub-items,
or malformed input that needs a precise error. This module is also the reference the fast path is tested
against (``parse_sense(data, fast_path=False)`` uses only it).

Rules: an unknown predicate, or an unknown ``(key ...)`` list inside a known one, is skipped and counted; a
known key with the wrong shape, a bad number or an atom where a list belongs is a ProtocolError at the
offending byte.
"""

from __future__ import annotations

from collections.abc import Callable

from agent.protocol.errors import ProtocolError
from agent.protocol.numbers import parse_finite_float, parse_float, parse_int
from agent.protocol.perceptors import (
    SEE_LINE,
    SEE_MYPOS,
    SEE_OBJECT,
    SEE_PLAYER,
    Accelerometer,
    AgentState,
    ForceResistance,
    GameState,
    Gyro,
    Hear,
    HingeJoint,
    Polar,
    See,
    Sense,
    TimePerceptor,
    VisibleLine,
    VisibleObject,
    VisiblePlayer,
)
from agent.protocol.sexpr import Atom, Node, read_located

Perceptor = (
    TimePerceptor | GameState | Gyro | Accelerometer | HingeJoint | ForceResistance | Hear | See | AgentState
)


def parse_sense_general(text: str) -> Sense:
    """A whole sense message (already checked by :func:`~agent.protocol.sexpr.ascii_text`) -> Sense.

    Raises:
        ProtocolError: as :func:`~agent.protocol.sense.parse_sense`.
    """
    accumulator = _Accumulator()
    pos = 0
    while True:
        nodes, pos = read_located(text, pos, limit=1)
        if not nodes:
            return accumulator.sense()
        perceptor, unknown = perceptor_from_tree(nodes[0], text)
        accumulator.unknown += unknown
        if perceptor is not None:
            accumulator.add(perceptor, nodes[0].offset, text)


def perceptor_from_tree(node: Node, text: str) -> tuple[Perceptor | None, int]:
    """The perceptor a top-level expression describes.

    Args:
        node: one top-level expression from :func:`~agent.protocol.sexpr.read_located`.
        text: the whole message (for error snippets).

    Returns:
        (perceptor, unknown): perceptor None when the predicate is unknown; unknown = expressions skipped.

    Raises:
        ProtocolError: a known predicate with a malformed body.
    """
    head = node[0] if node else None
    converter = _CONVERTERS.get(head) if isinstance(head, Atom) else None
    if converter is None:
        return None, 1
    return converter(node, text)


def _error(message: str, text: str, offset: int) -> ProtocolError:
    return ProtocolError.at(message, text, offset)


def _keyed(node: Node, text: str, known: frozenset[str]) -> tuple[dict[str, Node], int]:
    """The ``(key ...)`` lists of ``node[1:]`` by key, and how many had an unknown key."""
    fields: dict[str, Node] = {}
    unknown = 0
    for item in node[1:]:
        if not isinstance(item, Node) or not item or not isinstance(item[0], Atom):
            offset = item.offset
            raise _error(f"{node[0]}: expected a (key ...) list", text, offset)
        key = item[0]
        if key not in known:
            unknown += 1
        elif key in fields:
            raise _error(f"{node[0]}: ({key} ...) given twice", text, item.offset)
        else:
            fields[key] = item
    return fields, unknown


def _require(fields: dict[str, Node], key: str, node: Node, text: str) -> Node:
    item = fields.get(key)
    if item is None:
        raise _error(f"{node[0]}: missing ({key} ...)", text, node.offset)
    return item


def _atoms(item: Node, count: int, text: str) -> list[Atom]:
    """The ``count`` atoms after the key of ``item``, which must hold exactly those."""
    values = item[1:]
    if len(values) != count or not all(isinstance(value, Atom) for value in values):
        raise _error(f"({item[0]} ...) must hold {count} atom(s)", text, item.offset)
    return values  # type: ignore[return-value]


def _floats(item: Node, count: int, text: str) -> tuple[float, ...]:
    return tuple(parse_finite_float(atom, atom.offset, text) for atom in _atoms(item, count, text))


def _name(fields: dict[str, Node], node: Node, text: str) -> str:
    return str(_atoms(_require(fields, "n", node, text), 1, text)[0])


def _time(node: Node, text: str) -> tuple[TimePerceptor, int]:
    fields, unknown = _keyed(node, text, frozenset({"now"}))
    (now_s,) = _floats(_require(fields, "now", node, text), 1, text)
    return TimePerceptor(now_s), unknown


def _game_state(node: Node, text: str) -> tuple[GameState, int]:
    fields, unknown = _keyed(node, text, frozenset({"unum", "team", "sl", "sr", "t", "pm"}))

    def optional_int(key: str) -> int | None:
        if key not in fields:
            return None
        atom = _atoms(fields[key], 1, text)[0]
        return parse_int(atom, atom.offset, text)

    team = str(_atoms(fields["team"], 1, text)[0]) if "team" in fields else None
    (game_time_s,) = _floats(_require(fields, "t", node, text), 1, text)
    play_mode = str(_atoms(_require(fields, "pm", node, text), 1, text)[0])
    state = GameState(
        optional_int("unum"), team, optional_int("sl"), optional_int("sr"), game_time_s, play_mode
    )
    return state, unknown


def _gyro(node: Node, text: str) -> tuple[Gyro, int]:
    fields, unknown = _keyed(node, text, frozenset({"n", "rt"}))
    rate = _floats(_require(fields, "rt", node, text), 3, text)
    return Gyro(_name(fields, node, text), rate), unknown  # type: ignore[arg-type]


def _accelerometer(node: Node, text: str) -> tuple[Accelerometer, int]:
    fields, unknown = _keyed(node, text, frozenset({"n", "a"}))
    acc = _floats(_require(fields, "a", node, text), 3, text)
    return Accelerometer(_name(fields, node, text), acc), unknown  # type: ignore[arg-type]


def _hinge_joint(node: Node, text: str) -> tuple[HingeJoint, int]:
    fields, unknown = _keyed(node, text, frozenset({"n", "ax"}))
    (angle_deg,) = _floats(_require(fields, "ax", node, text), 1, text)
    return HingeJoint(_name(fields, node, text), angle_deg), unknown


def _force_resistance(node: Node, text: str) -> tuple[ForceResistance, int]:
    fields, unknown = _keyed(node, text, frozenset({"n", "c", "f"}))
    contact = _floats(_require(fields, "c", node, text), 3, text)
    force = _floats(_require(fields, "f", node, text), 3, text)
    return ForceResistance(_name(fields, node, text), contact, force), unknown  # type: ignore[arg-type]


def _hear(node: Node, text: str) -> tuple[Hear, int]:
    values = node[1:]
    if len(values) not in (3, 4) or not all(isinstance(value, Atom) for value in values):
        raise _error("hear: expected [TEAM] TIME self|DIRECTION MESSAGE atoms", text, node.offset)
    team = str(values[0]) if len(values) == 4 else None
    time_atom, direction_atom, message = values[-3:]
    game_time_s = parse_finite_float(time_atom, time_atom.offset, text)
    direction_deg = None if direction_atom == "self" else parse_finite_float(
        direction_atom, direction_atom.offset, text
    )
    return Hear(team, game_time_s, direction_deg, str(message)), 0


def _polar(item: object, text: str, owner: Node) -> Polar:
    """A ``(pol d theta phi)``. NaN and Inf are kept as sent: the real 0.7.3 server writes ``(pol nan nan
    nan)`` for a line end it cannot project (seen with a robot lying on its front); rejecting the message
    would lose the whole cycle, joints included. The world model drops such sightings."""
    if not isinstance(item, Node) or not item or item[0] != "pol":
        raise _error(f"{owner[0]}: expected (pol d theta phi)", text, getattr(item, "offset", owner.offset))
    return Polar(*(parse_float(atom, atom.offset, text) for atom in _atoms(item, 3, text)))


def _see(node: Node, text: str) -> tuple[See, int]:
    objects: list[VisibleObject] = []
    players: list[VisiblePlayer] = []
    lines: list[VisibleLine] = []
    my_pos = None
    order: list[str] = []
    unknown = 0
    for item in node[1:]:
        if not isinstance(item, Node) or not item or not isinstance(item[0], Atom):
            raise _error("See: expected a (NAME ...) list", text, item.offset)
        head = item[0]
        if head == "L":
            if len(item) != 3:
                raise _error("See: a line needs two (pol ...) end points", text, item.offset)
            lines.append(VisibleLine(_polar(item[1], text, item), _polar(item[2], text, item)))
            order.append(SEE_LINE)
        elif head == "P":
            player, skipped = _player(item, text)
            players.append(player)
            unknown += skipped
            order.append(SEE_PLAYER)
        elif head == "mypos":
            if my_pos is not None:
                raise _error("See: (mypos ...) given twice", text, item.offset)
            my_pos = _floats(item, 3, text)
            order.append(SEE_MYPOS)
        elif len(item) == 2 and isinstance(item[1], Node) and item[1] and item[1][0] == "pol":
            objects.append(VisibleObject(str(head), *_polar(item[1], text, item)))
            order.append(SEE_OBJECT)
        else:
            unknown += 1
    see = See(tuple(objects), tuple(players), tuple(lines), my_pos, "".join(order))  # type: ignore[arg-type]
    return see, unknown


def _player(item: Node, text: str) -> tuple[VisiblePlayer, int]:
    team: str | None = None
    unum: int | None = None
    parts: dict[str, Polar] = {}
    unknown = 0
    for sub in item[1:]:
        if not isinstance(sub, Node) or not sub or not isinstance(sub[0], Atom):
            raise _error("P: expected a (key ...) list", text, sub.offset)
        key = sub[0]
        if key == "team" and team is None and not parts:
            team = str(_atoms(sub, 1, text)[0])
        elif key == "id" and unum is None and not parts:
            atom = _atoms(sub, 1, text)[0]
            unum = parse_int(atom, atom.offset, text)
        elif len(sub) == 2 and isinstance(sub[1], Node) and sub[1] and sub[1][0] == "pol":
            if key in parts:
                raise _error(f"P: part {key} given twice", text, sub.offset)
            parts[str(key)] = _polar(sub[1], text, sub)
        else:
            unknown += 1
    if team is None:
        raise _error("P: missing (team NAME) before the parts", text, item.offset)
    return VisiblePlayer(team, unum, parts), unknown


def _agent_state(node: Node, text: str) -> tuple[AgentState, int]:
    fields, unknown = _keyed(node, text, frozenset({"pan_tilt", "battery", "temp"}))
    pan = tilt = None
    if "pan_tilt" in fields:
        pan_atom, tilt_atom = _atoms(fields["pan_tilt"], 2, text)
        pan, tilt = parse_int(pan_atom, pan_atom.offset, text), parse_int(tilt_atom, tilt_atom.offset, text)
    temperature = _floats(fields["temp"], 1, text)[0] if "temp" in fields else None
    battery = _floats(fields["battery"], 1, text)[0] if "battery" in fields else None
    return AgentState(temperature, battery, pan, tilt), unknown


_CONVERTERS: dict[str, Callable[[Node, str], tuple[Perceptor, int]]] = {
    "time": _time,
    "GS": _game_state,
    "GYR": _gyro,
    "ACC": _accelerometer,
    "HJ": _hinge_joint,
    "FRP": _force_resistance,
    "hear": _hear,
    "See": _see,
    "AgentState": _agent_state,
}


#: Perceptor type -> (Sense field, predicate name) for the predicates a message holds at most once.
_SINGLE: dict[type, tuple[str, str]] = {
    TimePerceptor: ("time", "time"),
    GameState: ("game_state", "GS"),
    Gyro: ("gyro", "GYR"),
    Accelerometer: ("acc", "ACC"),
    See: ("see", "See"),
    AgentState: ("agent_state", "AgentState"),
}


class _Accumulator:
    """The fields of the Sense being parsed; rejects a predicate given twice (the server never does)."""

    __slots__ = ("fields", "joints", "frp", "hears", "order", "unknown")

    def __init__(self) -> None:
        self.fields: dict[str, object] = {}
        self.joints: dict[str, float] = {}
        self.frp: dict[str, ForceResistance] = {}
        self.hears: list[Hear] = []
        self.order: list[str] = []
        self.unknown = 0

    def add(self, perceptor: Perceptor, offset: int, text: str) -> None:
        kind = type(perceptor)
        if kind is HingeJoint:
            if perceptor.name in self.joints:  # type: ignore[union-attr]
                raise _twice(f"HJ {perceptor.name}", text, offset)  # type: ignore[union-attr]
            self.joints[perceptor.name] = perceptor.angle_deg  # type: ignore[union-attr]
            self.order.append("HJ")
        elif kind is ForceResistance:
            if perceptor.name in self.frp:  # type: ignore[union-attr]
                raise _twice(f"FRP {perceptor.name}", text, offset)  # type: ignore[union-attr]
            self.frp[perceptor.name] = perceptor  # type: ignore[union-attr, assignment]
            self.order.append("FRP")
        elif kind is Hear:
            self.hears.append(perceptor)  # type: ignore[arg-type]
            self.order.append("hear")
        else:
            field_name, predicate = _SINGLE[kind]
            if field_name in self.fields:
                raise _twice(predicate, text, offset)
            self.fields[field_name] = perceptor
            self.order.append(predicate)

    def sense(self) -> Sense:
        get = self.fields.get
        return Sense(
            get("time"),  # type: ignore[arg-type]
            get("game_state"),  # type: ignore[arg-type]
            get("gyro"),  # type: ignore[arg-type]
            get("acc"),  # type: ignore[arg-type]
            self.joints,
            self.frp,
            tuple(self.hears),
            get("see"),  # type: ignore[arg-type]
            get("agent_state"),  # type: ignore[arg-type]
            self.unknown,
            tuple(self.order),
        )


def _twice(what: str, text: str, offset: int) -> ProtocolError:
    return ProtocolError.at(f"{what} given twice in one message", text, offset)
