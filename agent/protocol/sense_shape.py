"""Sense messages of a shape seen before, read by one compiled pattern per shape.

Why: a server sends each robot the same predicates in the same order every cycle (its joints and foot
sensors in the order of its body tree, vision every third cycle); only the numbers, which feet touch the
ground, the vision content and the hears change. So once the fast path of :mod:`agent.protocol.sense` has
parsed a message, its shape (the predicate order with every joint, foot and body name) becomes one regular
expression whose groups are the message's numbers: a later message of that shape is matched in one call and
its values are taken from the groups, almost all in C, instead of walking the predicates one by one.

The pattern spells each predicate exactly as the fast path's patterns do (numbers loosely; ``float`` checks
them and raises ValueError for the caller's general path), and the See predicate is read by the fast path's
own See reader, so both accept the same messages and give the same :class:`Sense`; tests check it on real
messages. A message that matches no known shape goes the usual way.
"""

from __future__ import annotations

import re
from collections.abc import Callable
from operator import itemgetter
from typing import Any

from agent.protocol.perceptors import (See, Sense, new_accelerometer, new_force_resistance, new_game_state, new_gyro,
                                       new_hear, new_sense, new_time)

#: Shapes kept at most (a server sends each robot a handful: vision or not, which feet touch, hears; the 22
#: agents of a match in one process share the cache, ~40-130 shapes of all their robot types); past it all go.
MAX_SHAPES = 256

_NUM = r"([-.0-9]++)"
_ATOM = r"([!-'*-~]++)"
_GS = rf"\(GS (?:\(unum (-?\d+)\) \(team {_ATOM}\) )?\(sl (-?\d+)\) \(sr (-?\d+)\) \(t {_NUM}\) \(pm {_ATOM}\)\)"
_HEAR = rf"\(hear {_ATOM} {_NUM} (self|[-.0-9]++) {_ATOM}\)"
_FRP_KEY = "(FRP"
_HEAR_KEY = "(hear"
_SEE_KEY = "(See"
_FIRST_FOOT = "(FRP (n "


def _key_of(text: str) -> tuple[int, int, bool, str]:
    """The `ShapeCache` key of a message: only a shape with this key can match it (see ShapeCache)."""
    foot = text.find(_FIRST_FOOT)
    first = "" if foot < 0 else text[foot + 8:text.find(")", foot + 8)]
    return (text.count(_FRP_KEY), text.count(_HEAR_KEY), _SEE_KEY in text, first)

SeeReader = Callable[[str, bytes, int], "tuple[See, int] | None"]


