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
    repeat: Annotated[int, typer.Option(min=1, max=100, help=(
        "timed runs; the figures are the run with the median real-time factor (the lower middle one of an even "
        "count), runs_realtime_factor lists all"))] = 1,
    as_json: Annotated[bool, typer.Option("--json", help="print one JSON object only")] = False,
) -> None:
    """Time the simulator: every agent parses its sense message and sends 22 joint commands per cycle.

    Why ``--repeat``: one run's factor swings 5-8 % with the machine's load (96-106x for the same code within an
    hour, 1 robot); the median of several is the figure to compare."""
    from sim.benchmark import TARGET_REALTIME_FACTOR, run

    runs = sorted((run(robots, cycles).as_dict() for _ in range(repeat)), key=lambda r: r["realtime_factor"])
    figures = runs[(len(runs) - 1) // 2]
    if repeat > 1:
        figures["runs_realtime_factor"] = [round(r["realtime_factor"], 2) for r in runs]
    if as_json:
        typer.echo(json.dumps(figures))
        return
    for key, value in figures.items():
        typer.echo(f"{key:>27}: {value:.6g}" if isinstance(value, float) else f"{key:>27}: {value}")
    target = TARGET_REALTIME_FACTOR.get(robots)
    if target:
        typer.echo(f"{'target':>27}: {target:g}x real time")


@bench_app.command("speed")
def bench_speed(
    players: Annotated[int, typer.Option(min=1, max=11, help="players per team of the timed match")] = 11,
    duration: Annotated[float, typer.Option(min=0.02, max=600.0, help="game time of the timed match, s")] = 20.0,
    agent_processes: Annotated[int, typer.Option(
        min=0, max=22, help="agent worker processes (as motion-studio match; 0: in-process)")] = 2,
    cycles: Annotated[int, typer.Option(min=1, max=1_000_000, help="timed cycles of the 1-robot engine run")] = 2000,
    as_json: Annotated[bool, typer.Option("--json", help="print one JSON object only")] = False,
) -> None:
    """Issue 15 "Speed": simulated seconds per wall second of a match of our agents (11 v 11) and of the engine
    alone with 1 robot (as ``bench sim --robots 1``), as ratios to real time."""
    from motion_studio.match_agents import SideAgents
    from sim.benchmark import TARGET_ENGINE_RATIO, TARGET_MATCH_RATIO, match_speed, run

    match = match_speed(SideAgents(), players, duration, agent_processes).as_dict()
    engine = run(1, cycles).as_dict()
    engine_alone = run(1, cycles, parse=False).as_dict()
    if as_json:
        typer.echo(json.dumps({"match": match, "engine_1_robot": engine, "engine_1_robot_no_parse": engine_alone}))
        return
    where = "in-process" if agent_processes == 0 else f"{agent_processes} agent processes"
    typer.echo(f"match {players} v {players} ({where}): {match['ratio']:.2f}x real time "
               f"(cycles x 20 ms / wall s; target {TARGET_MATCH_RATIO:g}x on 2 cores), game clock "
               f"{match['game_ratio']:.2f}x; {match['cycles']} cycles in {match['wall_seconds']:.1f} s; CPU s: "
               f"engine process {match['engine_process_cpu_s']:.1f}, agent workers {match['worker_cpu_s']:.1f}")
    typer.echo(f"engine, 1 robot: {engine['realtime_factor']:.1f}x real time (target {TARGET_ENGINE_RATIO:g}x; "
               f"agent parses), {engine_alone['realtime_factor']:.1f}x with an agent that does not parse; "
               f"mj_step alone {engine['raw_mujoco_realtime_factor']:.0f}x")
