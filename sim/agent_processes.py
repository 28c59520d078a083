"""Agents in worker processes: the engine keeps this process, the agents think in others, in lockstep.

`AgentProcessHost` runs the same cycle as `sim.inprocess.InProcessHost` (same sense bytes in, each agent's
reply passed to `SimEngine.receive` before the next step), with the agents built and stepped in worker
processes that exchange the per-cycle message bytes with this one through pipes. Since an agent sees only its
own bytes and the engine gets the replies in the same order at the same point of the cycle, a match plays
byte for byte as in-process for the same seed (tests/sim/test_agent_processes.py holds that).

Two things run at once, so a match uses more than one core:
- the agents of different workers (agents are spread over the workers in connection order, round robin);
- the agents and the engine. The sense messages of step k are final when `SimEngine.finish_step` of step k
  returns, and the replies to them are applied by `SimEngine.begin_step` of step k + 2 (as in-process: the
  next step hands the messages out, the one after applies the replies). So the host sends them on at once:
  while the agents answer them, the engine collects and applies the replies to step k - 1's messages and
  runs step k + 1's physics. Each worker answers its batches in the order it got them (at most two wait in its
  pipe), and the replies reach the engine at the same point of the cycle and in the same order as in-process.
  Sending at ``begin_step`` instead (the first design) left both workers idle while the engine took in the
  replies and applied them (about 1 ms of CPU a cycle in 11 v 11), and a core idle whenever one side waited
  for the other within the cycle; one batch of slack lets each side run on.

Failures: an agent's exception costs its cycle only (`sim.match.CrashGuard`, in the worker, as in-process).
A worker that dies (a segfault, ``os._exit``, killed) or answers nothing for `REPLY_TIMEOUT_S` costs its
agents the rest of the match: they answer ``(syn)`` every cycle (counted in ``stats.agent_errors``), their
robots stay on the field, and the match goes on. Workers end with this process: `close` (also on the way
out of a ``with`` block) stops and joins them, and each worker watches its parent
(`kinematics.child_process.end_with_parent`) in case this process is killed.
"""

from __future__ import annotations

import logging
import multiprocessing
import os
import signal
import time
from collections import deque
from collections.abc import Callable
from dataclasses import dataclass, field
from multiprocessing.connection import Connection
from typing import Any

from kinematics.child_process import end_with_parent
from sim.engine import SimEngine
from sim.inprocess import SYN_ONLY, HostStats

logger = logging.getLogger(__name__)

#: (team name, unum, robot type) -> agent with ``connect_message()`` and ``step(bytes) -> bytes``.
AgentFactory = Callable[[str, int, int], Any]
#: Seconds to wait for a worker's answer (an agent's build or one cycle of its agents) before it counts as dead.
REPLY_TIMEOUT_S = 60.0
#: Seconds a closing worker gets to leave by itself before it is terminated, then killed.
CLOSE_GRACE_S = 2.0


class AgentBuildError(RuntimeError):
    """The factory raised in a worker while building an agent (as `run_match` raises in-process)."""


@dataclass
class _Worker:
    process: Any
    conn: Connection
    agent_ids: list[int] = field(default_factory=list)
    alive: bool = True
    guard_errors: int = 0    # the CrashGuard errors of its agents, as last reported by the worker
    built: dict[int, tuple[bool, bytes | str]] = field(default_factory=dict)   # answers to builds, not yet read
    # answers to "step" read while waiting for something else (a build), oldest first, not yet passed on
    stepped: deque[tuple[Any, ...]] = field(default_factory=deque)


