"""Stand-up rollouts spread over worker processes, each with its own real rcssserver3d in its own private
loopback namespace (netns.sh), or with our simulator.

A worker (``python -m motion_studio.realserver.standup_pool --worker``, started through netns.sh) keeps one
``rollout_standup.StandUpBench`` per world and answers JSON lines on stdin/stdout: a request names the motions
to judge (XML phase text), the stand-up to play (or the StandUp skill), the lying start and the world
("real" or "sim"); the answer is the ``StandUpOutcome`` as JSON, or the error. ``RolloutPool.run`` hands the
requests to idle workers and collects the answers in order; a worker that dies is started again and its
request handed on once more.

    pool = RolloutPool(workers=2)
    outcomes = pool.run([RolloutRequest({"standup_back": motion}, "standup_back", RealStart("back", 3))])
    pool.close()
"""

from __future__ import annotations

import argparse
import json
import logging
import os
import selectors
import signal
import subprocess
import sys
import tempfile
from dataclasses import dataclass, field
from pathlib import Path

from motion_studio.realserver.rollout_standup import RealStart, StandUpOutcome
from motions.model import Motion

logger = logging.getLogger(__name__)

#: Seconds a worker may take for one rollout before it counts as hung (a rollout takes about 0.5 s, a
#: server start 1-2 s, a stalled server 2 x 10 s before the bench gives up).
REQUEST_TIMEOUT_S = 90.0


@dataclass(frozen=True)
class RolloutRequest:
    """One rollout: ``motions`` (name -> Motion) replace the shipped ones of those names; ``play`` is the
    stand-up played (ignored with ``use_skill``: the StandUp skill chooses); ``world``: "real" or "sim"."""

    motions: dict[str, Motion]
    play: str
    start: RealStart
    use_skill: bool = False
    world: str = "real"
    trace: bool = False

    def to_json(self) -> str:
        from motions.xml_phase import dumps_xml

        return json.dumps({"motions": {name: dumps_xml(motion) for name, motion in self.motions.items()},
                           "play": self.play, "start": [self.start.side, self.start.seed, self.start.noise_seed],
                           "use_skill": self.use_skill, "world": self.world, "trace": self.trace})


def outcome_from_json(data: dict) -> StandUpOutcome:
    return StandUpOutcome(**data)


@dataclass
class _Worker:
    process: subprocess.Popen
    busy: int | None = None
    """Index of the request it is working on."""
    buffer: bytes = b""
    started_s: float = 0.0
    retried: set[int] = field(default_factory=set)


class RolloutPool:
    """``workers`` worker processes (each its own namespace and, once asked for a real rollout, its own
    real server).

    Args:
        workers: how many processes (the real server takes about one core while it runs).
        workdir: where the workers keep their server logs (``<workdir>/worker<i>``); default a temp folder.
        motions_dir: the folder of the motion files the workers load (default the shipped ones).
        scripts: the real-server scripts folder (default ``motion_studio.realserver.paths.scripts_dir``).
    """

    def __init__(self, workers: int = 1, workdir: Path | None = None, motions_dir: Path | None = None,
                 scripts: Path | None = None) -> None:
        from motion_studio.realserver.paths import checked_scripts_dir

        self.scripts = checked_scripts_dir(scripts)
        self.workdir = workdir or Path(tempfile.mkdtemp(prefix="standup_pool_"))
        self.motions_dir = motions_dir
        self.selector = selectors.DefaultSelector()
        self.workers = [self._start(index) for index in range(max(1, workers))]

    def _start(self, index: int) -> _Worker:
        command = [str(self.scripts / "netns.sh"), sys.executable, "-m", "motion_studio.realserver.standup_pool",
                   "--worker", "--workdir", str(self.workdir / f"worker{index}"), "--scripts", str(self.scripts)]
        if self.motions_dir is not None:
            command += ["--motions-dir", str(self.motions_dir)]
        process = subprocess.Popen(command, stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                                   stderr=open(self.workdir / f"worker{index}.log", "ab"),
                                   cwd=Path(__file__).resolve().parents[2], start_new_session=True)
        os.set_blocking(process.stdout.fileno(), False)
        worker = _Worker(process)
        self.selector.register(process.stdout, selectors.EVENT_READ, worker)
        return worker

    def _restart(self, worker: _Worker) -> _Worker:
        index = self.workers.index(worker)
        self.selector.unregister(worker.process.stdout)
        _stop(worker.process)
        self.workers[index] = self._start(index)
        return self.workers[index]

    def run(self, requests: list[RolloutRequest]) -> list[StandUpOutcome | None]:
        """The outcome of each request, in order (None where a worker failed it twice)."""
        import time

        results: list[StandUpOutcome | None] = [None] * len(requests)
        pending = list(range(len(requests)))
        attempts = [0] * len(requests)
        done = 0
        while done < len(requests):
            for worker in list(self.workers):
                if worker.busy is None and pending:
                    index = pending.pop(0)
                    attempts[index] += 1
                    worker.busy, worker.started_s = index, time.monotonic()
                    try:
                        worker.process.stdin.write((requests[index].to_json() + "\n").encode())
                        worker.process.stdin.flush()
                    except OSError:
                        worker.busy = None
                        pending.insert(0, index)
                        attempts[index] -= 1
                        self._restart(worker)
            for key, _ in self.selector.select(timeout=1.0):
                worker = key.data
                chunk = worker.process.stdout.read() or b""
                if not chunk and worker.process.poll() is not None:
                    continue  # died: handled below
                worker.buffer += chunk
                while b"\n" in worker.buffer and worker.busy is not None:
                    line, worker.buffer = worker.buffer.split(b"\n", 1)
                    answer = json.loads(line)
                    index, worker.busy = worker.busy, None
                    if answer.get("ok"):
                        results[index] = outcome_from_json(answer["outcome"])
                        done += 1
                    else:
                        logger.warning("rollout %d failed: %s", index, answer.get("error"))
                        done += self._retry_or_give_up(index, attempts, pending)
            now = time.monotonic()
            for worker in list(self.workers):
                dead = worker.process.poll() is not None
                if worker.busy is not None and (dead or now - worker.started_s > REQUEST_TIMEOUT_S):
                    logger.warning("worker %s %s; starting it again", worker.process.pid,
                                   "died" if dead else "hung")
                    index = worker.busy
                    self._restart(worker)
                    done += self._retry_or_give_up(index, attempts, pending)
                elif dead:
                    self._restart(worker)
        return results

    @staticmethod
    def _retry_or_give_up(index: int, attempts: list[int], pending: list[int]) -> int:
        if attempts[index] < 2:
            pending.insert(0, index)
            return 0
        return 1

    def close(self) -> None:
        for worker in self.workers:
            self.selector.unregister(worker.process.stdout)
            _stop(worker.process)
        self.workers = []


