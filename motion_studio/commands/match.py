"""``motion-studio match``: full matches headless on our simulator, one or a checkpointed batch."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Annotated, Optional

import typer

from motion_studio.cli import app


@app.command()
def match(
    players: Annotated[int, typer.Option(min=1, max=11, help="players per team (1-11)")] = 3,
    duration: Annotated[float, typer.Option(min=0.02, max=3600.0, help="game time to play, s (600 = two halves; 0.02-3600)")] = 600.0,
    matches: Annotated[int, typer.Option(min=1, max=100000, help="number of matches (seeds seed..seed+N-1)")] = 1,
    workers: Annotated[int, typer.Option(min=1, max=1024, help="parallel processes for a batch")] = 1,
    ray: Annotated[Optional[str], typer.Option(
        help="run the batch on Ray: 'auto' or HOST:PORT joins a cluster, 'local' starts Ray here")] = None,
    seed: Annotated[int, typer.Option(min=0, help="first seed")] = 0,
    out: Annotated[Path, typer.Option(help="output folder: results.jsonl (checkpoint), logs, plot")] = Path("out/match"),
    log: Annotated[bool, typer.Option(help="write a SimSpark monitor log per match")] = True,
    left: Annotated[str, typer.Option(
        help="left team: ours, baseline (the seed: nearest player kicks), solo (our dribble, no coordination) or "
             "standing (robots that only stand)")] = "ours",
    right: Annotated[str, typer.Option(help="right team: ours, baseline, solo or standing")] = "ours",
    team_left: Annotated[str, typer.Option()] = "Left",
    team_right: Annotated[str, typer.Option()] = "Right",
    resume: Annotated[bool, typer.Option(help="keep finished matches of an earlier run of the same folder")] = True,
    summary_json: Annotated[Optional[bool], typer.Option("--json", help="print the results as JSON")] = False,
    agent_processes: Annotated[Optional[int], typer.Option(
        min=0, max=22, help="worker processes that run the agents of a single match while this one runs the "
                            "simulator (the same match, on more cores); 0 keeps them in this process. "
                            "Default: 2 for a single match (batches use their cores for parallel matches)")] = None,
) -> None:
    """Play matches with our agents and motions; results go to OUT/results.jsonl as each match ends."""
    from motion_studio.match_report import run_and_report
    from motion_studio.match_agents import check_kind
    from sim.ray_executor import RayUnavailable

    for kind in (left, right):
        try:
            check_kind(kind)
        except ValueError as error:
            typer.echo(f"error: {error}", err=True)
            raise typer.Exit(2) from None
        if kind.startswith("cmd:"):
            typer.echo("error: external agent commands (cmd:) are not supported yet", err=True)
            raise typer.Exit(2)
    if agent_processes is not None and agent_processes > 0 and (matches > 1 or workers > 1 or ray is not None):
        typer.echo("error: --agent-processes is for a single match (a batch runs whole matches in parallel)",
                   err=True)
        raise typer.Exit(2)
    try:
        lines, results = run_and_report(players=players, duration_s=duration, matches=matches, workers=workers,
                                        seed=seed, out=out, log=log, team_left=team_left, team_right=team_right,
                                        resume=resume, ray_address=ray, left=left, right=right,
                                        agent_processes=agent_processes)
    except RayUnavailable as error:  # say so, no traceback
        typer.echo(f"error: {error}", err=True)
        raise typer.Exit(2) from None
    if summary_json:
        typer.echo(json.dumps(results))
        return
    for line in lines:
        typer.echo(line)
