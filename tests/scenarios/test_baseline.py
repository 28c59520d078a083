"""The opponents of ``agent.team.baseline`` on our simulator: the baseline kicks (the seed's on-ball play,
REFERENCE §7.8), the solo team dribbles (ours without coordination)."""

from __future__ import annotations

import math

from agent.protocol.constants import CYCLE_S
from agent.skills.dribble import Dribble
from agent.team.baseline import seed_kick_is_strong
from motion_studio.match_agents import make_baseline_agent, make_solo_agent
from tests.alone_in_play import alone_in_play

BALL_M = (3.0, 0.0)


def _play_alone(make, seed: int, within_s: float) -> tuple[list[tuple[float, float]], object]:
    """Unum 2 of the left team alone, 1 m behind the ball and 0.5 m to its side, facing the opponent goal: the
    ball's (x, y) every cycle for ``within_s`` [m], and the agent."""
    agent = make("Left", 2, 0)
    engine, host = alone_in_play(agent, BALL_M[0] - 1.0, 0.5, seed=seed)
    engine.world.set_ball((*BALL_M, 0.042))
    path = []
    for _ in range(round(within_s / CYCLE_S)):
        host.run(1)
        path.append(tuple(engine.world.ball_position()[:2]))
    return path, agent


def _moved_in_the_first_second(path: list[tuple[float, float]]) -> float:
    """How far the ball got in the 1 s after it first moved 5 cm [m] (a kick launches it, pushes nudge it)."""
    first = next(i for i, p in enumerate(path) if math.dist(p, BALL_M) > 0.05)
    return math.dist(path[min(first + round(1.0 / CYCLE_S), len(path) - 1)], BALL_M)


def test_the_baseline_kicks_the_ball_toward_the_goal():
    # measured (seeds 0-2): the strong kick after 20.9-24.4 s (the line-up is slow), the ball 2.64-2.79 m out 1 s
    # later and at rest 4.0-4.1 m out
    path, _ = _play_alone(make_baseline_agent, seed=1, within_s=30.0)
    assert _moved_in_the_first_second(path) > 2.2
    assert path[-1][0] > BALL_M[0] + 3.0


def test_the_solo_team_dribbles_instead():
    # measured (seeds 0-2): the first push moves the ball 1.06-1.12 m in its first second; about 9 m on in 25 s
    path, agent = _play_alone(make_solo_agent, seed=1, within_s=25.0)
    assert isinstance(agent.behavior.skills.skill, Dribble)
    assert _moved_in_the_first_second(path) < 2.0
    assert path[-1][0] > BALL_M[0] + 4.0


def test_the_seed_plays_its_normal_kick_only_near_the_goal():
    assert seed_kick_is_strong((10.0, 0.0))
    assert seed_kick_is_strong((12.4, 0.5))
    assert not seed_kick_is_strong((13.0, 0.5))
