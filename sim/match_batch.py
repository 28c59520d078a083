"""Batches of matches in parallel processes, checkpointed line by line so a crash loses no finished match.

Each finished match is appended to a JSONL file as soon as it ends; a rerun with the same file skips the
match ids already there (resume). One process per match: MuJoCo and the agents are single-threaded, so
processes are how a batch uses the cores. Beyond one machine, the same `run_one` can be handed to any
executor (a Ray pool, say) by passing it as ``executor``.
"""

from __future__ import annotations

import json
import logging
from collections.abc import Callable, Iterable
from concurrent.futures import Executor, ProcessPoolExecutor, as_completed
from dataclasses import asdict, replace
from pathlib import Path
from typing import Any

from kinematics.child_process import end_with_parent
from sim.match import AgentFactory, MatchConfig, MatchResult, run_match

logger = logging.getLogger(__name__)


def finished_ids(checkpoint: Path) -> set[str]:
    """Match ids already in the checkpoint; a torn last line (crash mid-write) is ignored, not fatal."""
    if not checkpoint.exists():
        return set()
    done = set()
    for number, line in enumerate(checkpoint.read_text().splitlines(), 1):
        try:
            done.add(json.loads(line)["match_id"])
        except (json.JSONDecodeError, KeyError, TypeError):
            logger.warning("%s:%d: unreadable checkpoint line skipped", checkpoint, number)
    return done


def read_results(checkpoint: Path) -> list[dict[str, Any]]:
    """Every readable result of a checkpoint file, in file order."""
    results = []
    if checkpoint.exists():
        for line in checkpoint.read_text().splitlines():
            try:
                results.append(json.loads(line))
            except json.JSONDecodeError:
                continue
    return results


def append_result(checkpoint: Path, result: dict[str, Any]) -> None:
    """Append one result as a JSON line and flush it, so it survives a crash of what runs next.

    A torn last line (a crash mid-write) is closed first, so the new result starts a line of its own.
    """
    torn = checkpoint.exists() and checkpoint.stat().st_size > 0 and not checkpoint.read_bytes().endswith(b"\n")
    with checkpoint.open("a") as handle:
        if torn:
            handle.write("\n")
        handle.write(json.dumps(result) + "\n")
        handle.flush()


def run_one(config: MatchConfig, make_agent: AgentFactory) -> dict[str, Any]:
    """One match in this process; the failure of a match is reported as a result, not raised."""
    try:
        return asdict(run_match(config, make_agent))
    except Exception as error:  # a batch goes on when one match breaks; the reason is kept
        logger.exception("match %s failed", config.match_id)
        return {**asdict(MatchResult(config.match_id, config.seed)), "error": f"{type(error).__name__}: {error}"}


def batch_configs(base: MatchConfig, matches: int, first_seed: int = 0) -> list[MatchConfig]:
    """``matches`` copies of ``base`` with seeds first_seed.. and ids ``<base id>-<seed>``."""
    configs = []
    for seed in range(first_seed, first_seed + matches):
        match_id = f"{base.match_id}-{seed}"
        log_path = None
        if base.log_path is not None:  # "out/match.log.gz" -> "out/match-3.log.gz"
            base_log = Path(base.log_path)
            log_path = str(base_log.parent / (match_id + "".join(base_log.suffixes)))
        configs.append(replace(base, seed=seed, match_id=match_id, log_path=log_path))
    return configs


#: What plays one match of a batch: (config, agent factory) -> a JSON-able result with the config's ``match_id``.
MatchRunner = Callable[[MatchConfig, AgentFactory], dict[str, Any]]


def run_batch(configs: Iterable[MatchConfig], make_agent: AgentFactory, checkpoint: Path, workers: int = 1,
              on_result: Callable[[dict[str, Any]], None] | None = None,
              executor: Executor | None = None, run: MatchRunner = run_one) -> list[dict[str, Any]]:
    """Run the matches not yet in ``checkpoint``; returns all results in the checkpoint afterwards.

    Args:
        configs: the matches (distinct match ids).
        make_agent: a picklable (module-level) agent factory.
        checkpoint: JSONL file, appended to as each match ends.
        workers: processes (1 = run here, no pool).
        on_result: progress callback per finished match.
        executor: an executor to use instead of a local process pool.
        run: what plays one match (``run_one``; a picklable module-level function, e.g. the watched match of
            ``motion_studio.match_diagnose``), which reports its own failures as results.
    """
    checkpoint.parent.mkdir(parents=True, exist_ok=True)
    done = finished_ids(checkpoint)
    todo = [c for c in configs if c.match_id not in done]
    if done:
        logger.info("resuming: %d matches already in %s, %d to run", len(done), checkpoint, len(todo))

    def record(result: dict[str, Any]) -> None:
        append_result(checkpoint, result)
        if on_result is not None:
            on_result(result)

    if workers <= 1 and executor is None:
        for config in todo:
            record(run(config, make_agent))
    else:
        # workers end with this process even when it is killed (they would otherwise wait on the queue for ever)
        pool = executor or ProcessPoolExecutor(max_workers=workers, initializer=end_with_parent)
        try:
            futures = [pool.submit(run, config, make_agent) for config in todo]
            for future in as_completed(futures):
                record(future.result())
        finally:
            if executor is None:
                pool.shutdown()
    return read_results(checkpoint)
