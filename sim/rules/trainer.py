"""Trainer commands of the monitor port (REFERENCE §5.2), applied to the referee and the world.

Supported: ``(kickOff Left|Right|None)``, ``(playMode NAME)``, ``(dropBall)``, ``(ball (pos x y z)(vel x y z))``,
``(agent (unum n)(team Left|Right)(pos x y z))`` or ``(agent ... (move x y z angle))``, ``(time t)``,
``(score (left n)(right n))``. ``(reqfullstate)`` and ``(killsim)`` are the server's (sim.tcp_server);
``(select)``, ``(kill)``, ``(repos)``, ``(getAck)``, battery and temperature are accepted and ignored.
A bad command is logged with its text and skipped; the others in the same message still apply.
"""

from __future__ import annotations

import logging
import math
from collections.abc import Sequence

from agent.protocol.sexpr import parse_sexpr
from sim.referee import Referee
from sim.world_api import WorldView
from sim.errors import TrainerCommandError

logger = logging.getLogger(__name__)

_IGNORED = {"select", "kill", "repos", "getAck", "reqfullstate", "killsim"}


def apply_trainer_message(payload: bytes | str, referee: Referee, world: WorldView) -> list[str]:
    """Apply every command of one monitor message; returns the names of the commands applied.

    Raises:
        ProtocolError: the message is not valid S-expression text (nothing is applied).
    """
    applied = []
    for command in parse_sexpr(payload):
        name = command[0] if command and isinstance(command[0], str) else None
        try:
            if name is None:
                raise TrainerCommandError("a command must start with its name")
            if _apply(name, command[1:], referee, world):
                applied.append(name)
        except (ValueError, KeyError, IndexError, TypeError) as error:
            logger.warning("cycle %d: trainer command %s rejected: %s", referee.cycle, _text(command), error)
    return applied


def _apply(name: str, args: Sequence[object], referee: Referee, world: WorldView) -> bool:
    if name == "kickOff":
        referee.kick_off(_atom(args, 0))
    elif name == "playMode":
        referee.set_play_mode(_atom(args, 0))
    elif name == "dropBall":
        referee.drop_ball(world)
    elif name == "ball":
        pos = _vector(args, "pos", 3)
        vel = _vector(args, "vel", 3)
        if pos is None and vel is None:
            raise TrainerCommandError("expected (pos x y z) and/or (vel x y z)")
        world.set_ball(tuple(pos) if pos is not None else world.ball_position(),  # type: ignore[arg-type]
                       tuple(vel) if vel is not None else world.ball_velocity())  # type: ignore[arg-type]
    elif name == "agent":
        _agent(args, world)
    elif name == "time":
        referee.set_game_time(_finite(_atom(args, 0)))
    elif name == "score":
        left, right = _vector(args, "left", 1), _vector(args, "right", 1)
        referee.set_score(int(left[0]) if left else None, int(right[0]) if right else None)
    elif name in _IGNORED:
        return False
    else:
        raise TrainerCommandError(f"unknown trainer command {name!r}")
    return True


def _agent(args: Sequence[object], world: WorldView) -> None:
    unum = _vector(args, "unum", 1)
    team = _words(args, "team")
    if unum is None or team is None:
        raise TrainerCommandError("expected (unum n) and (team Left|Right)")
    side = team.lower()
    if side not in ("left", "right"):
        raise TrainerCommandError(f"unknown team {team!r}; expected Left or Right")
    pos = _vector(args, "pos", 3)
    move = _vector(args, "move", 4)
    # (move x y z angle): angle is SimSpark's yaw, 0 = facing +y, so heading (0 = facing +x) = angle + 90.
    if move is not None:
        world.move_robot(side, int(unum[0]), move[0], move[1], move[3] + 90.0, move[2])
    elif pos is not None:
        world.move_robot(side, int(unum[0]), pos[0], pos[1], None, pos[2])


def _atom(args: Sequence[object], index: int) -> str:
    value = args[index]
    if not isinstance(value, str):
        raise TrainerCommandError(f"expected a word, got {_text(value)}")
    return value


def _finite(token: str) -> float:
    value = float(token)
    if not math.isfinite(value):
        raise TrainerCommandError(f"expected a finite number, got {token!r}")
    return value


def _words(args: Sequence[object], key: str) -> str | None:
    for item in args:
        if isinstance(item, list) and item and item[0] == key and len(item) > 1 and isinstance(item[1], str):
            return item[1]
    return None


def _vector(args: Sequence[object], key: str, size: int) -> list[float] | None:
    for item in args:
        if isinstance(item, list) and item and item[0] == key:
            if len(item) != size + 1 or not all(isinstance(v, str) for v in item[1:]):
                raise TrainerCommandError(f"({key} ...) needs {size} numbers, got {_text(item)}")
            return [_finite(v) for v in item[1:]]  # type: ignore[arg-type]
    return None


def _text(expression: object) -> str:
    if isinstance(expression, list):
        return "(" + " ".join(_text(e) for e in expression) + ")"
    return str(expression)