class _Shape:
    """One message shape: its pattern and where each perceptor's values are among the pattern's groups."""

    def __init__(self, sense: Sense) -> None:
        pieces: list[str] = []
        group = 0
        joint_names: list[str] = []
        joint_groups: list[int] = []
        self.frp: list[tuple[str, int]] = []
        self.hears: list[int] = []
        self.time = self.game_state = -1
        see_at = -1   # the See predicate splits the pattern in two; the fast path's See reader reads it
        self.gyro: tuple[str, int] | None = None
        self.acc: tuple[str, int] | None = None
        joints, feet = iter(sense.joints), iter(sense.frp)
        for kind in sense.order:
            if kind == "HJ":
                name = next(joints)
                pieces.append(rf"\(HJ \(n {re.escape(name)}\) \(ax {_NUM}\)\)")
                joint_names.append(name)
                joint_groups.append(group)
                group += 1
            elif kind == "FRP":
                name = next(feet)
                pieces.append(rf"\(FRP \(n {re.escape(name)}\) \(c {_NUM} {_NUM} {_NUM}\) \(f {_NUM} {_NUM} {_NUM}\)\)")
                self.frp.append((name, group))
                group += 6
            elif kind in ("GYR", "ACC"):
                reading = sense.gyro if kind == "GYR" else sense.acc
                assert reading is not None
                key = "rt" if kind == "GYR" else "a"
                pieces.append(rf"\({kind} \(n {re.escape(reading.name)}\) \({key} {_NUM} {_NUM} {_NUM}\)\)")
                if kind == "GYR":
                    self.gyro = (reading.name, group)
                else:
                    self.acc = (reading.name, group)
                group += 3
            elif kind == "time":
                pieces.append(rf"\(time \(now {_NUM}\)\)")
                self.time = group
                group += 1
            elif kind == "GS":
                pieces.append(_GS)
                self.game_state = group
                group += 6
            elif kind == "hear":
                pieces.append(_HEAR)
                self.hears.append(group)
                group += 4
            elif kind == "See":
                see_at = len(pieces)
            else:
                raise ValueError(f"no shape for {kind!r}")
        if see_at < 0:
            self.pattern, self.tail = re.compile("".join(pieces)), None
        else:
            self.pattern, self.tail = re.compile("".join(pieces[:see_at])), re.compile("".join(pieces[see_at:]))
        self.order = sense.order
        self.frp_count = len(self.frp)
        # (foot-pressure predicates, hear predicates, sees, name of the first foot-pressure predicate)
        self.key = (self.frp_count, len(self.hears), see_at >= 0, self.frp[0][0] if self.frp else "")
        self.joint_names = tuple(joint_names)
        # itemgetter of one index gives the item itself, not a 1-tuple.
        single = len(joint_groups) == 1
        getter = itemgetter(*joint_groups) if joint_groups else (lambda groups: ())
        self.joint_values: Callable[[tuple[Any, ...]], Any] = (
            (lambda groups: (groups[joint_groups[0]],)) if single else getter)

    def read(self, text: str, raw: bytes, see_reader: SeeReader) -> Sense | None:
        """The Sense of ``text`` if it has this shape, else None.

        Raises:
            ValueError: a number ``float`` refuses (the caller's general path then locates it).
        """
        see = None
        if self.tail is None:
            m = self.pattern.fullmatch(text)
            if m is None:
                return None
            g = m.groups()
        else:   # the predicates before the See, the See, then the rest
            m = self.pattern.match(text)
            if m is None:
                return None
            found = see_reader(text, raw, m.end())
            if found is None:
                return None
            see, end = found
            rest = self.tail.fullmatch(text, end)
            if rest is None:
                return None
            g = m.groups() + rest.groups()
        i = self.game_state
        game_state = None
        if i >= 0:
            unum = g[i]
            game_state = new_game_state(None if unum is None else int(unum), g[i + 1], int(g[i + 2]),
                                        int(g[i + 3]), float(g[i + 4]), g[i + 5])
        gyro = acc = None
        if self.gyro is not None:
            name, i = self.gyro
            gyro = new_gyro(name, (float(g[i]), float(g[i + 1]), float(g[i + 2])))
        if self.acc is not None:
            name, i = self.acc
            acc = new_accelerometer(name, (float(g[i]), float(g[i + 1]), float(g[i + 2])))
        frp = {}
        for name, i in self.frp:
            frp[name] = new_force_resistance(name, (float(g[i]), float(g[i + 1]), float(g[i + 2])),
                                             (float(g[i + 3]), float(g[i + 4]), float(g[i + 5])))
        hears = []
        for i in self.hears:
            direction = g[i + 2]
            hears.append(new_hear(g[i], float(g[i + 1]), None if direction == "self" else float(direction),
                                  g[i + 3]))
        return new_sense(None if self.time < 0 else new_time(float(g[self.time])), game_state, gyro, acc,
                         dict(zip(self.joint_names, map(float, self.joint_values(g)))), frp, tuple(hears), see, None,
                         0, self.order)


class ShapeCache:
    """The shapes of the messages parsed so far, looked up by their numbers of foot-pressure and hear predicates,
    whether they see and the name of their first foot-pressure predicate (the parts of a shape that change
    deep inside a message, where a failed match would cost most). Those substrings occur in a message only as
    its predicates (atoms hold no parentheses), so a shape of another key could never match it: the lookup
    only skips tries that would fail.

    Args:
        see_reader: the fast path's See reader: (text, raw bytes, offset of ``(See``) -> (See, offset after
            it), or None when it does not recognise the predicate.
    """

    def __init__(self, see_reader: SeeReader) -> None:
        self.see_reader = see_reader
        self._by_key: dict[tuple[int, int, bool, str], list[_Shape]] = {}
        self._count = 0

    def parse(self, text: str, raw: bytes) -> Sense | None:
        """The Sense of a message of a known shape, else None.

        Raises:
            ValueError: a number ``float`` refuses.
        """
        for shape in self._by_key.get(_key_of(text), ()):
            sense = shape.read(text, raw, self.see_reader)
            if sense is not None:
                return sense
        return None

    def learn(self, sense: Sense) -> None:
        """Remember the shape of a message the fast path parsed (its ``order`` lists every predicate)."""
        if self._count >= MAX_SHAPES:
            self._by_key.clear()
            self._count = 0
        shape = _Shape(sense)
        self._by_key.setdefault(shape.key, []).append(shape)
        self._count += 1
