"""``motion-studio bench sim``: real-time factor of the simulator with N in-process agents."""

from __future__ import annotations

import json
from typing import Annotated

import typer

from motion_studio.cli import bench_app


@bench_app.command("sim")
def bench_sim(
    robots: Annotated[int, typer.Option(min=1, max=22, help="number of robots (agents), 1-22")] = 22,
    cycles: Annotated[int, typer.Option(min=1, max=1_000_000, help="timed cycles (20 ms of simulated time each)")] = 500,
    as_json: Annotated[bool, typer.Option("--json", help="print one JSON object only")] = False,
) -> None:
    """Time the simulator: every agent parses its sense message and sends 22 joint commands per cycle."""
    from sim.benchmark import TARGET_REALTIME_FACTOR, run

    figures = run(robots, cycles).as_dict()
    if as_json:
        typer.echo(json.dumps(figures))
        return
    for key, value in figures.items():
        typer.echo(f"{key:>27}: {value:.6g}" if isinstance(value, float) else f"{key:>27}: {value}")
    target = TARGET_REALTIME_FACTOR.get(robots)
    if target:
        typer.echo(f"{'target':>27}: {target:g}x real time")
