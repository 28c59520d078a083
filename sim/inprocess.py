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

from agent.protocol.errors import ProtocolError
from sim.engine import SimEngine

logger = logging.getLogger(__name__)

#: What the host answers for an agent whose step raised (it only ends that agent's cycle).
SYN_ONLY = b"(syn)"


class HostedAgent(Protocol):
    """An agent the host can run: the scene message first, then one reply per sense message."""

    def connect_message(self) -> bytes: ...

    def step(self, sense: bytes) -> bytes: ...


@dataclass
class HostStats:
    """Counts of a run: cycles stepped, sense messages delivered, agent steps that raised."""

    cycles: int = 0
    messages: int = 0
    agent_errors: int = 0
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
        """Step the engine ``cycles`` times; each agent answers each sense message before the next step."""
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
                except ProtocolError as error:
                    stats.agent_errors += 1
                    logger.warning("agent %d could not read its sense message: %s", agent_id, error)
                    reply = SYN_ONLY
                engine.receive(agent_id, reply)
        return stats
