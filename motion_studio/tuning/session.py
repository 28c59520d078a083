"""A tuner's run from the command line: CMA-ES (gait, kick, stand-up) or either optimizer on a curve problem
(lean, turn), with the progress bar, the plots and the lines that say where the files are.

Why here: each tuner used to carry its own loop; now each builds a :class:`Problem` and calls
:func:`run_cmaes` or :func:`run_optimizer`, which give the trace, checkpoint, resume, plots and the progress
bar the same way for all.
"""

from __future__ import annotations

import argparse
import functools
import sys
from collections.abc import Callable
from pathlib import Path
from typing import Any

from motion_studio.tuning.backends import Backend
from motion_studio.tuning.cma_es import CMAES
from motion_studio.tuning.problem import Problem
from motion_studio.tuning.progress import ProgressBar
from motion_studio.tuning.run_folder import draw_plots, where_lines
from motion_studio.tuning.runner import Event, RunResult, run
from motion_studio.tuning.trust_region import TrustRegion

#: Optimizer names of the curve tuners' CLI.
OPTIMIZERS = ("casadi", "cmaes")


def run_cmaes(problem: Problem, run_dir: Path, generations: int, sigma0: float, popsize: int | None = None,
              seed: int = 0, backend: Backend | None = None, progress: Callable[[str], None] | None = print,
              bar: bool = False, plots: bool = True, meta: dict[str, Any] | None = None) -> RunResult:
    """CMA-ES on ``problem`` for ``generations`` iterations in ``run_dir`` (resumed if it holds a checkpoint).

    Args:
        progress: told one line per generation (None: silent) and, at the end, where the files are.
        bar: show a progress bar (the CLI's choice).
    """
    def make(p: Problem) -> CMAES:
        return CMAES(p.x0(), sigma0, popsize, seed, max_iterations=generations)

    expected = 1 + generations * (popsize or CMAES(problem.x0(), sigma0, popsize, seed).popsize)

    def line(event: Event) -> str:
        return (f"{problem.name} generation {event.iteration + 1}/{generations}: min {event.loss:.4f} "
                f"best {event.best_loss:.4f} ({event.evaluations} candidates)")

    with ProgressBar(expected, problem.name, line if progress else None, disable=not bar) as on_event:
        def told(event: Event) -> None:
            on_event(event)
            if progress and not bar and event.kind == "iteration":
                progress(line(event))

        result = run(problem, make, run_dir, backend, on_event=told, meta=meta)
    if plots:
        paths = draw_plots(result, problem)
        for text in where_lines(result, paths):
            if progress:
                progress(text)
    return result


def run_optimizer(problem: Problem, optimizer: str, run_dir: Path, max_evaluations: int, radius: float = 0.15,
                  min_radius: float = 0.01, sigma0: float = 0.2, popsize: int | None = None, seed: int = 0, backend: Backend | None = None,
                  progress: Callable[[str], None] | None = print, bar: bool = False) -> RunResult:
    """The CasADi/IPOPT trust region (``casadi``) or CMA-ES (``cmaes``) on ``problem`` for at most
    ``max_evaluations`` candidates in ``run_dir`` (resumed if it holds a checkpoint); plots drawn after.

    Raises:
        TuningError: an unknown optimizer name.
    """
    from motion_studio.tuning.errors import TuningError

    if optimizer == "casadi":
        def make(p: Problem):  # noqa: ANN202 - TrustRegion or CMAES
            return TrustRegion(p, p.x0(), radius, min_radius=min_radius, max_iterations=10**6)
    elif optimizer == "cmaes":
        def make(p: Problem):  # noqa: ANN202
            return CMAES(p.x0(), sigma0, popsize, seed, max_iterations=10**6)
    else:
        raise TuningError(f"unknown optimizer {optimizer!r}; known: {', '.join(OPTIMIZERS)}")

    def line(event: Event) -> str:
        return (f"{problem.name} iteration {event.iteration + 1}: batch min {event.loss:.4g} best {event.best_loss:.4g}"
                f" ({event.evaluations} candidates)")

    with ProgressBar(max_evaluations, f"{problem.name} {optimizer}", line if progress else None,
                     disable=not bar) as on_event:
        def told(event: Event) -> None:
            on_event(event)
            if progress and not bar and event.kind == "iteration":
                progress(line(event))

        result = run(problem, make, run_dir, backend, max_evaluations=max_evaluations, on_event=told)
    paths = draw_plots(result, problem)
    for text in where_lines(result, paths):
        if progress:
            progress(text)
    return result


def add_curve_run_options(parser: argparse.ArgumentParser, run_name: str) -> None:
    """The options the curve tuners (lean, turn) share: a comparison of the optimizers, the run folder, and
    where the rollouts run."""
    parser.add_argument("--compare", action="store_true",
                        help="run both optimizers on one budget and print rollouts to CMA-ES's final objective")
    parser.add_argument("--run-dir", type=Path, default=None,
                        help=f"run folder (default out/tuning/{run_name}_<optimizer>)")
    parser.add_argument("--workers", type=int, default=1, help="local processes for the rollouts")
    parser.add_argument("--ray-address", default=None, help="run the rollouts on this Ray cluster ('local': a new one)")


def one_line_errors(program: str) -> Callable[[Callable[..., int]], Callable[..., int]]:
    """Decorate a tuner's ``main(argv)``: a ``TuningError`` (unknown parameter, lower > upper bound, NaN
    objective, another problem's checkpoint) prints one line naming it and returns exit code 2."""
    from motion_studio.tuning.errors import TuningError

    def wrap(main: Callable[..., int]) -> Callable[..., int]:
        @functools.wraps(main)
        def guarded_main(argv: list[str] | None = None) -> int:
            try:
                return main(argv)
            except TuningError as error:
                print(f"{program}: error: {error}", file=sys.stderr)
                return 2
        return guarded_main
    return wrap


def legacy_data(result: RunResult, full: Callable[[dict[str, float]], dict[str, Any]],
                key: str = "params") -> dict[str, Any]:
    """``{"best": {"loss", key, "result"}, "evaluations": [{"generation", key, "result"}]}``: the shape the
    tuners' callers and tests read; ``full`` turns tuned values into the whole parameter set."""
    evaluations = [{"generation": r["iteration"] + 1, key: full(r["values"]), "result": r["result"]}
                   for r in result.records if r["kind"] == "evaluation" and r["iteration"] >= 0]
    best = result.best
    return {"best": {"loss": best["loss"], key: full(best["values"]), "result": best["result"]},
            "evaluations": evaluations, "run_dir": str(result.run_dir)}


__all__ = ["OPTIMIZERS", "legacy_data", "one_line_errors", "run_cmaes", "run_optimizer"]
