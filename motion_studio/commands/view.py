"""``motion-studio view``: the Nao with its real shapes in meshcat, at a pose, or a match log replay."""

from __future__ import annotations

import time
from pathlib import Path
from typing import Annotated, Optional

import typer

from motion_studio.cli import app
from motion_studio.commands.options import RobotType


@app.command()
def view(
    joint: Annotated[Optional[list[str]], typer.Option("--joint", "-j",
                     help="NAME=DEGREES (wire, effector or Nao name, SimSpark sign); repeatable")] = None,
    pose: Annotated[Optional[Path], typer.Option(help="JSON file {joint: degrees}")] = None,
    robot_type: RobotType = 0,
    html: Annotated[Optional[Path], typer.Option(help="write a standalone HTML scene here instead of serving")] = None,
    log: Annotated[Optional[Path], typer.Option(help="replay a SimSpark monitor log instead of a pose")] = None,
) -> None:
    """Show the Nao at a pose in meshcat (127.0.0.1 only); prints the URL, Ctrl-C to stop."""
    from kinematics import SpecError
    from motion_studio.preview import preview_pose

    if log is not None:
        from sim.replay import replay_log

        try:
            url_or_path = replay_log(log, html_out=html, block=False)
        except ValueError as error:  # a log with no full state
            raise typer.BadParameter(str(error), param_hint="--log") from None
    else:
        try:
            url_or_path = preview_pose(robot_type, joint or [], pose, html)
        except SpecError as error:  # the joint, angle or pose file that is wrong, named in the message
            raise typer.BadParameter(str(error), param_hint="--pose" if error.field == "pose" else "--joint") \
                from None
    if html is not None:
        typer.echo(f"wrote {url_or_path}")
        return
    typer.echo(f"meshcat viewer: {url_or_path}  (Ctrl-C to stop)")
    try:
        while True:
            time.sleep(1.0)
    except KeyboardInterrupt:
        pass
