"""``motion-studio strike``: the kick's strike keyframe solved with IPOPT on the symbolic Nao
(``motion_studio.strike_keyframe``) and, with ``--refine``, the kick parameters it seeds refined by a short
CMA-ES run of MuJoCo rollouts (``motion_studio.strike_refine``). Prints; writes nothing into motions/."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Annotated

import typer

from motion_studio.cli import app


@app.command("strike")
def strike(
    refine: Annotated[bool, typer.Option(help="refine the seeded kick parameters by rollouts on our simulator")] = False,
    section: Annotated[str, typer.Option(help="kick section of motions/params/kick.toml the seed goes into")] = "kick",
    generations: Annotated[int, typer.Option(min=1, max=50, help="CMA-ES generations of the refinement")] = 3,
    popsize: Annotated[int, typer.Option(min=2, max=32, help="candidates per generation")] = 4,
    out: Annotated[Path | None, typer.Option(help="run folder (default out/tuning/kick_<section>_strike_refine)")] = None,
    as_json: Annotated[bool, typer.Option("--json", help="print one JSON object only")] = False,
) -> None:
    """The IPOPT strike keyframe (SimSpark degrees, rad/s, toe speed) and optionally its rollout refinement."""
    from dataclasses import asdict

    from motion_studio.strike_keyframe import optimise_strike
    from motion_studio.strike_refine import refine_strike, seeded_values

    keyframe = optimise_strike(0)
    figures: dict[str, object] = {"strike": asdict(keyframe), "seeded": seeded_values(keyframe)}
    if refine:
        try:
            result = refine_strike(section, generations, popsize=popsize, run_dir=out, strike=keyframe,
                                   progress=None if as_json else typer.echo)
        except ValueError as error:
            raise typer.BadParameter(str(error)) from None
        figures["refinement"] = {"start_loss": result.start_loss, "best_loss": result.best_loss,
                                 "best": result.best, "rollouts": result.rollouts, "run_dir": str(result.run_dir)}
    if as_json:
        typer.echo(json.dumps(figures))
        return
    for key, value in figures.items():
        typer.echo(f"{key}: {json.dumps(value)}")
