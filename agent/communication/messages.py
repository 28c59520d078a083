"""Team messages (REFERENCE §7.9 types i, s, c, l, b, x, e, a) in a compact fixed-width code, ≤ 20 characters.

Why not the thesis' ``c,4,-3,2,1,0``: whole metres and decimal text spend the 20 characters badly. Here
every value is a fixed number of base-88 digits, so a message needs no separators and positions keep
centimetres:

* alphabet: the 88 printable ASCII characters 0x21-0x7E except ``( ) ' " \\ ;`` (the server rejects space
  and parentheses, REFERENCE §3.8; the quotes, backslash and semicolon are avoided as FC Portugal does);
* a message is ``<type><unum digit><fields><check digit>``;
* fields: coordinate = 2 digits, centimetres + 3872 (±38.7 m); distance = 2 digits, centimetres (0-77.4 m);
  angle = 2 digits, tenths of a degree + 1800 (−180.0…180.0); action id = 1 digit;
* check digit = CRC-32 of (team name + message body) mod 88: a message from another team (which may use
  this code too) or a garbled one fails the check and is ignored.

Layouts (unum = the sender, except in ``a`` where it is the player the action is for):

| type | fields | length |
|---|---|---|
| i, s, e, x | – | 3 |
| l | x, y (self) | 7 |
| b | ball distance, ball angle (ego, left positive) | 7 |
| c | x, y (self), bx, by (ball) | 11 |
| a | action id, p1, p2 (coordinates), p3 (angle) | 10 |
"""

from __future__ import annotations

import math
import zlib
from dataclasses import dataclass

from agent.errors import MessageError

MAX_LENGTH = 20
ALPHABET = "".join(chr(c) for c in range(0x21, 0x7F) if chr(c) not in "()'\"\\;")
BASE = len(ALPHABET)  # 88
_VALUE = {ch: i for i, ch in enumerate(ALPHABET)}
_TWO_DIGITS = BASE * BASE  # 7744
COORD_OFFSET_CM = _TWO_DIGITS // 2  # 3872
ANGLE_OFFSET_DECIDEG = 1800

#: Type letter -> field kinds, in order (``p`` coordinate, ``d`` distance, ``a`` angle, ``n`` one digit).
LAYOUTS: dict[str, str] = {"i": "", "s": "", "e": "", "x": "", "l": "pp", "b": "da", "c": "pppp", "a": "nppa"}
#: Action ids of the 2012 code (REFERENCE §7.9).
ACTIONS = {1: "GoKickBallToGoal", 2: "ClearBall", 3: "WalkToDirection", 4: "WalkToCoordinate", 5: "TurnToLocate"}


@dataclass(frozen=True, slots=True)
class TeamMessage:
    """One decoded team message; unused fields are None."""

    kind: str
    """Type letter: i, s, c, l, b, x, e, a."""
    unum: int
    """Sender (the addressee for ``a``)."""
    position: tuple[float, float] | None = None
    """Sender's team-frame (x, y) [m] (c, l)."""
    ball: tuple[float, float] | None = None
    """Ball team-frame (x, y) [m] (c)."""
    ball_distance_m: float | None = None
    """Ball ground distance from the sender [m] (b)."""
    ball_angle_rad: float | None = None
    """Ball direction from the sender, ego, left positive [rad] (b)."""
    action: tuple[int, float, float, float] | None = None
    """(action id, p1 [m], p2 [m], p3 [rad]) (a)."""


def _digits(value: int, count: int, what: str) -> str:
    if not 0 <= value < BASE ** count:
        raise MessageError(f"{what} out of range: encoded value {value} needs more than {count} digit(s)",
                           field=what)
    out = []
    for _ in range(count):
        value, digit = divmod(value, BASE)
        out.append(ALPHABET[digit])
    return "".join(reversed(out))


def _number(text: str) -> int:
    value = 0
    for ch in text:
        value = value * BASE + _VALUE[ch]
    return value


def _check(team: str, body: str) -> str:
    return ALPHABET[zlib.crc32((team + "/" + body).encode("ascii")) % BASE]


