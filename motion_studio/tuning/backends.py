"""Rollout backends: where a batch of candidates is evaluated (this process, local processes, Ray, or a
whole-batch evaluator such as the real rcssserver3d bench).

Why one interface: the run loop hands a batch over and is told each result as it finishes, so the trace
records every finished rollout at once (a run killed mid-batch loses none of them) whatever runs them.
A candidate whose evaluation raises is a failed candidate (``{"failed": "..."}``), never a crash of the run.
"""

from __future__ import annotations

import logging
import traceback
from collections.abc import Callable, Sequence
from concurrent.futures import Executor, ProcessPoolExecutor, as_completed
from typing import Protocol

from motion_studio.tuning.errors import TuningError
from motion_studio.tuning.problem import Evaluate, Result

logger = logging.getLogger(__name__)

#: Told each finished candidate: (index in the batch, its result).
OnResult = Callable[[int, Result], None]
#: Backend names of the CLI.
BACKENDS = ("inprocess", "processes", "ray")


def guarded(evaluate: Evaluate, values: dict[str, float]) -> Result:
    """``evaluate(values)``, with an exception (a diverging rollout, an IK failure) turned into a failed
    candidate whose ``failed`` field is the error's one-line summary. Module-level so processes can run it."""
    try:
        result = evaluate(values)
    except Exception as error:  # noqa: BLE001 - any rollout failure is a failed candidate, by design
        logger.debug("candidate %s failed:\n%s", values, traceback.format_exc())
        return {"failed": f"{type(error).__name__}: {str(error).splitlines()[0] if str(error) else ''}"[:300]}
    if not isinstance(result, dict) or "loss" not in result:
        return {"failed": f"the evaluation returned {type(result).__name__} without a 'loss'"}
    return result


class Backend(Protocol):
    """Evaluates a batch; calls ``on_result`` as each candidate finishes; returns the results in order."""

    name: str

    def map(self, evaluate: Evaluate, batch: Sequence[dict[str, float]], on_result: OnResult) -> list[Result]: ...

    def close(self) -> None: ...


class InProcess:
    """One candidate after the other in this process (closures allowed: the real kick bench uses it)."""

    name = "inprocess"

    def map(self, evaluate: Evaluate, batch: Sequence[dict[str, float]], on_result: OnResult) -> list[Result]:
        results = []
        for index, values in enumerate(batch):
            results.append(guarded(evaluate, values))
            on_result(index, results[-1])
        return results

    def close(self) -> None:
        pass


class ExecutorBackend:
    """Candidates as tasks of a ``concurrent.futures.Executor`` (local processes, or Ray's adapter
    ``sim.ray_executor.RayExecutor``); ``evaluate`` and the values must pickle."""

    def __init__(self, name: str, executor: Executor) -> None:
        self.name = name
        self._executor = executor

    def map(self, evaluate: Evaluate, batch: Sequence[dict[str, float]], on_result: OnResult) -> list[Result]:
        futures = {self._executor.submit(guarded, evaluate, values): index for index, values in enumerate(batch)}
        results: list[Result | None] = [None] * len(batch)
        for future in as_completed(futures):
            index = futures[future]
            try:
                result = future.result()
            except Exception as error:  # noqa: BLE001 - a worker that died (segfault, OOM) fails its candidate
                result = {"failed": f"worker died: {type(error).__name__}: {error}"[:300]}
            results[index] = result
            on_result(index, result)
        return [r if r is not None else {"failed": "no result"} for r in results]

    def close(self) -> None:
        self._executor.shutdown()


class BatchBackend:
    """A whole batch at once through ``evaluate_batch`` (e.g. the real-server stand-up pool, which spreads a
    generation over its servers itself); the results are told when the batch returns."""

    def __init__(self, name: str, evaluate_batch: Callable[[Sequence[dict[str, float]]], list[Result]],
                 close: Callable[[], None] | None = None) -> None:
        self.name = name
        self._evaluate_batch = evaluate_batch
        self._close = close

    def map(self, evaluate: Evaluate, batch: Sequence[dict[str, float]], on_result: OnResult) -> list[Result]:
        try:
            results = list(self._evaluate_batch(batch))
        except Exception as error:  # noqa: BLE001 - a failed batch fails its candidates, the run goes on
            results = [{"failed": f"{type(error).__name__}: {error}"[:300]} for _ in batch]
        if len(results) != len(batch):
            raise TuningError(f"backend {self.name!r} returned {len(results)} results for {len(batch)} candidates")
        for index, result in enumerate(results):
            on_result(index, result)
        return results

    def close(self) -> None:
        if self._close is not None:
            self._close()


def make_backend(name: str = "inprocess", workers: int = 1, ray_address: str | None = None) -> Backend:
    """The backend called ``name`` (``processes`` with ``workers``; ``ray`` joins ``ray_address`` or starts a
    local Ray). ``ray_address`` alone selects Ray.

    Raises:
        TuningError: an unknown name (the message lists the known ones).
    """
    if ray_address and name == "inprocess":
        name = "ray"
    if name == "inprocess":
        return InProcess() if workers <= 1 else ExecutorBackend("processes", ProcessPoolExecutor(workers))
    if name == "processes":
        return ExecutorBackend("processes", ProcessPoolExecutor(max(1, workers)))
    if name == "ray":
        from sim.ray_executor import LOCAL, RayExecutor

        return ExecutorBackend("ray", RayExecutor(ray_address or LOCAL, num_cpus=workers if not ray_address else None))
    raise TuningError(f"unknown rollout backend {name!r}; known: {', '.join(BACKENDS)}")


__all__ = ["BACKENDS", "Backend", "BatchBackend", "ExecutorBackend", "InProcess", "OnResult", "guarded",
           "make_backend"]
