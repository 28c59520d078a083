"""``motion-studio demo``: the README's main job."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from motion_studio.cli import app


@app.command()
def demo(out: Annotated[Path, typer.Option(help="output folder")] = Path("out"),
         match_duration: Annotated[float, typer.Option(min=0.0, max=3600.0, help="game time of the match, s (0 = no match)")] = 600.0,
         players: Annotated[int, typer.Option(min=1, max=11, help="players per team in the match, 1-11")] = 11) -> None:
    """Run the most complete job the toolkit does today and write its results to OUT."""
    from motion_studio.demo import run_demo

    for line in run_demo(out, match_duration, players):
        typer.echo(line)
