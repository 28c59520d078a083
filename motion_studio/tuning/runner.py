"""The run loop every tuner uses: ask the optimizer, evaluate the batch on a backend, tell, trace and
checkpoint after every iteration, resume from the run folder after a crash or a kill -9.

Why this order: each finished candidate is appended to the trace as it comes in; the iteration's record
and then the checkpoint (the pickled optimizer, atomically replaced) follow once the batch is told. A run
started again in the same folder loads the checkpoint, asks the same candidates (the optimizers are
deterministic given their pickled state) and takes the results of those the trace already holds, so no
finished rollout is lost and the run ends exactly where an uninterrupted run would.
"""

from __future__ import annotations

import datetime
import logging
import math
import os
import pickle
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Protocol

import numpy as np

from motion_studio.tuning.backends import Backend, InProcess
from motion_studio.tuning.errors import TuningError
from motion_studio.tuning.problem import Problem, Result
from motion_studio.tuning.trace import TraceWriter, read_trace

logger = logging.getLogger(__name__)

CHECKPOINT_NAME = "checkpoint.pkl"
TRACE_NAME = "trace.jsonl"


class Optimizer(Protocol):
    """What the loop needs of an optimizer (``motion_studio.tuning.cma_es.CMAES``, ``...trust_region``)."""

    name: str
    iteration: int
    max_iterations: int

    def ask(self) -> list[np.ndarray]: ...

    def tell(self, xs: Sequence[np.ndarray], results: Sequence[Result], losses: Sequence[float]) -> None: ...

    def done(self) -> bool: ...

    def summary(self) -> dict[str, float]: ...


@dataclass(frozen=True)
class Event:
    """What a progress callback is told: after each candidate (``kind`` "evaluation") and iteration."""

    kind: str
    iteration: int
    evaluations: int
    best_loss: float
    loss: float


@dataclass
class RunResult:
    """The end of a run: the best candidate, counts, and where the run folder's files are."""

    problem: str
    best: dict[str, Any]
    """{"loss": penalised loss, "values": parameter values, "result": its figures, "evaluation": index}."""
    evaluations: int
    rollouts: int
    iterations: int
    run_dir: Path
    records: list[dict[str, Any]] = field(default_factory=list)

    @property
    def checkpoint(self) -> Path:
        return self.run_dir / CHECKPOINT_NAME

    @property
    def trace(self) -> Path:
        return self.run_dir / TRACE_NAME


def _atomic_pickle(path: Path, payload: object) -> None:
    tmp = path.with_suffix(".tmp")
    with tmp.open("wb") as file:
        pickle.dump(payload, file)
        file.flush()
        os.fsync(file.fileno())
    tmp.replace(path)


def checked_loss(problem: Problem, values: dict[str, float], result: Result) -> tuple[float, bool]:
    """The penalised loss of a result, and whether the candidate failed (failed: the problem's fail loss).

    Raises:
        TuningError: a NaN (or infinite) loss from an evaluation that did not fail: the objective is wrong,
            and ranking by it would silently mislead the optimizer.
    """
    if "failed" in result:
        return float(problem.fail_loss), True
    loss = float(result["loss"])
    if not math.isfinite(loss):
        shown = ", ".join(f"{k}={v:g}" for k, v in values.items())
        raise TuningError(f"problem {problem.name!r}: objective returned {loss} for {shown}")
    return problem.penalised_loss(result), False


class _Best:
    def __init__(self) -> None:
        self.entry: dict[str, Any] = {"loss": math.inf, "values": {}, "result": {}, "evaluation": -1}

    def offer(self, loss: float, values: dict[str, float], result: Result, evaluation: int) -> None:
        if loss < self.entry["loss"]:
            self.entry = {"loss": loss, "values": dict(values), "result": result, "evaluation": evaluation}