def _field_values(message: TeamMessage) -> list[float]:
    kind = message.kind
    if kind == "l":
        return list(_need(message.position, "position"))
    if kind == "c":
        return list(_need(message.position, "position")) + list(_need(message.ball, "ball"))
    if kind == "b":
        return [_need(message.ball_distance_m, "ball_distance_m"), _need(message.ball_angle_rad, "ball_angle_rad")]
    if kind == "a":
        return list(_need(message.action, "action"))
    return []


def _need(value, name: str):  # type: ignore[no-untyped-def]
    if value is None:
        raise MessageError(f"message field {name} is required for this type", field=name)
    return value


def encode(message: TeamMessage, team: str) -> str:
    """The say text for ``message``.

    Args:
        message: what to say.
        team: own team name (salts the check digit).

    Returns:
        3-11 characters of :data:`ALPHABET`.

    Raises:
        MessageError: unknown type, a missing field, a value out of range, or (never expected) a result
            longer than 20 characters.
    """
    layout = LAYOUTS.get(message.kind)
    if layout is None:
        raise MessageError(f"unknown message type {message.kind!r}; known: {', '.join(LAYOUTS)}", field="kind")
    parts = [message.kind, _digits(message.unum, 1, "unum")]
    for kind, value in zip(layout, _field_values(message), strict=True):
        if not math.isfinite(value):
            raise MessageError(f"non-finite value {value!r} in a {message.kind} message", field=kind)
        if kind == "p":
            parts.append(_digits(round(value * 100.0) + COORD_OFFSET_CM, 2, "coordinate"))
        elif kind == "d":
            parts.append(_digits(round(value * 100.0), 2, "distance"))
        elif kind == "a":
            decideg = round(math.degrees(math.remainder(value, 2.0 * math.pi)) * 10.0)
            parts.append(_digits(decideg + ANGLE_OFFSET_DECIDEG, 2, "angle"))
        else:
            parts.append(_digits(int(value), 1, "action id"))
    body = "".join(parts)
    text = body + _check(team, body)
    if len(text) > MAX_LENGTH:  # a layout bug, not input: the server would drop it silently
        raise MessageError(f"team message {text!r} is {len(text)} characters, over {MAX_LENGTH}", field="kind")
    return text


_WIDTH = {"p": 2, "d": 2, "a": 2, "n": 1}


def decode(text: str, team: str) -> TeamMessage:
    """A heard text back into a :class:`TeamMessage`.

    Args:
        text: the heard message.
        team: own team name (the check digit must match it).

    Raises:
        MessageError: not one of our messages (unknown type, wrong length, a character outside the alphabet,
            a failed check digit).
    """
    if len(text) < 3 or len(text) > MAX_LENGTH:
        raise MessageError(f"team message {text!r}: length {len(text)} is not ours", field="length")
    layout = LAYOUTS.get(text[0])
    if layout is None:
        raise MessageError(f"team message {text!r}: unknown type {text[0]!r}", field="kind")
    if len(text) != 3 + sum(_WIDTH[k] for k in layout):
        raise MessageError(f"team message {text!r}: wrong length for type {text[0]}", field="length")
    if any(ch not in _VALUE for ch in text):
        raise MessageError(f"team message {text!r}: character outside the alphabet", field="text")
    body = text[:-1]
    if _check(team, body) != text[-1]:
        raise MessageError(f"team message {text!r}: check digit fails for team {team!r}", field="check")
    values: list[float] = []
    pos = 2
    for kind in layout:
        raw = _number(text[pos:pos + _WIDTH[kind]])
        pos += _WIDTH[kind]
        if kind == "p":
            values.append((raw - COORD_OFFSET_CM) / 100.0)
        elif kind == "d":
            values.append(raw / 100.0)
        elif kind == "a":
            values.append(math.radians((raw - ANGLE_OFFSET_DECIDEG) / 10.0))
        else:
            values.append(float(raw))
    kind, unum = text[0], _VALUE[text[1]]
    if kind == "l":
        return TeamMessage(kind, unum, position=(values[0], values[1]))
    if kind == "c":
        return TeamMessage(kind, unum, position=(values[0], values[1]), ball=(values[2], values[3]))
    if kind == "b":
        return TeamMessage(kind, unum, ball_distance_m=values[0], ball_angle_rad=values[1])
    if kind == "a":
        return TeamMessage(kind, unum, action=(int(values[0]), values[1], values[2], values[3]))
    return TeamMessage(kind, unum)
