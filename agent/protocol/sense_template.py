"""Our server's sense messages from flat values: one precompiled printf template per message shape.

Why: the server writes one message per robot every 20 ms, and writing them value by value from a `Sense` of
dataclasses (`format_sense`) cost the 22-robot simulator more than its physics. A robot's message has a
fixed shape up to a few switches: its type fixes the joint and foot-sensor names, and each cycle only
decides which feet touch the ground, whether it sees and how many messages it hears. For each shape the
predicate order comes from `sense_format.server_layout` and every spelling from `sense_format`'s
templates, so this module defines neither; the values then go through one ``bytes % tuple``, in C.
tests/agent/test_protocol_sense_template.py checks it writes `format_sense`'s bytes for every shape.

The See predicate's content varies too much for one template per shape; the vision writer (sim.vision)
assembles it from the item templates here (`object_template`, `player_template`, `part_template`,
`line_template`) and hands it over as bytes.

Every template takes its numbers either as floats (``number=PRINTF_NUMBER``, printf writes them) or as
their spellings written beforehand (``number=SPELLED_NUMBER``: bytes from `numbers.fixed2_table`, which a
writer of many values at once looks up instead of formatting each).
"""

from __future__ import annotations

from collections.abc import Sequence
from operator import itemgetter

from agent.protocol.errors import ProtocolError
from agent.protocol.numbers import FIXED2
from agent.protocol.perceptors import (Accelerometer, ForceResistance, GameState, Gyro, Hear, See, Sense,
                                       TimePerceptor)
from agent.protocol.sense_format import (ACC, FRP, GYR, HJ, LINE, OBJECT, PART, PLAYER_CLOSE, PLAYER_ID,
                                         PLAYER_OPEN, SEE_CLOSE, SEE_OPEN, SEE_SEPARATOR, TIME, check_atoms,
                                         game_state_text, hear_text, server_layout)

#: Number placeholders of the templates: floats for printf, or spellings (bytes) written beforehand.
PRINTF_NUMBER, SPELLED_NUMBER = FIXED2, "%s"
#: The See predicate's frame and separators, and a field line's item (six values: both ends' d, θ, φ).
SEE_OPEN_BYTES = SEE_OPEN.encode("ascii")
SEE_SEPARATOR_BYTES = SEE_SEPARATOR.encode("ascii")
SEE_CLOSE_BYTES = SEE_CLOSE.encode("ascii")
PLAYER_CLOSE_BYTES = PLAYER_CLOSE.encode("ascii")
LINE_TEMPLATE = LINE.encode("ascii")
# Slots of the parts written beforehand at the front of the pool `SenseTemplate.format` picks from; the hears
# follow, then the floats (so a caller's row may carry padding after them).
_TIME_SLOT, _GS_SLOT, _SEE_SLOT, _HEAR_SLOT = range(4)
_ZERO3 = (0.0, 0.0, 0.0)


def _with_name(template: str, name: str, number: str = PRINTF_NUMBER) -> str:
    """``template`` with its numbers' placeholders made ``number`` and then its first ``%s`` (always the name)
    replaced by ``name``, a ``%`` in the name escaped, for later ``%``."""
    check_atoms([name], template)
    return template.replace(FIXED2, number).replace("%s", name.replace("%", "%%"), 1)


def object_template(name: str, number: str = PRINTF_NUMBER) -> bytes:
    """A vision object item (``(F1L (pol d θ φ))``) as a template of its three values.

    Raises:
        ProtocolError: ``name`` is not an atom.
    """
    return _with_name(OBJECT, name, number).encode("ascii")


def player_template(team: str, unum: int | None) -> bytes:
    """The opening of a vision player item (``(P (team T) (id N)``), with no values; parts and
    `PLAYER_CLOSE_BYTES` follow.

    Raises:
        ProtocolError: ``team`` is not an atom.
    """
    check_atoms([team], PLAYER_OPEN)
    text = PLAYER_OPEN % team + ("" if unum is None else PLAYER_ID % unum)
    return text.replace("%", "%%").encode("ascii")


def part_template(name: str, number: str = PRINTF_NUMBER) -> bytes:
    """One visible part of a player (`` (head (pol d θ φ))``, leading space included), three values.

    Raises:
        ProtocolError: ``name`` is not an atom.
    """
    return _with_name(PART, name, number).encode("ascii")


def line_template(number: str = PRINTF_NUMBER) -> bytes:
    """A field line item (``(L (pol d θ φ) (pol d θ φ))``), six values."""
    return LINE.replace(FIXED2, number).encode("ascii")


def time_bytes(now_s: float) -> bytes:
    """The ``(time (now F))`` predicate."""
    return (TIME % (now_s,)).encode("ascii")


def game_state_bytes(state: GameState) -> bytes:
    """The ``(GS ...)`` predicate.

    Raises:
        ProtocolError: the team or play mode is not an atom.
    """
    atoms: list[str] = []
    text = game_state_text(state, atoms)
    check_atoms(atoms, text)
    return text.encode("ascii")


