"""Sense messages: ``parse_sense`` (agent side) and ``format_sense`` (our server), byte-exact with 0.7.3.

Parsing runs every 20 ms in every agent, so it has a fast path: compiled patterns that match the server's
exact spelling of each predicate (``(HJ (n llj4) (ax -61.93))``, one space inside a predicate, none between
predicates, 2-decimal floats) and build the values straight from the match groups. Whatever those patterns
do not recognise (an unknown predicate, other spacing, a malformed message) goes through the general reader
and :mod:`agent.protocol.sense_tree`, which gives the same values, skips and counts unknown expressions, and
raises a ProtocolError at the offending byte. ``parse_sense(data, fast_path=False)`` uses only the general
path; the tests check both paths agree on every real message.

``format_sense`` lives in :mod:`agent.protocol.sense_format` and is re-exported here, so the pair is
imported from one place.
"""

from __future__ import annotations

import re
from collections.abc import Callable
from functools import partial

from agent.protocol.errors import ProtocolError
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
from agent.protocol.sense_format import format_sense
from agent.protocol.sense_tree import Perceptor, perceptor_from_tree
from agent.protocol.sexpr import ascii_text, read_located

# --- Fast-path patterns: the server's exact spelling; anything else takes the general path. -------------
_NUM = r"-?\d+(?:\.\d+)?"
_ATOM = r"[!-'*-~]+"
_F, _I, _N = rf"({_NUM})", r"(-?\d+)", rf"({_ATOM})"
_POL = rf"\(pol {_F} {_F} {_F}\)"
_POL_UNCAPTURED = rf"\(pol {_NUM} {_NUM} {_NUM}\)"

# Joints come in runs (hj1 hj2, then raj1 ... rlj5, ...): one match per run, one findall for its values.
_HJ_RUN = re.compile(rf"(?:\(HJ \(n {_ATOM}\) \(ax {_NUM}\)\))+")
_HJ_ITEM = re.compile(rf"\(HJ \(n {_N}\) \(ax {_F}\)\)")
_PREDICATE = re.compile(
    rf"\(FRP \(n {_N}\) \(c {_F} {_F} {_F}\) \(f {_F} {_F} {_F}\)\)"  # groups 1-7
    rf"|\(time \(now {_F}\)\)"  # 8
    rf"|\(GS (?:\(unum {_I}\) \(team {_N}\) )?\(sl {_I}\) \(sr {_I}\) \(t {_F}\) \(pm {_N}\)\)"  # 9-14
    rf"|\(GYR \(n {_N}\) \(rt {_F} {_F} {_F}\)\)"  # 15-18
    rf"|\(ACC \(n {_N}\) \(a {_F} {_F} {_F}\)\)"  # 19-22
    rf"|\(hear {_N} {_F} (self|{_NUM}) {_N}\)"  # 23-26
)
# Inside See, items of one kind also come in runs (objects, then players, then lines).
_LINE_RUN = re.compile(rf"(?: \(L {_POL_UNCAPTURED} {_POL_UNCAPTURED}\))+")
_OBJECT_RUN = re.compile(rf"(?: \((?!(?:L|P|mypos) ){_ATOM} {_POL_UNCAPTURED}\))+")
_NAMED_POLAR = re.compile(rf" \({_N} {_POL}\)")  # an object, or a player's part
_PLAYER = re.compile(rf" \(P \(team {_N}\)(?: \(id {_I}\))?((?: \({_ATOM} {_POL_UNCAPTURED}\))*)\)")
_MYPOS = re.compile(rf" \(mypos {_F} {_F} {_F}\)")
_NUMBER = re.compile(_NUM)

__all__ = ["format_sense", "parse_sense"]

_new_tuple = tuple.__new__
_new_polar = partial(tuple.__new__, Polar)
_new_line = partial(tuple.__new__, VisibleLine)
_EMPTY_SEE = See((), (), ())


