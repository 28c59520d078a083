"""The run folder's plots, drawn from the trace alone: the objective per iteration, and for a curve problem
the tuned curve against the measured points of the rollouts that shaped it.

Why from the trace: a resumed or finished run, or one copied from another machine, draws the same figures
again without its optimizer (``motion-studio tune plot RUN_DIR``).
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import Any

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402 - the backend is chosen before pyplot loads

from motion_studio.tuning.problem import CurveView  # noqa: E402

OBJECTIVE_PNG = "objective.png"
CURVE_PNG = "curve.png"


def _finite(value: Any) -> float | None:
    try:
        value = float(value)
    except (TypeError, ValueError):
        return None
    return value if value == value and abs(value) != float("inf") else None


def plot_objective(records: Sequence[dict[str, Any]], path: Path, title: str = "") -> Path:
    """Best loss so far and each iteration's batch minimum against the rollouts spent; every evaluated
    candidate as a dot. Writes ``path`` (PNG)."""
    iterations = [r for r in records if r["kind"] == "iteration"]
    evaluations = [r for r in records if r["kind"] == "evaluation"]
    per_candidate = next((r.get("rollouts_per_candidate", 1) for r in records if r["kind"] == "run"), 1)
    figure, axis = plt.subplots(figsize=(7.0, 4.0))
    losses = [(n + 1) * per_candidate for n in range(len(evaluations))], [_finite(r["loss"]) for r in evaluations]
    axis.scatter([x for x, y in zip(*losses) if y is not None], [y for y in losses[1] if y is not None], s=8,
                 color="0.6", label="candidate")
    finite_points = [(x, y) for x, y in zip(*losses) if y is not None]
    if finite_points:
        running, best = [], float("inf")
        for _, y in finite_points:
            best = min(best, y)
            running.append(best)
        axis.step([x for x, _ in finite_points], running, where="post", color="C0", label="best so far")
    if iterations:
        axis.plot([r["rollouts"] for r in iterations], [r["batch_min"] for r in iterations], "o-", ms=3,
                  color="C1", lw=0.8, label="iteration's best")
    finite = [y for y in losses[1] if y is not None]
    if finite and min(finite) > 0 and max(finite) / max(min(finite), 1e-300) > 100:
        axis.set_yscale("log")
    return _finish(figure, axis, "rollouts", "loss (lower is better)", title or "objective per iteration", path)


def plot_curve(records: Sequence[dict[str, Any]], view: CurveView, best_values: dict[str, float], path: Path,
               title: str = "") -> Path:
    """The tuned curve (``view.tuned`` of the best values), the target, and the measured points of every
    rollout (lighter = earlier), the best candidate's in colour. Writes ``path`` (PNG)."""
    evaluations = [r for r in records if r["kind"] == "evaluation" and "failed" not in r["result"]]
    figure, axis = plt.subplots(figsize=(7.0, 4.5))
    for index, record in enumerate(evaluations):
        xs, ys = view.measured(record["result"])
        shade = 0.85 - 0.5 * index / max(1, len(evaluations) - 1)
        axis.scatter(xs, ys, s=7, color=str(round(shade, 3)), zorder=1)
    best = [r for r in evaluations if r["values"] == best_values]
    best_result = best[-1]["result"] if best else {}
    if best:
        xs, ys = view.measured(best_result)
        axis.scatter(xs, ys, s=30, color="C3", zorder=3, label="best candidate, measured")
    xs, ys = view.tuned(best_values, best_result)
    axis.plot(xs, ys, color="C0", lw=2, zorder=2, label="tuned curve")
    if view.target is not None:
        axis.plot(xs, view.target(xs), "k--", lw=1, zorder=2, label="target")
    axis.scatter([], [], s=7, color="0.6", label="rollouts (lighter = earlier)")
    return _finish(figure, axis, view.xlabel, view.ylabel, title or "tuned curve and the rollouts that shaped it", path)


def _finish(figure: Any, axis: Any, xlabel: str, ylabel: str, title: str, path: Path) -> Path:
    """Labels, grid and legend as every tuning plot has them; writes ``path`` (PNG) and frees the figure."""
    axis.set_xlabel(xlabel)
    axis.set_ylabel(ylabel)
    axis.set_title(title)
    axis.grid(alpha=0.3)
    axis.legend(fontsize=8)
    figure.tight_layout()
    figure.savefig(path, dpi=100)
    plt.close(figure)
    return path


__all__ = ["CURVE_PNG", "OBJECTIVE_PNG", "plot_curve", "plot_objective"]
