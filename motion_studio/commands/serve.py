"""``motion-studio serve``: the MuJoCo simulator on TCP like rcssserver3d (agents 3100, monitor/trainer 3200);
``motion-studio kickoff``: start the game on a running server, as RoboViz's kick-off key does."""

from __future__ import annotations

import socket
from pathlib import Path
from typing import Annotated, Optional

import typer

from motion_studio.cli import app
from motion_studio.commands.options import choice

KICK_OFF_MODES = ("manual", "auto")
KICK_OFF_SIDES = ("Left", "Right", "None")


def how_to_start(host: str, monitor_port: int | None, automatic: bool, wait_s: float) -> list[str]:
    """The lines that tell a user how the game starts and how to watch it."""
    if automatic:
        start = f"kick-off: automatic, {wait_s:g} s after the first agent connects"
    elif monitor_port:
        start = (f"kick-off: the game waits in BeforeKickOff until you run `motion-studio kickoff --port "
                 f"{monitor_port}` (or press K in RoboViz); `serve --kickoff auto` kicks off by itself")
    else:
        start = "kick-off: no monitor port (--monitor-port 0), so only `serve --kickoff auto` can start the game"
    lines = [start, f"agents: `python -m agent --host {host} --port <agent port> --team Mine` (or motion-studio agent)"]
    if monitor_port:
        lines.append(f"watch: RoboViz with --serverHost={host} --serverPort={monitor_port}")
    return lines


@app.command()
def serve(
    port: Annotated[int, typer.Option(min=0, max=65535, help="agent port (0 = a free one)")] = 3100,
    sync: Annotated[bool, typer.Option("--sync/--realtime",
                                       help="sync: wait for every agent's (syn), as fast as they answer; "
                                            "realtime: 50 Hz wall clock, never wait")] = True,
    seed: Annotated[Optional[int], typer.Option(min=0, help="random seed (noise, referee); default: random")] = None,
    log: Annotated[Optional[Path], typer.Option(help="write a SimSpark monitor log here")] = None,
    monitor_port: Annotated[int, typer.Option(min=0, max=65535, help="monitor/trainer port; 0 = none")] = 3200,
    host: Annotated[str, typer.Option(help="bind address (loopback by default)")] = "127.0.0.1",
    kickoff: Annotated[str, typer.Option(help="manual: wait for (kickOff ...) from a monitor or `motion-studio "
                                              "kickoff`, as rcssserver3d does; auto: kick off by itself after "
                                              "--kickoff-wait")] = "manual",
    kickoff_wait: Annotated[float, typer.Option(min=0.0, max=600.0, help="seconds an automatic kick-off waits "
                                                "after the first agent (rcssserver3d: 30)")] = 30.0,
) -> None:
    """Serve a match: agents connect as to rcssserver3d; monitors (RoboViz) and trainers on the monitor port.

    Ctrl-C stops it.
    """
    from sim.serve import ServeOptions, build_simulation_server

    automatic = choice(kickoff, KICK_OFF_MODES, "--kickoff") == "auto"
    options = ServeOptions(host=host, agent_port=port, monitor_port=monitor_port or None, sync=sync,
                           real_time=not sync, seed=seed, log_path=str(log) if log else None,
                           automatic_kick_off=automatic, kick_off_wait_s=kickoff_wait)
    server, close_log = build_simulation_server(options)
    monitor = f", monitor/trainer port {server.monitor_port}" if server.monitor_port else ""
    typer.echo(f"serving on {host}: agent port {server.agent_port}{monitor} "
               f"({'sync' if sync else 'real time'}){f', log {log}' if log else ''}  (Ctrl-C to stop)")
    for line in how_to_start(host, server.monitor_port, automatic, kickoff_wait):
        typer.echo(line)
    try:
        server.serve_forever()
    except KeyboardInterrupt:
        pass
    finally:
        server.stop()
        close_log()
        typer.echo(f"stopped after {server.stats.cycles} cycles")


@app.command()
def kickoff(
    side: Annotated[str, typer.Option(help="team that kicks off: Left, Right or None (coin toss)")] = "None",
    host: Annotated[str, typer.Option(help="the server's address")] = "127.0.0.1",
    port: Annotated[int, typer.Option(min=1, max=65535, help="its monitor/trainer port")] = 3200,
) -> None:
    """Start the game on a running server (ours or rcssserver3d): send ``(kickOff SIDE)`` on its monitor port."""
    from agent.protocol.framing import frame

    choice(side, KICK_OFF_SIDES, "--side")
    try:
        with socket.create_connection((host, port), timeout=5.0) as connection:
            connection.sendall(frame(f"(kickOff {side})".encode()))
    except OSError as error:
        raise typer.BadParameter(f"no server on {host}:{port} ({error.strerror or error})", param_hint="--port") \
            from None
    typer.echo(f"sent (kickOff {side}) to {host}:{port}")
