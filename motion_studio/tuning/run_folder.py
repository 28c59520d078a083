"""A run folder's paths, its plots after a run, and the lines a command prints about it.

Why separate from the loop: the loop is the core (values in, records out); drawing PNGs and saying where the
files are is the edge every tuner's command shares.
"""

from __future__ import annotations

from pathlib import Path

from motion_studio.tuning.plots import CURVE_PNG, OBJECTIVE_PNG, plot_curve, plot_objective
from motion_studio.tuning.problem import Problem
from motion_studio.tuning.runner import RunResult
from motion_studio.tuning.trace import read_trace

#: Default parent of run folders (relative to where the command runs, like the other commands' out/).
RUNS_DIR = Path("out") / "tuning"


def default_run_dir(name: str, optimizer: str = "") -> Path:
    """``out/tuning/<problem>[_<optimizer>]`` (``:`` of section names turned into ``_``)."""
    return RUNS_DIR / "_".join(part.replace(":", "_") for part in (name, optimizer) if part)


def draw_plots(result: RunResult, problem: Problem) -> list[Path]:
    """The objective plot, and the curve plot for a curve problem, drawn from the run's trace file."""
    records = read_trace(result.trace)
    title = f"{problem.name}: {records[0].get('optimizer', '')}" if records else problem.name
    paths = [plot_objective(records, result.run_dir / OBJECTIVE_PNG, title)]
    if problem.curve is not None and result.best["values"]:
        paths.append(plot_curve(records, problem.curve, result.best["values"], result.run_dir / CURVE_PNG, title))
    return paths


def where_lines(result: RunResult, plots: list[Path]) -> list[str]:
    """What a tuning command prints at the end: where the plots, the checkpoint and the trace are."""
    return [f"plots: {', '.join(str(p) for p in plots)}", f"checkpoint: {result.checkpoint}",
            f"trace: {result.trace}"]





def best_evaluation(run_dir: Path) -> dict:
    """The trace record of the lowest-loss candidate a run folder holds, with ``"generations"``: how many
    generations the run finished, and ``"command"``: the command line its run record holds (None if none).

    Raises:
        TuningError: the folder has no trace or no evaluated candidate.
    """
    from motion_studio.tuning.errors import TuningError

    records = read_trace(Path(run_dir) / "trace.jsonl")
    evaluations = [r for r in records if r["kind"] == "evaluation" and not r.get("failed")]
    if not evaluations:
        raise TuningError(f"{run_dir}: no evaluated candidate in its trace.jsonl")
    best = min(evaluations, key=lambda r: r["loss"])
    command = next((r.get("command") for r in records if r["kind"] == "run"), None)
    return {**best, "generations": sum(1 for r in records if r["kind"] == "iteration"), "command": command}


def best_values(run_dir: Path) -> dict[str, float]:
    """The tuned values of the lowest-loss candidate a run folder's trace holds (a search started from
    another's best).

    Raises:
        TuningError: the folder has no trace or no evaluated candidate.
    """
    return dict(best_evaluation(run_dir)["values"])


__all__ = ["RUNS_DIR", "best_evaluation", "best_values", "default_run_dir", "draw_plots", "where_lines"]
