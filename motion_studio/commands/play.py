"""``motion-studio play FILE``: play a motion on a simulated robot, headless; did it stay up?"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Annotated, Optional

import typer

from motion_studio.cli import app
from motion_studio.commands.options import RobotType, choice


@app.command()
def play(
    motion_file: Annotated[Path, typer.Argument(help="XML phase (.xml) or Webots (.motion) file")],
    robot_type: RobotType = 0,
    hold: Annotated[float, typer.Option(min=0.0, max=600.0, help="seconds recorded after the motion ends")] = 1.0,
    plot: Annotated[Optional[Path], typer.Option(help="write a PNG of torso height and tilt here")] = None,
    html: Annotated[Optional[Path], typer.Option(help="write a standalone 3D animation (meshcat HTML) here")] = None,
    as_json: Annotated[bool, typer.Option("--json", help="print one JSON object only")] = False,
    start: Annotated[str, typer.Option(help="standing, or lying on the back, front or side (a stand-up's start); "
                                            "auto: lying for standup_back/_front files, else standing")] = "auto",
) -> None:
    """Play MOTION_FILE with the agent's motion controller on our simulator and report whether the robot
    stayed up, or from a lying start whether it stood up (exit code 1 if it is down)."""
    import motions
    from motion_studio.editor.physics_preview import STARTS
    from motion_studio.play import default_start, play_motion, write_animation, write_plot

    start = default_start(motion_file) if start == "auto" else choice(start, ("auto", *STARTS), "--start")

    try:
        motion = motions.load(motion_file)
    except (OSError, motions.MotionFormatError) as error:
        raise typer.BadParameter(str(error), param_hint="MOTION_FILE") from None
    result = play_motion(motion, robot_type, hold_s=hold, start=start)
    summary = result.summary()
    if plot is not None:
        summary["plot"] = str(write_plot(result, motion_file.name, plot))
    if html is not None:
        summary["html"] = str(write_animation(result, robot_type, html))
    if as_json:
        typer.echo(json.dumps(summary))
    else:
        for key, value in summary.items():
            shown = f"{value:.3f}" if isinstance(value, float) else value
            typer.echo(f"{key:>22}: {shown}")
    if result.fell:
        raise typer.Exit(1)