def _fast_see(text: str, pos: int) -> tuple[See, int] | None:
    """The See predicate at ``text[pos:]`` (which starts ``(See``) and the offset after it, or None when
    it is not in the server's spelling (the general path then reads it)."""
    start = pos + 4
    if text.startswith(" )", start):
        return _EMPTY_SEE, start + 2
    objects: list[VisibleObject] = []
    players: list[VisiblePlayer] = []
    lines: list[VisibleLine] = []
    my_pos = None
    runs: list[str] = []
    i = start
    while True:
        m = _LINE_RUN.match(text, i)
        if m is not None:
            stop = m.end()
            values = iter(map(float, _NUMBER.findall(text, i, stop)))
            polars = map(_new_polar, zip(values, values, values))
            new_lines = list(map(_new_line, zip(polars, polars)))
            lines += new_lines
            runs.append(SEE_LINE * len(new_lines))
            i = stop
            continue
        m = _OBJECT_RUN.match(text, i)
        if m is not None:
            stop = m.end()
            new_objects = [
                _new_tuple(VisibleObject, (name, float(d), float(t), float(p)))
                for name, d, t, p in _NAMED_POLAR.findall(text, i, stop)
            ]
            objects += new_objects
            runs.append(SEE_OBJECT * len(new_objects))
            i = stop
            continue
        m = _PLAYER.match(text, i)
        if m is not None:
            team, unum, parts_text = m.group(1, 2, 3)
            found = _NAMED_POLAR.findall(parts_text)
            parts = {part: _new_polar((float(d), float(t), float(p))) for part, d, t, p in found}
            if len(parts) != len(found):
                return None  # a part named twice: the general path reports it
            players.append(VisiblePlayer(team, None if unum is None else int(unum), parts))
            runs.append(SEE_PLAYER)
            i = m.end()
            continue
        m = _MYPOS.match(text, i)
        if m is not None and my_pos is None:
            my_pos = (float(m[1]), float(m[2]), float(m[3]))
            runs.append(SEE_MYPOS)
            i = m.end()
            continue
        break
    if i == start or not text.startswith(")", i):
        return None
    return See(tuple(objects), tuple(players), tuple(lines), my_pos, "".join(runs)), i + 1


def _fast_frp(m: re.Match[str]) -> ForceResistance:
    a, b, c, d, e, f = map(float, m.group(2, 3, 4, 5, 6, 7))
    return ForceResistance(m[1], (a, b, c), (d, e, f))


def _fast_game_state(m: re.Match[str]) -> GameState:
    unum = m[9]
    return GameState(None if unum is None else int(unum), m[10], int(m[11]), int(m[12]), float(m[13]), m[14])


def _fast_hear(m: re.Match[str]) -> Hear:
    direction = m[25]
    return Hear(m[23], float(m[24]), None if direction == "self" else float(direction), m[26])


#: ``_PREDICATE`` match's ``lastindex`` (its last group, which tells the alternative) -> builder.
_FAST_BUILDERS: dict[int, Callable[[re.Match[str]], Perceptor]] = {
    7: _fast_frp,
    8: lambda m: TimePerceptor(float(m[8])),
    14: _fast_game_state,
    18: lambda m: Gyro(m[15], (float(m[16]), float(m[17]), float(m[18]))),
    22: lambda m: Accelerometer(m[19], (float(m[20]), float(m[21]), float(m[22]))),
    26: _fast_hear,
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


def parse_sense(data: bytes | str, *, fast_path: bool = True) -> Sense:
    """One sense message -> :class:`Sense`.

    Args:
        data: the frame payload (no length prefix).
        fast_path: False parses every predicate with the general reader (same result, ~5x slower); it
            exists so tests can cross-check the two paths.

    Returns:
        The typed message; unknown predicates are skipped and counted in ``Sense.unknown``.

    Raises:
        ProtocolError: malformed input (bad byte, unbalanced list, bad number, a known predicate with the
            wrong shape, a predicate or joint given twice, NaN/Inf), with its byte offset.
    """
    text = ascii_text(data)
    accumulator = _Accumulator()
    joints = accumulator.joints
    order = accumulator.order
    pos = 0
    end = len(text)
    while pos < end:
        if fast_path:
            m = _HJ_RUN.match(text, pos)
            if m is not None:
                stop = m.end()
                pairs = _HJ_ITEM.findall(text, pos, stop)
                count = len(joints) + len(pairs)
                for name, value in pairs:
                    joints[name] = float(value)
                if len(joints) != count:
                    return parse_sense(data, fast_path=False)  # raises, locating the repeated joint
                order += ["HJ"] * len(pairs)
                pos = stop
                continue
            if text.startswith("(See", pos):
                found = _fast_see(text, pos)
                if found is not None:
                    accumulator.add(found[0], pos, text)
                    pos = found[1]
                    continue
            else:
                m = _PREDICATE.match(text, pos)
                if m is not None:
                    accumulator.add(_FAST_BUILDERS[m.lastindex](m), pos, text)  # type: ignore[index]
                    pos = m.end()
                    continue
        nodes, pos_after = read_located(text, pos, limit=1)
        if not nodes:
            break  # only separators were left
        perceptor, unknown = perceptor_from_tree(nodes[0], text)
        accumulator.unknown += unknown
        if perceptor is not None:
            accumulator.add(perceptor, nodes[0].offset, text)
        pos = pos_after
    return accumulator.sense()
