"""``motion-studio bench tuning``: the symbolic Nao against Pinocchio, and the CasADi trust region against
CMA-ES on the lean and turn curves (rollouts to the same objective, the tuned curves' errors)."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Annotated

import typer

from motion_studio.cli import bench_app


@bench_app.command("tuning")
def bench_tuning(
    as_json: Annotated[bool, typer.Option("--json", help="print one JSON object only")] = False,
    quick: Annotated[bool, typer.Option(help="small budgets and problems (about 3 minutes on 2 cores)")] = False,
    workers: Annotated[int, typer.Option(min=1, max=64, help="local processes for the rollouts")] = 2,
    out: Annotated[Path | None, typer.Option(help="run folders (default out/tuning/bench[_quick], made anew)")] = None,
) -> None:
    """Figures of the tuning room (not pass/fail): symbolic_vs_pinocchio_max_diff_m, curve_solver,
    lean_curvature_error_deg_m, turn_prediction_error_deg, casadi/cmaes_rollouts_to_target, wall_s; the keyframe
    NLPs: strike_toe_speed_m_s, standup_keypose_margin_m (authored crouch vs IPOPT's), strike_refine_loss (the
    IPOPT strike's seeded kick and its rollout refinement)."""
    from motion_studio.tuning.bench import run

    figures = run(quick, out, workers, progress=None if as_json else typer.echo)
    if as_json:
        typer.echo(json.dumps(figures))
        return
    for key, value in figures.items():
        typer.echo(f"{key:>34}: {json.dumps(value)}")
