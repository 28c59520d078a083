"""Options several subcommands share, with their ranges, so every command checks them the same way."""

from __future__ import annotations

from typing import Annotated

import typer

from kinematics.spec import ROBOT_TYPES

#: ``--type``: a SimSpark robot type (REFERENCE §2.5).
RobotType = Annotated[int, typer.Option("--type", min=min(ROBOT_TYPES), max=max(ROBOT_TYPES),
                                        help=f"robot type {min(ROBOT_TYPES)}-{max(ROBOT_TYPES)}")]
#: Players per team: the league's 1-11.
PLAYERS_MIN, PLAYERS_MAX = 1, 11
#: A TCP port; 0 asks the system for a free one where a command allows it.
PORT_MIN, PORT_MAX = 0, 65535


def choice(value: str, allowed: tuple[str, ...], option: str) -> str:
    """``value`` if it is one of ``allowed``, else a one-line BadParameter naming ``option`` and the choices."""
    if value not in allowed:
        raise typer.BadParameter(f"{value!r} is not one of {', '.join(allowed)}", param_hint=option)
    return value
