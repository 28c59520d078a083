"""Two agents of one team exchange team messages through our server (sim.inprocess, same bytes as TCP);
an agent of the other team says things too and is ignored."""

from __future__ import annotations

import pytest

from agent import Agent, AgentConfig
from agent.communication import decode
from sim.engine import FrozenReferee, SimEngine
from sim.inprocess import InProcessHost


@pytest.fixture(scope="module")
def game():
    host = InProcessHost(SimEngine(seed=3, referee=FrozenReferee()), record=True)
    ours = {2: Agent(AgentConfig("Ours", 2)), 5: Agent(AgentConfig("Ours", 5))}
    theirs = Agent(AgentConfig("Them", 5))
    ids = {}
    # One after another: robots built in the same cycle collide (REFERENCE real-server notes).
    for unum, agent in ours.items():
        ids[unum] = host.add(agent)
        host.run(5)
    ids["them"] = host.add(theirs)
    host.run(140)  # > 4 rounds of 33 cycles
    return host, ours, theirs, ids


def test_teammates_know_each_other_from_say(game):
    host, ours, _, ids = game
    world = host.engine.world
    for unum, agent in ours.items():
        other = 5 if unum == 2 else 2
        truth = world.torso_position(ids[other])
        report = agent.world.reports[other]  # the latest decoded message of that teammate
        assert report.kind in ("l", "c") and report.active
        assert report.position == pytest.approx((truth[0], truth[1]), abs=0.1)  # both on the left team
        assert agent.world.now_s - report.heard_s < 33 * 0.02 + 1e-9  # refreshed every round of 11 slots
        tracked = agent.world.teammates[other]  # the newer of the last sighting and the last report
        assert tracked.source in ("say", "vision")
        assert tracked.position == pytest.approx((truth[0], truth[1]), abs=0.2)


def test_the_other_teams_messages_are_ignored(game):
    _, ours, theirs, _ = game
    assert theirs.said  # it did talk
    for agent in ours.values():
        assert agent.world.ignored_messages > 0
        assert set(agent.world.reports) <= {2, 5}


def test_messages_fit_and_the_team_never_says_twice_within_2_cycles(game):
    host, ours, _, ids = game
    for unum, agent in ours.items():
        assert len(agent.said) >= 3
        assert all(len(text) <= 20 and decode(text, "Ours").unum == unum for text in agent.said)
    own_messages = [message for _, agent_id, message in host.stats.transcript if agent_id == ids[2]]
    heard = [index for index, message in enumerate(own_messages) if b"(hear Ours" in message]
    assert len(heard) >= 6
    assert all(b - a >= 2 for a, b in zip(heard, heard[1:]))
