"""sim.inprocess: agents get exactly the bytes a TCP client of the same engine would get."""

from __future__ import annotations

from agent import Agent, AgentConfig
from sim.engine import SimEngine
from sim.inprocess import InProcessHost
from tests.sim.scripted import Scripted

REPLIES = {0: b"(init (unum 0)(teamname A))(syn)", 2: b"(beam -4 1 0)(syn)", 8: b"(he1 1.5)(lae1 -2)(syn)",
           12: b"(say ping)(syn)"}


def test_host_bytes_equal_a_directly_driven_engine() -> None:
    host = InProcessHost(SimEngine(seed=7), record=True)
    host.add(Scripted(dict(REPLIES)))
    host.add(Scripted({0: b"(init (unum 0)(teamname B))(syn)"}))
    host.run(30)

    # The same engine driven by hand, as a TCP server would: scene first, then one reply per message.
    engine = SimEngine(seed=7)
    agents = {engine.connect(): Scripted(dict(REPLIES)), engine.connect(): Scripted({0: b"(init (unum 0)(teamname B))(syn)"})}
    for key, agent in agents.items():
        engine.receive(key, agent.connect_message())
    direct = []
    for _ in range(30):
        for key, payload in engine.step().items():
            direct.append((engine.cycle, key, payload))
            engine.receive(key, agents[key].step(payload))
    assert host.stats.transcript == direct
    assert len(direct) > 50


def test_the_real_agent_runs_in_process() -> None:
    host = InProcessHost(SimEngine(seed=1))
    agent = Agent(AgentConfig("Mine", 3))
    key = host.add(agent)
    stats = host.run(60)
    assert stats.agent_errors == 0 and stats.messages == 58
    assert host.engine.agents[key].unum == 3 and host.engine.errors[key] == 0
    assert agent.world.game.unum == 3
