"""Agents in worker processes (sim.agent_processes): the same match byte for byte as in-process, and a failing
agent or a dying worker never ends the match."""

from __future__ import annotations

import os
from dataclasses import asdict

import pytest

from motion_studio.match_agents import SideAgents, make_idle_agent
from sim.agent_processes import AgentBuildError, AgentProcessHost
from sim.engine import SimEngine
from sim.match import MatchConfig, run_match
from tests.sim.crashing_agent import CrashingAgent


def _replies_of(monkeypatch: pytest.MonkeyPatch, config: MatchConfig, make_agent, agent_processes: int):
    """The match result (without its wall time) and every payload the engine received, in order, with its cycle."""
    received: list[tuple[int, int, bytes]] = []
    original = SimEngine.receive

    def receive(self, agent_id, payload):
        received.append((self.cycle, agent_id, bytes(payload)))
        return original(self, agent_id, payload)

    monkeypatch.setattr(SimEngine, "receive", receive)
    result = asdict(run_match(config, make_agent, agent_processes=agent_processes))
    result.pop("wall_s")
    monkeypatch.setattr(SimEngine, "receive", original)
    return result, received


def test_begin_step_then_finish_step_is_step():
    from sim.benchmark import WaveAgent

    runs = []
    for split in (False, True):
        engine = SimEngine(seed=5)
        agents = {}
        for i in range(4):
            agent = WaveAgent("Left" if i % 2 == 0 else "Right", i % 4, phase=0.3 * i)
            agent_id = engine.connect()
            engine.receive(agent_id, agent.connect_message())
            agents[agent_id] = agent
        messages = []
        for _ in range(60):
            if split:
                out = engine.begin_step()
                engine.finish_step()
            else:
                out = engine.step()
            messages.append(out)
            for agent_id, payload in out.items():
                engine.receive(agent_id, agents[agent_id].step(payload))
        runs.append(messages)
    assert runs[0] == runs[1]
    assert sum(len(out) for out in runs[0]) > 4 * 50


@pytest.mark.parametrize("processes", [1, 2, 3])
def test_worker_processes_play_the_in_process_match_byte_for_byte(monkeypatch, processes):
    # our soccer agents, two a side, past the kick-off (they walk to the ball): every reply the engine gets
    config = MatchConfig(players_per_team=2, duration_s=2.0, kick_off_wait_s=1.0, seed=3)
    in_process, replies = _replies_of(monkeypatch, config, SideAgents(), 0)
    workers, replies_workers = _replies_of(monkeypatch, config, SideAgents(), processes)
    assert workers == in_process
    assert in_process["final_play_mode"] in {"KickOff_Left", "KickOff_Right", "PlayOn"}
    assert len(replies) > 4 * 100
    assert replies_workers == replies


def test_an_agent_that_raises_in_a_worker_costs_its_cycles_only_as_in_process():
    config = MatchConfig(players_per_team=1, duration_s=1.0, kick_off_wait_s=0.5)
    in_process = asdict(run_match(config, CrashingAgent))
    in_workers = asdict(run_match(config, CrashingAgent, agent_processes=2))
    assert in_workers["agent_errors"] >= 10
    for result in (in_process, in_workers):
        result.pop("wall_s")
    assert in_workers == in_process


class DyingAgent:
    """The left team's agent takes its whole worker process down at its 30th sense message (a segfault, say)."""

    def __init__(self, team, unum, robot_type):
        self.inner = make_idle_agent(team, unum, robot_type)
        self.team = team
        self.count = 0

    def connect_message(self):
        return self.inner.connect_message()

    def step(self, sense):
        self.count += 1
        if self.team == "Left" and self.count == 30:
            os._exit(3)
        return self.inner.step(sense)


def test_a_dying_worker_never_ends_the_match():
    # two workers: the left agents (connection order left, right, ... round robin) share the first one
    config = MatchConfig(players_per_team=2, duration_s=1.0, kick_off_wait_s=0.5)
    result = run_match(config, DyingAgent, agent_processes=2)
    assert result.game_time_s == pytest.approx(1.0, abs=0.03)
    assert result.final_play_mode in {"KickOff_Left", "KickOff_Right"}
    cycles_after_death = result.cycles - 30 - 8   # the robot's 30th message came some cycles after it connected
    assert result.agent_errors >= 2 * (cycles_after_death - 10)   # both left agents answer (syn) from then on
    assert result.agent_errors <= 2 * result.cycles


def test_the_workers_are_gone_after_the_match_and_after_a_failed_build():
    def broken(team, unum, robot_type):
        raise ValueError("no such agent")

    engine = SimEngine()
    with AgentProcessHost(engine, broken, 2) as host:
        processes = [worker.process for worker in host._workers]
        handle = host.build("Left", 1, 0)
        with pytest.raises(AgentBuildError, match="no such agent"):
            host.connect(handle)
    assert all(not process.is_alive() for process in processes)
    assert all(process.exitcode is not None for process in processes)


def test_processes_must_be_positive():
    with pytest.raises(ValueError):
        AgentProcessHost(SimEngine(), make_idle_agent, 0)
