"""Sense messages: ``parse_sense`` (agent side) and ``format_sense`` (our server), byte-exact with 0.7.3.

Parsing runs every 20 ms in every agent, so it has a fast path: compiled patterns for the server's exact
spelling of each predicate (``(HJ (n llj4) (ax -61.93))``: one space inside a predicate, none between
predicates), tried at each predicate start, with the values taken straight from the match groups. Runs of
one kind (joints, vision objects, lines) are matched at once and their values extracted in bulk, since per
item Python work is what costs. Any message the fast path does not fully recognise (an unknown predicate,
other spacing, a duplicate, a bad number, a malformed message) is parsed again by the general path,
:mod:`agent.protocol.sense_tree`, which gives the same values, skips and counts unknown expressions, and
raises a ProtocolError at the offending byte. The tests check both paths agree on every real message.

Before the fast path, a message whose shape (predicates, order and names) was parsed before is read by that
shape's single pattern (:mod:`agent.protocol.sense_shape`): the same result, without walking the predicates.

``format_sense`` lives in :mod:`agent.protocol.sense_format` and is re-exported here.
"""

from __future__ import annotations

import re
from functools import partial

from agent.protocol.perceptors import (
    SEE_LINE,
    SEE_MYPOS,
    SEE_OBJECT,
    SEE_PLAYER,
    ForceResistance,
    Hear,
    Polar,
    See,
    Sense,
    VisibleLine,
    VisibleObject,
    VisiblePlayer,
    new_accelerometer,
    new_force_resistance,
    new_game_state,
    new_gyro,
    new_hear,
    new_see,
    new_sense,
    new_time,
    new_visible_player,
)
from agent.protocol.sense_format import format_sense
from agent.protocol.sense_shape import ShapeCache
from agent.protocol.sense_tree import parse_sense_general
from agent.protocol.sexpr import ascii_text

__all__ = ["format_sense", "parse_sense"]

# --- Fast-path patterns ---------------------------------------------------------------------------------
# Numbers are matched loosely ([-.0-9]+) because float() then checks them: a token float() refuses raises
# ValueError and the general path reports it. For these characters float() and the strict parser of
# numbers.py accept the same tokens. Once a run of joints, objects or lines has matched, its names and
# numbers are cut out with str/bytes operations and converted with map/zip, all in C: per-item Python work
# is what costs on the agent's 20 ms cycle.
_NUM = r"[-.0-9]++"  # possessive: a token always ends at a space or ')', so never backtrack into it
_ATOM = r"[!-'*-~]++"
_F, _I, _N = rf"({_NUM})", r"(-?\d+)", rf"({_ATOM})"
_POL_UNCAPTURED = rf"\(pol {_NUM} {_NUM} {_NUM}\)"

_HJ_RUN = re.compile(rf"(?:\(HJ \(n {_ATOM}\) \(ax {_NUM}\)\))++")
#: First three characters of a predicate -> (its pattern, its name).
_SIMPLE: dict[str, tuple[re.Pattern[str], str]] = {
    "(FR": (re.compile(rf"\(FRP \(n {_N}\) \(c {_F} {_F} {_F}\) \(f {_F} {_F} {_F}\)\)"), "FRP"),
    "(ti": (re.compile(rf"\(time \(now {_F}\)\)"), "time"),
    "(GS": (
        re.compile(rf"\(GS (?:\(unum {_I}\) \(team {_N}\) )?\(sl {_I}\) \(sr {_I}\) \(t {_F}\) \(pm {_N}\)\)"),
        "GS",
    ),
    "(GY": (re.compile(rf"\(GYR \(n {_N}\) \(rt {_F} {_F} {_F}\)\)"), "GYR"),
    "(AC": (re.compile(rf"\(ACC \(n {_N}\) \(a {_F} {_F} {_F}\)\)"), "ACC"),
    "(he": (re.compile(rf"\(hear {_N} {_F} (self|{_NUM}) {_N}\)"), "hear"),
}
# Lines hold no names, so their run is matched on the bytes (about a third faster than on str here).
_LINE_RUN = re.compile(rf"(?: \(L {_POL_UNCAPTURED} {_POL_UNCAPTURED}\))++".encode())
_OBJECT_RUN = re.compile(rf"(?: \((?!(?:L|P|mypos) ){_ATOM} {_POL_UNCAPTURED}\))++")
_PLAYER = re.compile(rf" \(P \(team {_N}\)(?: \(id {_I}\))?((?: \({_ATOM} {_POL_UNCAPTURED}\))*+)\)")
_MYPOS = re.compile(rf" \(mypos {_F} {_F} {_F}\)")
#: Deleting these bytes from a run of lines leaves its 6 numbers per line, separated by spaces.
_LINE_SYNTAX_BYTES = b"(Lpol)"

