"""``format_sense``: the exact bytes rcssserver3d 0.7.3 sends for a :class:`Sense` (used by our server).

Follows SimSpark's ``SexpParser``: ``(name`` + space + items joined by one space + ``)``, predicates
concatenated with no separator, so an empty vision frame is ``(See )``; floats ``%.2f`` (with ``-0.00``),
ints as ints (REFERENCE §1, §3.1). A parsed Sense carries its wire order and is written back byte for byte;
a Sense built with ``order=()`` is written in the server's own order (REFERENCE §3.3). The one byte
difference left: a NaN is written ``nan`` even where glibc would write ``-nan`` (a server that sends NaN is
broken either way).
"""

from __future__ import annotations

import re

from agent.protocol.errors import ProtocolError
from agent.protocol.perceptors import (
    SEE_LINE,
    SEE_MYPOS,
    SEE_OBJECT,
    SEE_PLAYER,
    AgentState,
    ForceResistance,
    GameState,
    Hear,
    See,
    Sense,
)

#: Where each foot sensor goes in the server's order: before the joint that follows its body in the scene
#: graph (REFERENCE §3.3: ``rlj5, FRP rf, rlj6``). The toe sensors of type 4 are placed by analogy
#: (unverified: no type-4 sample yet).
_FRP_BEFORE_JOINT = {"rf": "rlj6", "lf": "llj6", "rf1": "rlj7", "lf1": "llj7"}
#: Vision comes right after the head joints (the camera sits on the head).
_SEE_AFTER_JOINT = "hj2"


def server_layout(sense: Sense) -> tuple[list[str], list[ForceResistance]]:
    """The predicate order rcssserver3d uses for ``sense``'s content (REFERENCE §3.3), and the FRPs in it.

    ``time``, ``GS``, the hears, ``GYR``, ``ACC``, then the joints in ``sense.joints`` order with ``See``
    after ``hj2`` and each FRP before the joint that follows its foot; ``AgentState`` last. Anything without
    its anchor (a See without ``hj2``, an FRP of another name) follows the joints.

    Returns:
        (predicate names in order, the FRPs in the order their ``FRP`` entries appear).
    """
    order: list[str] = []
    if sense.time is not None:
        order.append("time")
    if sense.game_state is not None:
        order.append("GS")
    order += ["hear"] * len(sense.hears)
    if sense.gyro is not None:
        order.append("GYR")
    if sense.acc is not None:
        order.append("ACC")
    frp_at_joint: dict[str, ForceResistance] = {}
    leftover: list[ForceResistance] = []  # FRPs without their anchor joint, or of an unknown name: after the joints
    for name, frp in sense.frp.items():
        anchor = _FRP_BEFORE_JOINT.get(name)
        if anchor is not None and anchor in sense.joints:
            frp_at_joint[anchor] = frp
        else:
            leftover.append(frp)
    frps: list[ForceResistance] = []
    see_pending = sense.see is not None
    for joint in sense.joints:
        if joint in frp_at_joint:
            order.append("FRP")
            frps.append(frp_at_joint[joint])
        order.append("HJ")
        if see_pending and joint == _SEE_AFTER_JOINT:
            order.append("See")
            see_pending = False
    order += ["FRP"] * len(leftover)
    frps += leftover
    if see_pending:
        order.append("See")
    if sense.agent_state is not None:
        order.append("AgentState")
    return order, frps


# Spellings of the predicates as printf templates: the one definition, used here value by value and by
# agent.protocol.sense_template for whole messages at once. "%.2f" is done in C, far cheaper per value
# than a Python call, and gives the same digits as the server's printf (Python writes every NaN "nan").
HJ = "(HJ (n %s) (ax %.2f))"
FRP = "(FRP (n %s) (c %.2f %.2f %.2f) (f %.2f %.2f %.2f))"
TIME = "(time (now %.2f))"
GYR = "(GYR (n %s) (rt %.2f %.2f %.2f))"
ACC = "(ACC (n %s) (a %.2f %.2f %.2f))"
SEE_OPEN, SEE_SEPARATOR, SEE_CLOSE = "(See ", " ", ")"
OBJECT = "(%s (pol %.2f %.2f %.2f))"
PLAYER_OPEN, PLAYER_ID, PLAYER_CLOSE = "(P (team %s)", " (id %d)", ")"
PART = " (%s (pol %.2f %.2f %.2f))"
LINE = "(L (pol %.2f %.2f %.2f) (pol %.2f %.2f %.2f))"
MYPOS = "(mypos %.2f %.2f %.2f)"

