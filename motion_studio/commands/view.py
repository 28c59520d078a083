"""``motion-studio view``: the Nao with its real shapes in meshcat, at a pose, or a match log replay."""

from __future__ import annotations

import time
from pathlib import Path
from typing import Annotated, Optional

import typer

from motion_studio.cli import app


@app.command()
def view(
    joint: Annotated[Optional[list[str]], typer.Option("--joint", "-j",
                     help="NAME=DEGREES (wire, effector or Nao name, SimSpark sign); repeatable")] = None,
    pose: Annotated[Optional[Path], typer.Option(help="JSON file {joint: degrees}")] = None,
    robot_type: Annotated[int, typer.Option("--type", help="robot type 0-4")] = 0,
    html: Annotated[Optional[Path], typer.Option(help="write a standalone HTML scene here instead of serving")] = None,
    log: Annotated[Optional[Path], typer.Option(help="replay a SimSpark monitor log instead of a pose")] = None,
) -> None:
    """Show the Nao at a pose in meshcat (127.0.0.1 only); prints the URL, Ctrl-C to stop."""
    from motion_studio.preview import preview_pose

    if log is not None:
        from sim.replay import replay_log

        url_or_path = replay_log(log, html_out=html, block=False)
    else:
        url_or_path = preview_pose(robot_type, joint or [], pose, html)
    if html is not None:
        typer.echo(f"wrote {url_or_path}")
        return
    typer.echo(f"meshcat viewer: {url_or_path}  (Ctrl-C to stop)")
    try:
        while True:
            time.sleep(1.0)
    except KeyboardInterrupt:
        pass