class AgentProcessHost:
    """Hosts agents in ``processes`` worker processes against ``engine`` (see the module docstring).

    Use: ``host.build(team, unum, robot_type)`` for each agent up front (the workers build them in parallel,
    in order), then ``host.connect(handle)`` at the moment the agent connects (its scene message goes to the
    engine then), and ``host.run(cycles)`` or ``start_cycle``/``end_cycle`` pairs.

    Args:
        engine: the simulation; None to set ``host.engine`` after the workers started (before any `connect`):
            they fork from this process, and need nothing of an engine built before them.
        make_agent: the agent factory, called in the workers (forked: it need not pickle).
        processes: worker processes (>= 1).
    """

    def __init__(self, engine: SimEngine | None, make_agent: AgentFactory, processes: int = 2) -> None:
        if processes < 1:
            raise ValueError(f"processes must be >= 1, got {processes}")
        self.engine = engine
        self.stats = HostStats()
        self._workers: list[_Worker] = []
        self._handles: list[tuple[int, str]] = []   # build order: (worker index, name)
        self._worker_of: dict[int, _Worker] = {}
        self._pending: dict[int, bytes] | None = None
        # messages handed to the workers whose replies are not collected yet, oldest first, with the workers
        # that got a batch of them: the current cycle's and the batch sent ahead (see the module docstring)
        self._in_flight: deque[tuple[dict[int, bytes], list[_Worker]]] = deque()
        context = multiprocessing.get_context("fork" if "fork" in multiprocessing.get_all_start_methods() else None)
        daemon = not multiprocessing.current_process().daemon   # a daemonic pool worker may not have daemons
        parent = os.getpid()
        try:
            for index in range(processes):
                ours, theirs = context.Pipe()
                process = context.Process(target=_serve, args=(theirs, make_agent, parent),
                                          name=f"agents-{index}", daemon=daemon)
                process.start()
                theirs.close()
                self._workers.append(_Worker(process, ours))
        except BaseException:
            self.close()
            raise

    # ---- agents --------------------------------------------------------------------------------------
    def build(self, team: str, unum: int, robot_type: int, name: str | None = None) -> int:
        """Ask a worker to build an agent (returns at once); returns the handle for `connect`."""
        handle = len(self._handles)
        worker_index = handle % len(self._workers)
        name = name or f"{team} {unum}"
        self._handles.append((worker_index, name))
        worker = self._workers[worker_index]
        if worker.alive:
            try:
                worker.conn.send(("build", handle, team, unum, robot_type, name))
            except OSError:
                self._lost(worker, "it could not be sent an agent to build")
        return handle

    def connect(self, handle: int) -> int:
        """Connect the agent built as ``handle``: its connect message goes to the engine; returns its agent id.

        Raises:
            AgentBuildError: the factory raised in the worker (the match cannot have that agent).
        """
        worker_index, name = self._handles[handle]
        worker = self._workers[worker_index]
        message = None
        while worker.alive and handle not in worker.built:
            self._receive(worker, "building agent " + name)
        if handle in worker.built:
            ok, message = worker.built.pop(handle)
            if not ok:
                raise AgentBuildError(f"agent {name} not built: {message}")
        agent_id = self.engine.connect()
        if worker.alive:
            try:
                worker.conn.send(("id", handle, agent_id))
            except OSError:
                self._lost(worker, "it could not be sent an agent id")
        worker.agent_ids.append(agent_id)
        self._worker_of[agent_id] = worker
        if message is not None:
            self.engine.receive(agent_id, message)
        return agent_id

    @property
    def guard_errors(self) -> int:
        """Agent steps that raised in the workers (each answered ``(syn)`` for its cycle)."""
        return sum(worker.guard_errors for worker in self._workers)

    @property
    def workers_alive(self) -> int:
        return sum(worker.alive for worker in self._workers)

    # ---- the cycle -----------------------------------------------------------------------------------
    def run(self, cycles: int) -> HostStats:
        """Step the engine ``cycles`` times; every agent answers each sense message before the next step."""
        for _ in range(cycles):
            self.start_cycle()
            self.end_cycle()
        return self.stats

    def start_cycle(self) -> None:
        """Step the engine: apply the replies collected so far, run the physics, and send this step's messages
        on to the workers at once (they answer them while the engine waits for, and applies, the previous
        step's replies: see the module docstring).

        Between `start_cycle` and `end_cycle` the caller may read the world and the referee (what the
        in-process host's caller does after `InProcessHost.run`), and change the referee's play mode (the
        messages sent ahead were written before: in-process, too, they are made before the caller looks)."""
        if self._pending is not None:
            raise RuntimeError("start_cycle twice without end_cycle")
        engine, stats = self.engine, self.stats
        out = engine.begin_step()
        stats.cycles += 1
        stats.messages += sum(agent_id in self._worker_of for agent_id in out)
        if not self._in_flight:   # the first cycle: nothing was sent ahead
            self._in_flight.append((out, self._send(out)))
        elif self._in_flight[0][0] is not out:
            raise RuntimeError("the engine handed out other messages than those sent ahead "
                               "(was the engine stepped outside this host?)")
        self._pending = out
        ahead = engine.finish_step()
        self._in_flight.append((ahead, self._send(ahead)))

    def end_cycle(self) -> None:
        """Collect the replies to the messages `start_cycle` handed out and pass them to the engine in their
        order (the in-process order)."""
        out, self._pending = self._pending, None
        if out is None:
            raise RuntimeError("end_cycle without start_cycle")
        _, sent = self._in_flight.popleft()
        replies: dict[int, bytes] = {}
        for worker in sent:
            answer = self._stepped(worker, f"cycle {self.engine.cycle}")
            if answer is not None:
                replies.update(answer[1])
                worker.guard_errors = answer[2]
        engine, stats = self.engine, self.stats
        for agent_id in out:
            worker = self._worker_of.get(agent_id)
            if worker is None:
                continue
            reply = replies.get(agent_id)
            if reply is None:   # its worker is gone
                reply = SYN_ONLY
                stats.agent_errors += 1
                stats.errors_by_agent[agent_id] = stats.errors_by_agent.get(agent_id, 0) + 1
            engine.receive(agent_id, reply)

    def _send(self, messages: dict[int, bytes]) -> list[_Worker]:
        """Send each worker the messages of its agents (one pipe message each); returns the workers sent to."""
        batches: dict[int, list[tuple[int, bytes]]] = {}
        for agent_id, payload in messages.items():
            worker = self._worker_of.get(agent_id)
            if worker is not None:
                batches.setdefault(id(worker), []).append((agent_id, payload))
        sent = []
        for worker in self._workers:
            batch = batches.get(id(worker))
            if batch is None or not worker.alive:
                continue
            try:
                worker.conn.send(("step", batch))
                sent.append(worker)
            except OSError:
                self._lost(worker, "it could not be sent its agents' messages")
        return sent

    # ---- workers -------------------------------------------------------------------------------------
    def _stepped(self, worker: _Worker, what: str) -> tuple[Any, ...] | None:
        """The worker's answer to its oldest batch of messages not yet answered here, or None if it is lost."""
        while not worker.stepped and worker.alive:
            self._receive(worker, what)
        return worker.stepped.popleft() if worker.stepped else None

    def _receive(self, worker: _Worker, what: str) -> None:
        """Read the worker's next answer into ``worker.built`` or ``worker.stepped``; mark the worker lost when
        it ended or said nothing for `REPLY_TIMEOUT_S`."""
        try:
            if worker.conn.poll(REPLY_TIMEOUT_S):
                answer = worker.conn.recv()
                if answer[0] == "built":
                    worker.built[answer[1]] = (answer[2], answer[3])
                elif answer[0] == "stepped":
                    worker.stepped.append(answer)
                return
            self._lost(worker, f"no answer within {REPLY_TIMEOUT_S:g} s ({what})")
        except (EOFError, OSError):
            self._lost(worker, f"it ended ({what}; exit code {worker.process.exitcode})")

    def _lost(self, worker: _Worker, reason: str) -> None:
        if not worker.alive:
            return
        worker.alive = False
        logger.error("agent worker %s lost: %s; its agents %s answer (syn) from now on", worker.process.name,
                     reason, worker.agent_ids or "(none connected yet)")
        _stop(worker)

    def close(self) -> None:
        """Stop the workers and wait for them (idempotent)."""
        for worker in self._workers:
            if worker.alive:
                try:
                    worker.conn.send(("close",))
                except OSError:
                    pass
            worker.alive = False
        for worker in self._workers:
            _stop(worker)
        self._in_flight.clear()
        self._pending = None

    def __enter__(self) -> AgentProcessHost:
        return self

    def __exit__(self, *_exc: object) -> None:
        self.close()


