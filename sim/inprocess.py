"""In-process hosting: agents as Python objects, fed exactly the bytes a TCP client would get, no sockets.

An agent is any object with ``connect_message() -> bytes`` (its first message, the ``scene`` command) and
``step(sense: bytes) -> bytes`` (one sense payload in, one effector payload out), as `agent.agent.Agent`.
The host follows the real connection sequence (REFERENCE §3.2): the agent sends ``scene`` on connecting,
gets its first sense message once the robot exists, and answers every sense message; the engine is the
same `sim.engine.SimEngine` the TCP server runs, so the bytes are identical.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass, field
from typing import Protocol

from sim.engine import LOGGED_ERRORS_PER_AGENT, SimEngine

logger = logging.getLogger(__name__)

#: What the host answers for an agent whose step raised (it only ends that agent's cycle).
SYN_ONLY = b"(syn)"


class HostedAgent(Protocol):
    """An agent the host can run: the scene message first, then one reply per sense message."""

    def connect_message(self) -> bytes: ...

    def step(self, sense: bytes) -> bytes: ...


@dataclass
class HostStats:
    """Counts of a run: cycles stepped, sense messages delivered, agent steps that raised (in all and per agent
    id)."""

    cycles: int = 0
    messages: int = 0
    agent_errors: int = 0
    errors_by_agent: dict[int, int] = field(default_factory=dict)
    transcript: list[tuple[int, int, bytes]] = field(default_factory=list)


class InProcessHost:
    """Runs agents against an engine without sockets.

    Args:
        engine: the simulation (a new `SimEngine()` if None).
        record: keep every delivered sense message in `stats.transcript` as (cycle, agent id, bytes).
    """

    def __init__(self, engine: SimEngine | None = None, record: bool = False) -> None:
        self.engine = engine or SimEngine()
        self.record = record
        self.agents: dict[int, HostedAgent] = {}
        self.stats = HostStats()

    def add(self, agent: HostedAgent) -> int:
        """Connect an agent: its connect message goes to the engine now; returns its agent id."""
        agent_id = self.engine.connect()
        self.agents[agent_id] = agent
        self.engine.receive(agent_id, agent.connect_message())
        return agent_id

    def remove(self, agent_id: int) -> None:
        """Disconnect an agent (its robot leaves the field)."""
        self.agents.pop(agent_id, None)
        self.engine.disconnect(agent_id)

    def run(self, cycles: int) -> HostStats:
        """Step the engine ``cycles`` times; each agent answers each sense message before the next step.

        An agent whose step raises (any Exception: a bad sense message, a bug in a skill) loses that cycle
        only: the host logs it with the agent id and the traceback, counts it in `stats`, and answers
        ``(syn)`` for it, as a server survives a broken client. The match goes on.
        """
        engine, stats = self.engine, self.stats
        for _ in range(cycles):
            out = engine.step()
            stats.cycles += 1
            for agent_id, payload in out.items():
                agent = self.agents.get(agent_id)
                if agent is None:
                    continue
                stats.messages += 1
                if self.record:
                    stats.transcript.append((engine.cycle, agent_id, payload))
                try:
                    reply = agent.step(payload)
                except Exception as error:  # noqa: BLE001 - the host's edge: one agent's failure costs its cycle only
                    reply = SYN_ONLY
                    self._agent_failed(agent_id, error)
                engine.receive(agent_id, reply)
        return stats

    def _agent_failed(self, agent_id: int, error: Exception) -> None:
        stats = self.stats
        stats.agent_errors += 1
        count = stats.errors_by_agent[agent_id] = stats.errors_by_agent.get(agent_id, 0) + 1
        # A broken agent fails every cycle: the first failures with their traceback, the rest quietly.
        level = logging.WARNING if count <= LOGGED_ERRORS_PER_AGENT else logging.DEBUG
        logger.log(level, "agent %d: step raised %s (cycle %d answered with (syn)): %s", agent_id,
                   type(error).__name__, self.engine.cycle, error, exc_info=count <= LOGGED_ERRORS_PER_AGENT)