def run(problem: Problem, make_optimizer: Callable[[Problem], Optimizer], run_dir: Path,
        backend: Backend | None = None, max_evaluations: int | None = None, evaluate_start: bool = True,
        on_event: Callable[[Event], None] | None = None, meta: dict[str, Any] | None = None) -> RunResult:
    """Run (or resume) ``problem`` in ``run_dir``.

    Args:
        problem: what is tuned.
        make_optimizer: builds a fresh optimizer; a resumed checkpoint keeps its optimizer's state and takes
            only the fresh one's ``max_iterations`` (so a finished run can be extended).
        run_dir: the run folder: ``checkpoint.pkl``, ``trace.jsonl`` (and the plots drawn afterwards).
        backend: where candidates run (default: this process).
        max_evaluations: stop after this many evaluations (counted at iteration ends; the start included).
        evaluate_start: evaluate the start first (the best so far begins there).
        on_event: progress callback (a bar at the CLI edge).
        meta: recorded in the trace's first record (command, options).

    Returns:
        The best candidate and the counts; ``records`` is the whole trace.

    Raises:
        TuningError: the folder's checkpoint belongs to another problem, or an objective returned NaN.
    """
    backend = backend or InProcess()
    run_dir.mkdir(parents=True, exist_ok=True)
    checkpoint_path, trace_path = run_dir / CHECKPOINT_NAME, run_dir / TRACE_NAME
    records = read_trace(trace_path)
    best = _Best()
    if checkpoint_path.is_file():
        with checkpoint_path.open("rb") as file:
            state = pickle.load(file)
        if state["problem"] != problem.name or state["parameters"] != list(problem.names):
            raise TuningError(f"{checkpoint_path}: checkpoint of problem {state['problem']!r} over "
                              f"{state['parameters']}, not {problem.name!r} over {list(problem.names)}; "
                              f"use another run folder")
        optimizer: Optimizer = state["optimizer"]
        if hasattr(optimizer, "attach"):
            optimizer.attach(problem)  # the trust region keeps no functions in its pickle
        # The iteration budget is this call's, not the pickled one: a finished run resumed with more
        # generations goes on from where it stopped (it ended at once before, having met its old budget).
        optimizer.max_iterations = make_optimizer(problem).max_iterations
        done_iterations = optimizer.iteration
        # Keep what the checkpoint covers plus the finished candidates of the iteration it was in.
        records = [r for r in records if r["kind"] != "iteration" or r["iteration"] < done_iterations]
        records = [r for r in records if r["kind"] != "evaluation" or r["iteration"] <= done_iterations]
        writer = TraceWriter(trace_path, keep=records)
        writer.write({"kind": "resume", "iteration": done_iterations, "time": _now()})
        logger.info("resumed %s at iteration %d", checkpoint_path, done_iterations)
    else:
        optimizer = make_optimizer(problem)
        records = []
        writer = TraceWriter(trace_path, keep=[])
        first = {"kind": "run", "problem": problem.name, "optimizer": optimizer.name, "backend": backend.name,
                 "time": _now(), "rollouts_per_candidate": problem.rollouts_per_candidate,
                 "parameters": [{"name": p.name, "low": p.low, "high": p.high, "unit": p.unit}
                                for p in problem.parameters], **(meta or {})}
        writer.write(first)
        records.append(first)
        # A checkpoint before the first rollout: a run killed in its first iteration resumes too.
        _atomic_pickle(checkpoint_path, {"problem": problem.name, "parameters": list(problem.names),
                                         "optimizer": optimizer})
    evaluations = sorted((r for r in records if r["kind"] == "evaluation"), key=lambda r: (r["iteration"], r["index"]))
    # Before the first iteration the start's record is taken again from the cache by evaluate_batch below.
    finished = [r for r in evaluations if r["iteration"] < optimizer.iteration and optimizer.iteration > 0]
    for index, record in enumerate(finished):
        best.offer(record["loss"], record["values"], record["result"], index)
    count = len(finished)
    shown = {"best": best.entry["loss"]}  # the running best the progress bar shows

    def evaluate_batch(iteration: int, xs: list[np.ndarray]) -> tuple[list[Result], list[float]]:
        nonlocal count
        cached = {r["index"]: r for r in evaluations if r["iteration"] == iteration}
        batch = [problem.values(x) for x in xs]
        results: list[Result | None] = [None] * len(xs)
        losses = [math.nan] * len(xs)
        todo = []
        for index, values in enumerate(batch):
            hit = cached.get(index)
            if hit is not None and hit["values"] == values:
                results[index], losses[index] = hit["result"], hit["loss"]
            else:
                todo.append(index)

        told_indices: list[int] = []

        def told(position: int, result: Result) -> None:
            index = todo[position]
            told_indices.append(index)
            loss, failed = checked_loss(problem, batch[index], result)
            results[index], losses[index] = result, loss
            record = {"kind": "evaluation", "iteration": iteration, "index": index, "x": list(map(float, xs[index])),
                      "values": batch[index], "loss": loss, "failed": failed, "result": result}
            writer.write(record)
            records.append(record)
            shown["best"] = min(shown["best"], loss)
            if on_event is not None:
                on_event(Event("evaluation", iteration, count + len(told_indices), shown["best"], loss))

        backend.map(problem.evaluate, [batch[i] for i in todo], told)
        for index in range(len(xs)):
            best.offer(losses[index], batch[index], results[index], count + index)  # type: ignore[arg-type]
        count += len(xs)
        return results, losses  # type: ignore[return-value]

    try:
        if evaluate_start and optimizer.iteration == 0:
            evaluate_batch(-1, [problem.x0()])  # taken from the trace if a killed run finished it
        while not optimizer.done() and (max_evaluations is None or count < max_evaluations):
            iteration = optimizer.iteration
            xs = optimizer.ask()
            results, losses = evaluate_batch(iteration, xs)
            optimizer.tell(xs, results, losses)
            record = {"kind": "iteration", "iteration": iteration, "evaluations": count,
                      "rollouts": count * problem.rollouts_per_candidate, "batch_min": float(np.min(losses)),
                      "batch_median": float(np.median(losses)), "best_loss": best.entry["loss"],
                      "best_values": best.entry["values"], "time": _now(), **optimizer.summary()}
            writer.write(record)
            records.append(record)
            _atomic_pickle(checkpoint_path, {"problem": problem.name, "parameters": list(problem.names),
                                             "optimizer": optimizer})
            if on_event is not None:
                on_event(Event("iteration", iteration, count, best.entry["loss"], float(np.min(losses))))
    finally:
        writer.close()
    return RunResult(problem.name, best.entry, count, count * problem.rollouts_per_candidate, optimizer.iteration,
                     run_dir, records)


def _now() -> str:
    return datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="seconds")


__all__ = ["CHECKPOINT_NAME", "Event", "Optimizer", "RunResult", "TRACE_NAME", "checked_loss", "run"]
