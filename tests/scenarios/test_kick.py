"""Kicking on our simulator with the real agent and the shipped motions: KickToward from just behind the
ball moves it at least 2 m forward (issue 6) and the kicker stays up; the kick motion alone does the same
from its spot."""

from __future__ import annotations

import math

import pytest

from agent.motion import default_library
from agent.skills.kick import KickToward
from motion_studio.kick_rollout import Placement, ball_spot, run_kick
from motion_studio.skill_bench.kick import _skill_scenario, skill_run

LIMIT_S = 12.0


@pytest.fixture(scope="module")
def library():
    return default_library()


def test_kick_toward_moves_the_ball_2m_forward_without_falling(library):
    """The robot stands 2 cm off the right foot's kick spot; the target lies 10 m straight ahead."""
    spot = library.get("kick").constants
    scenario = _skill_scenario((-4.0, 0.0), 0.0, seed=3, library=library)
    truth = scenario.truth()
    ball = ball_spot(truth, spot["ball_forward_m"] + 0.02, spot["ball_left_m"] - 0.01, 0.0)
    scenario.place_ball(ball)
    skill = KickToward(ball[0] + 10.0, ball[1])
    result = skill_run(scenario, skill, ball, (ball[0] + 10.0, ball[1]), LIMIT_S)
    rest = scenario.history[-1].ball_m
    assert skill.kicked, skill.reason
    assert rest[0] - ball[0] >= 2.0, result
    assert abs(math.degrees(math.atan2(rest[1] - ball[1], rest[0] - ball[0]))) < 20.0, result
    assert not result["fell"]


@pytest.mark.parametrize("motion", ["kick_strong_left"])
def test_mirrored_strong_kick_from_its_spot(library, motion):
    run = run_kick(library, motion, Placement(), seed=1, max_s=8.0)
    assert run.contact_s is not None
    assert run.distance_m >= 2.0
    assert abs(run.direction_error_deg) < 20.0
    assert not run.fell