_ATOM_TEXT = r"[!-'*-~]+"
_ATOM = re.compile(_ATOM_TEXT)
_ATOM_LIST = re.compile(rf"{_ATOM_TEXT}(?: {_ATOM_TEXT})*")


def format_sense(sense: Sense) -> bytes:
    """The exact bytes rcssserver3d would send for ``sense`` (frame payload, no length prefix).

    Uses ``sense.order`` when set (so ``format_sense(parse_sense(m)) == m`` for server messages), else the
    server's own order. Floats are written ``%.2f``; expressions counted in ``sense.unknown`` are not
    reproduced.

    Raises:
        ProtocolError: ``order`` does not match the content (e.g. three ``HJ`` for two joints), or a name
            or message is not a valid atom (offset = bytes written before the problem).
    """
    if sense.order:
        order = sense.order
        frps = list(sense.frp.values())
        _check_counts(sense, order)
    else:
        order, frps = server_layout(sense)  # type: ignore[assignment]
    out: list[str] = []
    atoms: list[str] = []  # names and messages, checked at once at the end
    joints = iter(sense.joints.items())
    frp_iter = iter(frps)
    hears = iter(sense.hears)
    for kind in order:
        if kind == "HJ":
            name, angle_deg = next(joints)
            out.append(HJ % (name, angle_deg))
            atoms.append(name)
        elif kind == "FRP":
            frp = next(frp_iter)
            out.append(FRP % (frp.name, *frp.contact_m, *frp.force_n))
            atoms.append(frp.name)
        elif kind == "See":
            out.append(_format_see(sense.see, atoms, out))  # type: ignore[arg-type]
        elif kind == "hear":
            out.append(hear_text(next(hears), atoms))
        elif kind == "time":
            out.append(TIME % (sense.time.now_s,))  # type: ignore[union-attr]
        elif kind == "GS":
            out.append(game_state_text(sense.game_state, atoms))  # type: ignore[arg-type]
        elif kind == "GYR":
            out.append(GYR % (sense.gyro.name, *sense.gyro.rate_deg_s))  # type: ignore[union-attr]
            atoms.append(sense.gyro.name)  # type: ignore[union-attr]
        elif kind == "ACC":
            out.append(ACC % (sense.acc.name, *sense.acc.acc_m_s2))  # type: ignore[union-attr]
            atoms.append(sense.acc.name)  # type: ignore[union-attr]
        else:
            out.append(_format_agent_state(sense.agent_state))  # type: ignore[arg-type]
    written = "".join(out)
    check_atoms(atoms, written)
    return written.encode("ascii")


def check_atoms(atoms: list[str], written: str) -> None:
    """Raise unless every name or message in ``atoms`` is a valid atom.

    Args:
        atoms: the names and messages written; written: the text so far (for the error's offset).

    Raises:
        ProtocolError: the first invalid one (empty, or holding a space or parenthesis).
    """
    joined = " ".join(atoms)  # one regex call for all names; the space count catches "a b" as one name
    if atoms and (_ATOM_LIST.fullmatch(joined) is None or joined.count(" ") != len(atoms) - 1):
        bad = next(atom for atom in atoms if _ATOM.fullmatch(atom) is None)
        offset = written.find(bad) if bad else len(written)
        raise ProtocolError.at(f"{bad!r} is not a valid atom (empty, or holds a space or parenthesis)",
                               written, max(offset, 0))