_new_polar = partial(tuple.__new__, Polar)
_new_line = partial(tuple.__new__, VisibleLine)
_new_object = partial(tuple.__new__, VisibleObject)
_EMPTY_SEE = See((), (), ())


def parse_sense(data: bytes | str, *, fast_path: bool = True) -> Sense:
    """One sense message -> :class:`Sense`.

    Args:
        data: the frame payload (no length prefix).
        fast_path: False skips the fast path (same result, slower); it exists so tests can cross-check.

    Returns:
        The typed message; unknown predicates are skipped and counted in ``Sense.unknown``.

    Raises:
        ProtocolError: malformed input (bad byte, unbalanced list, bad number, a known predicate with the
            wrong shape, a predicate or joint given twice, NaN/Inf), with its byte offset.
    """
    if fast_path:
        # No byte check first: the fast path's patterns admit only printable ASCII and spaces and must cover
        # the whole message, so a message it accepts is clean (latin-1 decoding cannot fail or hide a byte).
        if isinstance(data, bytes):
            text, raw = data.decode("latin-1"), data
        else:
            text, raw = data, data.encode("latin-1", "replace")
        try:
            # A message of a shape parsed before is read by that shape's one pattern (sense_shape).
            sense = _SHAPES.parse(text, raw)
            if sense is None:
                sense = _parse_fast(text, raw)
                if sense is not None:
                    _SHAPES.learn(sense)
        except ValueError:  # a number float() refused
            sense = None
        if sense is not None:
            return sense
    return parse_sense_general(ascii_text(data))


def _parse_fast(text: str, raw: bytes) -> Sense | None:
    """The Sense of a message in the server's exact spelling, or None for the general path to parse.

    Raises:
        ValueError: a number token float() refuses (the general path then locates it).
    """
    joints: dict[str, float] = {}
    frp: dict[str, ForceResistance] = {}
    hears: list[Hear] = []
    order: list[str] = []
    time = game_state = gyro = acc = see = None
    joint_count = 0
    pos = 0
    end = len(text)
    while pos < end:
        head = text[pos : pos + 3]
        if head == "(HJ":
            m = _HJ_RUN.match(text, pos)
            if m is None:
                return None
            stop = m.end()
            # "(HJ (n a) (ax 1.00))(HJ (n b) (ax 2.00))" -> "a 1.00 b 2.00": names and values alternate.
            tokens = text[pos + 7 : stop - 2].replace(") (ax ", " ").replace("))(HJ (n ", " ").split(" ")
            values = iter(tokens)
            joints.update(zip(values, map(float, values)))
            count = len(tokens) // 2
            joint_count += count
            order += ["HJ"] * count
            pos = stop
            continue
        if head == "(Se":
            found = _fast_see(text, raw, pos)
            if found is None or see is not None:
                return None
            see, pos = found
            order.append("See")
            continue
        entry = _SIMPLE.get(head)
        m = None if entry is None else entry[0].match(text, pos)
        if m is None:
            return None
        kind = entry[1]  # type: ignore[index]
        if kind == "FRP":
            name = m[1]
            if name in frp:
                return None
            a, b, c, d, e, f = map(float, m.group(2, 3, 4, 5, 6, 7))
            frp[name] = new_force_resistance(name, (a, b, c), (d, e, f))
        elif kind == "hear":
            direction = m[3]
            hears.append(new_hear(m[1], float(m[2]), None if direction == "self" else float(direction), m[4]))
        elif kind == "time":
            if time is not None:
                return None
            time = new_time(float(m[1]))
        elif kind == "GS":
            if game_state is not None:
                return None
            unum = m[1]
            game_state = new_game_state(
                None if unum is None else int(unum), m[2], int(m[3]), int(m[4]), float(m[5]), m[6]
            )
        elif kind == "GYR":
            if gyro is not None:
                return None
            gyro = new_gyro(m[1], (float(m[2]), float(m[3]), float(m[4])))
        else:
            if acc is not None:
                return None
            acc = new_accelerometer(m[1], (float(m[2]), float(m[3]), float(m[4])))
        order.append(kind)
        pos = m.end()
    if len(joints) != joint_count:
        return None  # a joint given twice
    return new_sense(time, game_state, gyro, acc, joints, frp, tuple(hears), see, None, 0, tuple(order))


