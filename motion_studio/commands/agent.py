"""``motion-studio agent``: run one soccer agent against a server (same as ``python -m agent``)."""

from __future__ import annotations

from typing import Annotated

import typer

from motion_studio.cli import app
from motion_studio.commands.options import choice


@app.command("agent")
def agent_command(
    host: Annotated[str, typer.Option(help="server address")] = "127.0.0.1",
    port: Annotated[int, typer.Option(min=1, max=65535, help="agent port")] = 3100,
    team: Annotated[str, typer.Option(help="team name")] = "Nao3D",
    unum: Annotated[int, typer.Option(min=0, max=11, help="uniform number 1-11, 0 = next free")] = 0,
    robot_type: Annotated[str, typer.Option("--type", help="robot type 0-4, or auto (our team's type for the "
                                                           "unum: 0, 2, 4 cycled)")] = "auto",
    localization: Annotated[str, typer.Option(help="self-localization: ekf or seed")] = "ekf",
    attempts: Annotated[int, typer.Option(min=1, max=1000, help="connection attempts before giving up")] = 5,
    behavior: Annotated[str, typer.Option(help="soccer (play with the shipped motions) or idle")] = "soccer",
) -> None:
    """Connect to HOST:PORT, join TEAM as UNUM and play until the server goes away."""
    from agent.runner import run_cli
    from agent.team.composition import parse_robot_type, robot_type_for

    choice(localization, ("ekf", "seed"), "--localization")
    choice(behavior, ("soccer", "idle"), "--behavior")
    try:
        chosen = parse_robot_type(robot_type)
    except ValueError as error:
        raise typer.BadParameter(str(error), param_hint="--type") from None
    code = run_cli(host, port, team, unum, robot_type_for(unum) if chosen is None else chosen, localization,
                   attempts, behavior)
    if code:
        raise typer.Exit(code)