def _stop(process: subprocess.Popen) -> None:
    """End a worker: EOF on its stdin, then SIGTERM (either way it stops its server first), then SIGKILL."""
    try:
        process.stdin.close()
    except OSError:
        pass
    for ask in (None, process.terminate):
        if ask is not None:
            ask()
        try:
            process.wait(15)
            return
        except subprocess.TimeoutExpired:
            continue
    process.kill()
    process.wait(5)


# ---- the worker --------------------------------------------------------------------------------------
def _worker(workdir: Path, scripts: Path | None, motions_dir: Path | None) -> int:
    from agent.motion import default_library
    from motion_studio.realserver.rollout_standup import RealWorld, SimWorld, StandUpBench
    from motions.xml_phase import loads_xml

    library = default_library(0, motions_dir)
    benches = {"real": StandUpBench(lambda behavior: RealWorld(workdir, behavior, scripts), library),
               "sim": StandUpBench(lambda behavior: SimWorld(behavior), library)}
    out = sys.stdout
    sys.stdout = sys.stderr  # stray prints must not break the answers
    signal.signal(signal.SIGTERM, _exit_on_signal)  # SystemExit: the finally below stops the servers
    try:
        for line in sys.stdin:
            try:
                request = json.loads(line)
                motions = {name: loads_xml(text) for name, text in request["motions"].items()}
                side, seed, noise_seed = request["start"]
                outcome = benches[request["world"]].rollout(motions, request["play"], RealStart(side, seed, noise_seed),
                                                            request["use_skill"], request["trace"])
                answer = {"ok": True, "outcome": outcome.to_json()}
            except Exception as error:  # the parent logs it and hands the request on once more
                logger.exception("rollout failed")
                answer = {"ok": False, "error": f"{type(error).__name__}: {error}"}
            out.write(json.dumps(answer) + "\n")
            out.flush()
    finally:
        for bench in benches.values():
            bench.close()
    return 0


def _exit_on_signal(signum: int, frame: object) -> None:
    raise SystemExit(128 + signum)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--worker", action="store_true", help="answer rollout requests on stdin (JSON lines)")
    parser.add_argument("--workdir", type=Path, default=Path(tempfile.gettempdir()) / "standup_worker")
    parser.add_argument("--scripts", type=Path, default=None, help="the real-server scripts folder")
    parser.add_argument("--motions-dir", type=Path, default=None, help="motion files (default the shipped ones)")
    args = parser.parse_args(argv)
    if not args.worker:
        parser.error("only --worker is supported")
    logging.basicConfig(level=logging.WARNING, format="%(levelname)s %(name)s: %(message)s")
    return _worker(args.workdir, args.scripts, args.motions_dir)


if __name__ == "__main__":
    raise SystemExit(main())