def hear_bytes(hear: Hear) -> bytes:
    """One ``(hear ...)`` predicate.

    Raises:
        ProtocolError: the team or message is not an atom.
    """
    atoms: list[str] = []
    text = hear_text(hear, atoms)
    check_atoms(atoms, text)
    return text.encode("ascii")


class SenseTemplate:
    """The sense messages of one robot type, written from flat values.

    Args:
        joints: wire joint names in the server's order (the order the angles come in).
        foot_sensors: the robot's FRP sensor names (``rf``, ``lf``, and ``rf1``, ``lf1`` on type 4).
        gyro_name / acc_name: bodies of the gyro and the accelerometer.
        number: `PRINTF_NUMBER` (values are floats) or `SPELLED_NUMBER` (values are their spellings).

    Raises:
        ProtocolError: a name is not an atom.
    """

    def __init__(self, joints: Sequence[str], foot_sensors: Sequence[str], gyro_name: str = "torso",
                 acc_name: str = "torso", number: str = PRINTF_NUMBER) -> None:
        self.number = number
        self.joints = tuple(joints)
        self.foot_sensors = tuple(foot_sensors)
        self.gyro_name = gyro_name
        self.acc_name = acc_name
        check_atoms([*self.joints, *self.foot_sensors, gyro_name, acc_name], "")
        self.value_count = 6 + len(self.joints) + 6 * len(self.foot_sensors)
        """Floats `format` takes: gyro 3, accelerometer 3, one per joint, 6 per foot sensor."""
        self._shapes: dict[tuple[int, bool, int], tuple[bytes, itemgetter]] = {}  # type: ignore[type-arg]

    def format(self, values: list[float], time: bytes, game_state: bytes, frp_mask: int = 0,
               see: bytes | None = None, hears: Sequence[bytes] = ()) -> bytes:
        """One sense message (frame payload).

        Args:
            values: `value_count` floats, or their spellings (more are ignored): gyro rate x, y, z [deg/s];
                acceleration x, y, z [m/s²]; the joint angles [deg] in `joints` order; then per foot sensor in
                `foot_sensors` order its contact point x, y, z [m] and force x, y, z [N] (ignored for sensors
                not in ``frp_mask``).
            time, game_state: `time_bytes` and `game_state_bytes` of this cycle.
            frp_mask: bit i set = ``foot_sensors[i]`` has contact (its FRP is sent).
            see: the See predicate (from the vision writer), or None in a cycle without vision.
            hears: `hear_bytes` of this cycle's messages, in order.
        """
        shape = self._shapes.get((frp_mask, see is not None, len(hears)))
        if shape is None:
            shape = self._shapes[(frp_mask, see is not None, len(hears))] = self._build(
                frp_mask, see is not None, len(hears))
        template, pick = shape
        return template % pick([time, game_state, see, *hears, *values])

    def _build(self, frp_mask: int, has_see: bool,
               hear_count: int) -> tuple[bytes, itemgetter]:  # type: ignore[type-arg]
        """The template of one shape and the picker of its values from the pool `format` builds."""
        active = [name for i, name in enumerate(self.foot_sensors) if frp_mask >> i & 1]
        sample = Sense(TimePerceptor(0.0), GameState(None, None, 0, 0, 0.0, "BeforeKickOff"),
                       Gyro(self.gyro_name, _ZERO3), Accelerometer(self.acc_name, _ZERO3),
                       dict.fromkeys(self.joints, 0.0),
                       {name: ForceResistance(name, _ZERO3, _ZERO3) for name in active},
                       tuple(Hear(None, 0.0, None, "x") for _ in range(hear_count)),
                       See((), (), ()) if has_see else None)
        order, frps = server_layout(sample)
        joint_count, first = len(self.joints), _HEAR_SLOT + hear_count   # first: pool index of the floats
        pieces: list[str] = []
        picks: list[int] = []
        joints, feet, hears = iter(range(joint_count)), iter(frps), iter(range(hear_count))
        for kind in order:
            if kind == "HJ":
                index = next(joints)
                pieces.append(_with_name(HJ, self.joints[index], self.number))
                picks.append(first + 6 + index)
            elif kind == "FRP":
                name = next(feet).name
                start = first + 6 + joint_count + 6 * self.foot_sensors.index(name)
                pieces.append(_with_name(FRP, name, self.number))
                picks.extend(range(start, start + 6))
            elif kind == "GYR":
                pieces.append(_with_name(GYR, self.gyro_name, self.number))
                picks.extend((first, first + 1, first + 2))
            elif kind == "ACC":
                pieces.append(_with_name(ACC, self.acc_name, self.number))
                picks.extend((first + 3, first + 4, first + 5))
            elif kind in ("time", "GS", "See", "hear"):
                pieces.append("%s")
                slot = {"time": _TIME_SLOT, "GS": _GS_SLOT, "See": _SEE_SLOT}.get(kind)
                picks.append(slot if slot is not None else _HEAR_SLOT + next(hears))
            else:
                raise ProtocolError(f"the sense template has no slot for {kind!r}", 0, b"")
        return "".join(pieces).encode("ascii"), itemgetter(*picks)