def _check_counts(sense: Sense, order: tuple[str, ...]) -> None:
    expected = {
        "HJ": len(sense.joints),
        "FRP": len(sense.frp),
        "hear": len(sense.hears),
        "time": sense.time is not None,
        "GS": sense.game_state is not None,
        "GYR": sense.gyro is not None,
        "ACC": sense.acc is not None,
        "See": sense.see is not None,
        "AgentState": sense.agent_state is not None,
    }
    for name, count in expected.items():
        if order.count(name) != count:
            raise ProtocolError(
                f"Sense.order lists {order.count(name)} {name} but the Sense holds {int(count)}", 0, b""
            )
    if len(order) != sum(expected.values()):
        unknown = sorted(set(order) - set(expected))
        raise ProtocolError(f"Sense.order holds unknown predicate names {unknown}", 0, b"")


def _format_see(see: See, atoms: list[str], out: list[str]) -> str:
    layout = see.order or (
        SEE_OBJECT * len(see.objects)
        + SEE_PLAYER * len(see.players)
        + SEE_MYPOS * (see.my_pos_m is not None)
        + SEE_LINE * len(see.lines)
    )
    counts = (len(see.objects), len(see.players), int(see.my_pos_m is not None), len(see.lines))
    if tuple(layout.count(kind) for kind in (SEE_OBJECT, SEE_PLAYER, SEE_MYPOS, SEE_LINE)) != counts or len(
        layout
    ) != sum(counts):
        written = "".join(out)
        raise ProtocolError.at(f"See.order {layout!r} does not match the See's content", written, len(written))
    objects, players, lines = iter(see.objects), iter(see.players), iter(see.lines)
    items: list[str] = []
    for kind in layout:
        if kind == SEE_LINE:
            begin, end = next(lines)
            items.append(LINE % (*begin, *end))
        elif kind == SEE_OBJECT:
            visible = next(objects)
            items.append(OBJECT % visible)
            atoms.append(visible.name)
        elif kind == SEE_PLAYER:
            player = next(players)
            unum = "" if player.unum is None else PLAYER_ID % player.unum
            parts = "".join([PART % (part, *polar) for part, polar in player.parts.items()])
            items.append(f"{PLAYER_OPEN % player.team}{unum}{parts}{PLAYER_CLOSE}")
            atoms.append(player.team)
            atoms.extend(player.parts)
        else:
            items.append(MYPOS % see.my_pos_m)  # type: ignore[misc]
    return SEE_OPEN + SEE_SEPARATOR.join(items) + SEE_CLOSE


def hear_text(hear: Hear, atoms: list[str]) -> str:
    """``(hear ...)`` of one message; its team and text are appended to ``atoms`` for `check_atoms`."""
    direction = "self" if hear.direction_deg is None else f"{hear.direction_deg:.2f}"
    team = "" if hear.team is None else f"{hear.team} "
    if hear.team is not None:
        atoms.append(hear.team)
    atoms.append(hear.message)
    return f"(hear {team}{hear.game_time_s:.2f} {direction} {hear.message})"


def game_state_text(state: GameState, atoms: list[str]) -> str:
    """``(GS ...)``; its team and play mode are appended to ``atoms`` for `check_atoms`."""
    items = []
    if state.unum is not None:
        items.append(f"(unum {state.unum})")
    if state.team is not None:
        items.append(f"(team {state.team})")
        atoms.append(state.team)
    if state.score_left is not None:
        items.append(f"(sl {state.score_left})")
    if state.score_right is not None:
        items.append(f"(sr {state.score_right})")
    items.append(f"(t {state.game_time_s:.2f})")
    items.append(f"(pm {state.play_mode})")
    atoms.append(state.play_mode)
    return f"(GS {' '.join(items)})"


def _format_agent_state(state: AgentState) -> str:
    items = []
    if state.pan_deg is not None and state.tilt_deg is not None:
        items.append(f"(pan_tilt {state.pan_deg} {state.tilt_deg})")
    if state.battery is not None:
        items.append(f"(battery {state.battery:.2f})")
    if state.temperature is not None:
        items.append(f"(temp {state.temperature:.2f})")
    return f"(AgentState {' '.join(items)})"