def _stop(worker: _Worker) -> None:
    process = worker.process
    # The batch sent ahead is answered after the match: read such answers while the worker leaves, so that one
    # too big for the pipe never keeps it writing until it is terminated.
    deadline = time.monotonic() + CLOSE_GRACE_S
    while process.is_alive() and time.monotonic() < deadline:
        try:
            if worker.conn.poll(0.01):
                worker.conn.recv()
        except (EOFError, OSError):
            break
    process.join(max(0.0, deadline - time.monotonic()))
    if process.is_alive():
        process.terminate()
        process.join(CLOSE_GRACE_S)
    if process.is_alive():
        process.kill()
        process.join()
    worker.conn.close()


def _serve(conn: Connection, make_agent: AgentFactory, parent_pid: int) -> None:
    """A worker: builds agents, answers each cycle's messages, until told to close or its parent is gone."""
    from sim.match import CrashGuard

    end_with_parent(parent_pid)
    signal.signal(signal.SIGINT, signal.SIG_IGN)   # Ctrl-C is the match process's to handle; it closes us
    built: dict[int, CrashGuard] = {}
    by_id: dict[int, CrashGuard] = {}
    while True:
        try:
            message = conn.recv()
        except (EOFError, OSError):
            return
        kind = message[0]
        if kind == "step":
            conn.send(("stepped", [(agent_id, by_id[agent_id].step(payload)) for agent_id, payload in message[1]],
                       sum(guard.errors for guard in built.values())))
        elif kind == "build":
            _, handle, team, unum, robot_type, name = message
            try:
                guard = CrashGuard(make_agent(team, unum, robot_type), name)
                connect = guard.connect_message()
            except Exception as error:  # noqa: BLE001 - reported to the match process, which raises it
                conn.send(("built", handle, False, f"{type(error).__name__}: {error}"))
                continue
            built[handle] = guard
            conn.send(("built", handle, True, connect))
        elif kind == "id":
            by_id[message[2]] = built[message[1]]
        elif kind == "close":
            return
