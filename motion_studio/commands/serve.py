"""``motion-studio serve``: the MuJoCo simulator on TCP like rcssserver3d (agents 3100, monitor/trainer 3200)."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated, Optional

import typer

from motion_studio.cli import app


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
) -> None:
    """Serve a match: agents connect as to rcssserver3d; monitors (RoboViz) and trainers on the monitor port.

    Ctrl-C stops it.
    """
    from sim.serve import ServeOptions, build_simulation_server

    options = ServeOptions(host=host, agent_port=port, monitor_port=monitor_port or None, sync=sync,
                           real_time=not sync, seed=seed, log_path=str(log) if log else None)
    server, close_log = build_simulation_server(options)
    monitor = f", monitor/trainer port {server.monitor_port}" if server.monitor_port else ""
    typer.echo(f"serving on {host}: agent port {server.agent_port}{monitor} "
               f"({'sync' if sync else 'real time'}){f', log {log}' if log else ''}  (Ctrl-C to stop)")
    try:
        server.serve_forever()
    except KeyboardInterrupt:
        pass
    finally:
        server.stop()
        close_log()
        typer.echo(f"stopped after {server.stats.cycles} cycles")
