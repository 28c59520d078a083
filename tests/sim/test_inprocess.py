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


class _Failing(Scripted):
    """Raises in its step at the given message indices (a bug in an agent), else behaves as Scripted."""

    def __init__(self, failing: set[int], error: type[Exception], replies: dict[int, bytes]) -> None:
        super().__init__(replies)
        self.failing = failing
        self.error = error

    def step(self, sense: bytes) -> bytes:
        reply = super().step(sense)
        if len(self.received) - 1 in self.failing:
            raise self.error(f"boom at message {len(self.received) - 1}")
        return reply


def test_an_agent_that_raises_loses_that_cycle_only(caplog) -> None:  # noqa: ANN001 - pytest fixture
    import logging
    host = InProcessHost(SimEngine(seed=2))
    broken = _Failing({3, 4, 9}, ZeroDivisionError, {0: b"(init (unum 0)(teamname A))(syn)", 4: b"(he1 1)(syn)"})
    steady = Scripted({0: b"(init (unum 0)(teamname B))(syn)"})
    broken_id, steady_id = host.add(broken), host.add(steady)
    with caplog.at_level(logging.WARNING, logger="sim.inprocess"):
        stats = host.run(20)
    # Every message reached both agents; the three failures were counted, logged with the id, answered (syn).
    assert len(broken.received) == len(steady.received) == 18
    assert stats.agent_errors == 3 and stats.errors_by_agent == {broken_id: 3}
    failures = [r for r in caplog.records if r.name == "sim.inprocess"]
    assert len(failures) == 3 and all(f"agent {broken_id}:" in r.getMessage() for r in failures)
    assert all("ZeroDivisionError" in r.getMessage() and r.exc_info for r in failures)
    # The (syn) answers kept it in sync and its joints untouched (its he1 command was lost with message 4).
    assert host.engine.errors[broken_id] == 0 and host.engine.ready() is True
    assert host.engine.agents[broken_id].team == "A" and host.engine.agents[steady_id].team == "B"
    assert abs(host.engine.world.motors.targets(broken_id)[0]) < 1e-12


def test_a_broken_agent_is_logged_quietly_after_the_first_failures(caplog) -> None:  # noqa: ANN001
    import logging

    from sim.engine import LOGGED_ERRORS_PER_AGENT
    host = InProcessHost(SimEngine(seed=2))
    host.add(_Failing(set(range(1000)), RuntimeError, {}))
    with caplog.at_level(logging.WARNING, logger="sim.inprocess"):
        stats = host.run(40)
    assert stats.agent_errors == 38
    assert len([r for r in caplog.records if r.name == "sim.inprocess"]) == LOGGED_ERRORS_PER_AGENT
