"""CasADi trust region against CMA-ES on one problem and one rollout budget: how many rollouts each needed
to reach the same objective (CMA-ES's final best), read from their traces.

Why from the traces: the count is a fact of each run's record (evaluation order, rollouts per candidate),
so a comparison can be recomputed from the run folders without running anything again.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from motion_studio.tuning.backends import Backend
from motion_studio.tuning.cma_es import CMAES
from motion_studio.tuning.problem import Problem
from motion_studio.tuning.runner import Event, RunResult, run
from motion_studio.tuning.trust_region import TrustRegion


def rollouts_to_target(records: Sequence[dict[str, Any]], target: float) -> int | None:
    """Rollouts spent until the first candidate with loss <= ``target`` (the start included); None: never."""
    per_candidate = next((r.get("rollouts_per_candidate", 1) for r in records if r["kind"] == "run"), 1)
    evaluations = sorted((r for r in records if r["kind"] == "evaluation"), key=lambda r: (r["iteration"], r["index"]))
    for position, record in enumerate(evaluations):
        if record["loss"] <= target:
            return (position + 1) * per_candidate
    return None


@dataclass(frozen=True)
class Comparison:
    """Both runs and the figures of the comparison."""

    casadi: RunResult
    cmaes: RunResult
    target_loss: float
    casadi_rollouts_to_target: int | None
    cmaes_rollouts_to_target: int | None

    def table(self) -> dict[str, Any]:
        return {"target_loss": round(self.target_loss, 6),
                "casadi_best_loss": round(self.casadi.best["loss"], 6),
                "cmaes_best_loss": round(self.cmaes.best["loss"], 6),
                "casadi_rollouts": self.casadi.rollouts, "cmaes_rollouts": self.cmaes.rollouts,
                "casadi_rollouts_to_target": self.casadi_rollouts_to_target,
                "cmaes_rollouts_to_target": self.cmaes_rollouts_to_target}


def compare(problem: Problem, run_root: Path, max_evaluations: int, radius: float = 0.15, min_radius: float = 0.01,
            sigma0: float = 0.2,
            popsize: int | None = None, seed: int = 0, backend: Backend | None = None,
            on_event: Callable[[Event], None] | None = None) -> Comparison:
    """Run the trust region and CMA-ES from the problem's start, each for at most ``max_evaluations``
    candidates, in ``run_root/casadi`` and ``run_root/cmaes`` (resumed if there)."""
    casadi_run = run(problem, lambda p: TrustRegion(p, p.x0(), radius, min_radius=min_radius, max_iterations=10**6),
                     run_root / "casadi", backend, max_evaluations=max_evaluations, on_event=on_event)
    cmaes_run = run(problem, lambda p: CMAES(p.x0(), sigma0, popsize, seed, max_iterations=10**6),
                    run_root / "cmaes", backend, max_evaluations=max_evaluations, on_event=on_event)
    target = cmaes_run.best["loss"]
    return Comparison(casadi_run, cmaes_run, target, rollouts_to_target(casadi_run.records, target),
                      rollouts_to_target(cmaes_run.records, target))


__all__ = ["Comparison", "compare", "rollouts_to_target"]
