"""Turning in place on our simulator with the real agent: TurnToFace ends facing a point 90 deg to the side
(from its own localization, judged by the simulator's truth) without falling, and TurnBy beyond one motion's
range ends near the requested heading."""

from __future__ import annotations

import math

import pytest

from agent.skills.turn import TurnBy, TurnToFace
from agent.skills.walk import WalkTo
from motion_studio.scenarios import Scenario

START_M = (-5.0, 0.0)
LIMIT_CYCLES = 500  # 10 s; the turns take about 2 s


def _scenario(skill, heading_deg: float) -> Scenario:
    """The robot placed at START_M; the skill starts once the robot stands there (not during the connection
    at its formation spot, before the move)."""
    scenario = Scenario(None, position_m=START_M, heading_deg=heading_deg, recover_falls=False)
    scenario.run(5)
    scenario.set_skill(skill)
    return scenario


def _run_until_done(scenario: Scenario, skill) -> None:
    truths = scenario.run(LIMIT_CYCLES, stop=lambda truth: skill.done or truth.fallen)
    assert not any(t.fallen for t in truths), "the robot fell while turning"
    assert skill.done, "the skill did not finish in 10 s"
    assert not any(t.fallen for t in scenario.run(25))  # and it stands still afterwards


def _heading_error_deg(actual_deg: float, wanted_deg: float) -> float:
    return abs((actual_deg - wanted_deg + 180.0) % 360.0 - 180.0)


@pytest.mark.parametrize("side", [1.0, -1.0])
def test_turn_to_face_a_point_90_degrees_to_the_side(side):
    target = (START_M[0], START_M[1] + 3.0 * side)
    skill = TurnToFace(*target)
    scenario = _scenario(skill, 0.0)
    _run_until_done(scenario, skill)
    truth = scenario.history[-1]
    bearing_deg = math.degrees(math.atan2(target[1] - truth.torso_m[1], target[0] - truth.torso_m[0]))
    assert _heading_error_deg(truth.heading_deg, bearing_deg) <= 10.0
    assert math.hypot(truth.torso_m[0] - START_M[0], truth.torso_m[1] - START_M[1]) < 0.1  # in place
    assert 3 <= skill.motions_played <= 4  # 90 deg is beyond one motion's range: it stepped round, no dithering


def test_turn_by_150_degrees_right_with_localization():
    skill = TurnBy(-150.0)
    scenario = _scenario(skill, 30.0)
    _run_until_done(scenario, skill)
    assert _heading_error_deg(scenario.history[-1].heading_deg, 30.0 - 150.0) <= 10.0


def test_a_walk_to_a_point_behind_chains_its_turn_motions():
    """WalkTo a point 3 m behind: the 180 deg turn before the walk is turn motions back to back (no stance
    and settle between them, ``WalkConfig.chain_turn_deg``), so the robot walks off facing the point
    within 4.5 s (each stance and settle adds about 0.7 s); it stays upright and arrives."""
    target = (START_M[0] - 3.0, START_M[1])
    skill = WalkTo(*target)
    scenario = _scenario(skill, 0.0)
    motion = scenario.behavior.motion
    started = []
    walking_after_s = None
    for _ in range(1000):
        truth = scenario.run(1)[0]
        assert not truth.fallen, "the robot fell"
        started += [event.motion for event in motion.events if event.kind == "start"]
        if walking_after_s is None and motion.motion_name == "walk_forward":
            walking_after_s = truth.time_s - scenario.history[0].time_s
        if skill.done:
            break
    turns = started[:started.index("stand")]   # the stance comes once, before the walk
    assert len(turns) >= 4 and set(turns) == {"turn_right"}, started
    assert walking_after_s is not None and walking_after_s <= 4.5   # measured 3.6 s
    assert skill.reached
