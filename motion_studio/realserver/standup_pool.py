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

Run as a command it measures the shipped stand-ups (the agent's StandUp skill by default) from seeded lying
starts on both servers: stood within 3 s (issue 12), stood at all, median and worst time::

    python -m motion_studio.realserver.standup_pool --starts 40 --seed 100 --worlds real,sim

``--transfer`` takes the lying starts of ``motion-studio transfer --seed SEED`` instead (the same outcome per start
as the transfer's real runs, without a server restart per run). Run it outside netns.sh: each worker makes its own
namespace, and inside one they would share ports.
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
    robot_type: int = 0

    def to_json(self) -> str:
        from motions.xml_phase import dumps_xml

        return json.dumps({"motions": {name: dumps_xml(motion) for name, motion in self.motions.items()},
                           "play": self.play, "start": [self.start.side, self.start.seed, self.start.noise_seed,
                                                          self.start.transfer_seed],
                           "use_skill": self.use_skill, "world": self.world, "trace": self.trace,
                           "robot_type": self.robot_type})


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

    benches: dict[tuple[str, int], StandUpBench] = {}

    def bench(world: str, robot_type: int) -> StandUpBench:
        # one server per world and robot type (a robot's type is fixed when it connects)
        key = (world, robot_type)
        if key not in benches:
            for other in [k for k in benches if k[0] == world]:
                benches.pop(other).close()  # one real server per worker, one namespace
            library = default_library(robot_type, motions_dir)
            make = ((lambda behavior: RealWorld(workdir, behavior, scripts, robot_type)) if world == "real"
                    else (lambda behavior: SimWorld(behavior, robot_type=robot_type)))
            benches[key] = StandUpBench(make, library, robot_type)
        return benches[key]

    out = sys.stdout
    sys.stdout = sys.stderr  # stray prints must not break the answers
    signal.signal(signal.SIGTERM, _exit_on_signal)  # SystemExit: the finally below stops the servers
    try:
        for line in sys.stdin:
            try:
                request = json.loads(line)
                motions = {name: loads_xml(text) for name, text in request["motions"].items()}
                side, seed, noise_seed, *transfer_seed = request["start"]
                if request["world"] not in ("real", "sim"):
                    raise ValueError(f"unknown world {request['world']!r}; known: real, sim")
                outcome = bench(request["world"], request.get("robot_type", 0)).rollout(
                    motions, request["play"], RealStart(side, seed, noise_seed, *transfer_seed), request["use_skill"], request["trace"])
                answer = {"ok": True, "outcome": outcome.to_json()}
            except Exception as error:  # the parent logs it and hands the request on once more
                logger.exception("rollout failed")
                answer = {"ok": False, "error": f"{type(error).__name__}: {error}"}
            out.write(json.dumps(answer) + "\n")
            out.flush()
    finally:
        for opened in benches.values():
            opened.close()
    return 0


def _exit_on_signal(signum: int, frame: object) -> None:
    raise SystemExit(128 + signum)


# ---- figures --------------------------------------------------------------------------------------------
#: A stand counts if it comes within this time of the stand-up's start (issue 12) [s].
TARGET_S = 3.0


def figures(times_s: list[float | None], target_s: float = TARGET_S) -> dict[str, object]:
    """Stood within ``target_s`` (count, share), stood at all, median and worst time of the stands."""
    stood = sorted(t for t in times_s if t is not None)
    within = sum(t <= target_s for t in stood)
    return {"starts": len(times_s), "within": within, "share": within / max(1, len(times_s)), "stood": len(stood),
            "median_s": stood[len(stood) // 2] if stood else None, "worst_s": stood[-1] if stood else None}


def measure(sides: list[str], count: int, seed: int, worlds: list[str], use_skill: bool, workers: int,
            motions_dir: Path | None = None, robot_type: int = 0,
            transfer: bool = False) -> dict[str, dict[str, dict[str, object]]]:
    """The shipped stand-ups (or those of ``motions_dir``) from ``count`` seeded starts per side on each
    world (``transfer``: the lying starts of ``motion-studio transfer --seed seed``): side -> world ->
    :func:`figures` plus the times."""
    from motion_studio.realserver.rollout_standup import real_starts, transfer_starts

    make_starts = transfer_starts if transfer else real_starts
    requests = [RolloutRequest({}, f"standup_{side}", start, use_skill, world, robot_type=robot_type)
                for side in sides for world in worlds for start in make_starts(side, count, seed)]
    pool = RolloutPool(workers, motions_dir=motions_dir)
    try:
        outcomes = pool.run(requests)
    finally:
        pool.close()
    out: dict[str, dict[str, dict[str, object]]] = {}
    for side in sides:
        for world in worlds:
            times = [o.time_s if o else None for r, o in zip(requests, outcomes)
                     if r.start.side == side and r.world == world]
            out.setdefault(side, {})[world] = {**figures(times), "times_s": times}
    return out


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--worker", action="store_true", help="answer rollout requests on stdin (JSON lines)")
    parser.add_argument("--workdir", type=Path, default=Path(tempfile.gettempdir()) / "standup_worker")
    parser.add_argument("--scripts", type=Path, default=None, help="the real-server scripts folder")
    parser.add_argument("--motions-dir", type=Path, default=None, help="motion files (default the shipped ones)")
    parser.add_argument("--sides", default="back,front", help="measure these stand-ups (not with --worker)")
    parser.add_argument("--starts", type=int, default=20, help="seeded lying starts per side")
    parser.add_argument("--seed", type=int, default=100, help="seed of the starts (the tuner uses 1 by default)")
    parser.add_argument("--worlds", default="real,sim", help="real, sim or both (comma-separated)")
    parser.add_argument("--motion", action="store_true", help="play the motion itself, not the StandUp skill")
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--type", type=int, default=0, help="robot type (its own stand-ups when it has them)")
    parser.add_argument("--json", type=Path, help="also write the figures as JSON")
    parser.add_argument("--transfer", action="store_true",
                        help="the lying starts of motion-studio transfer --seed SEED (zero pose, the case's fall)")
    args = parser.parse_args(argv)
    logging.basicConfig(level=logging.WARNING, format="%(levelname)s %(name)s: %(message)s")
    if args.worker:
        return _worker(args.workdir, args.scripts, args.motions_dir)
    results = measure(args.sides.split(","), args.starts, args.seed, args.worlds.split(","), not args.motion,
                      args.workers, args.motions_dir, args.type, args.transfer)
    for side, worlds in results.items():
        for world, row in worlds.items():
            print(f"standup_{side} type {args.type} {world:4s}: within {TARGET_S:g} s {row['within']}/{row['starts']} "
                  f"({100 * row['share']:.0f} %), stood {row['stood']}, median {row['median_s']} s, "
                  f"worst {row['worst_s']} s")
    if args.json:
        args.json.write_text(json.dumps(results, indent=1))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