def _fast_see(text: str, raw: bytes, pos: int) -> tuple[See, int] | None:
    """The See predicate at ``text[pos:]`` (which starts ``(Se``) and the offset after it, or None."""
    if not text.startswith("(See", pos):
        return None
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
        # Each item starts " (": the next character tells the kind, so only one pattern is tried.
        kind = text[i + 2 : i + 4]
        if kind == "L ":
            line_run = _LINE_RUN.match(raw, i)
            if line_run is None:
                return None
            stop = line_run.end()
            numbers = iter(map(float, raw[i:stop].translate(None, _LINE_SYNTAX_BYTES).split()))
            polars = map(_new_polar, zip(numbers, numbers, numbers))
            new_lines = list(map(_new_line, zip(polars, polars)))
            lines += new_lines
            runs.append(SEE_LINE * len(new_lines))
        elif kind == "P ":
            m = _PLAYER.match(text, i)
            if m is None:
                return None
            stop = m.end()
            team, unum, parts_text = m.group(1, 2, 3)
            part_tokens = iter(parts_text[2:-2].replace(" (pol ", " ").replace(")) (", " ").split(" "))
            floats = map(float, part_tokens)
            parts = dict(zip(part_tokens, map(_new_polar, zip(floats, floats, floats))))
            if len(parts) != parts_text.count("(pol "):
                return None  # a part named twice
            players.append(new_visible_player(team, None if unum is None else int(unum), parts))
            runs.append(SEE_PLAYER)
        elif kind == "my":
            m = _MYPOS.match(text, i)
            if m is None or my_pos is not None:
                return None
            stop = m.end()
            my_pos = (float(m[1]), float(m[2]), float(m[3]))
            runs.append(SEE_MYPOS)
        else:
            m = _OBJECT_RUN.match(text, i)
            if m is None:
                break
            stop = m.end()
            # " (B (pol 1.00 2.00 3.00)) (F1L (pol ...))" -> "B 1.00 2.00 3.00 F1L ...".
            tokens = iter(text[i + 2 : stop - 2].replace(" (pol ", " ").replace(")) (", " ").split(" "))
            new_objects = list(map(_new_object, zip(tokens, map(float, tokens), map(float, tokens),
                                                    map(float, tokens))))
            objects += new_objects
            runs.append(SEE_OBJECT * len(new_objects))
        i = stop
    if i == start or not text.startswith(")", i):
        return None
    return new_see(tuple(objects), tuple(players), tuple(lines), my_pos, "".join(runs)), i + 1


#: Shapes of the messages parsed so far (see agent.protocol.sense_shape).
_SHAPES = ShapeCache(_fast_see)
