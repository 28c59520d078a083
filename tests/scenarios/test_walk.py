"""Walk scenarios on our simulator with the real agent and the shipped walk motions: the forward walk covers
2 m without falling (issue 6) and stops standing, the other walks move the way their names say, the walk
lean curves the walk, and the walk skills (WalkTo, WalkDirection, WalkToBall) reach their goals from the
world model's beliefs. Outcomes are checked against the simulator's ground truth."""

from __future__ import annotations

import math

import pytest

from agent.motion import default_library
from agent.skills.base import PlayMotion
from agent.skills.walk import WalkDirection, WalkTo
from agent.skills.walk_ball import WalkToBall
from motion_studio.scenarios import Scenario
from motion_studio.walk_rollout import run_walk

CYCLES_PER_S = 50


@pytest.fixture(scope="module")
def library():
    return default_library(0)


def test_walk_forward_covers_two_metres_without_falling_and_stops_standing(library):
    run = run_walk(library, "walk_forward", 6.0, position_m=(-5.0, 0.0), x_limit_m=None, stop_s=2.5)
    assert not run.fell and not run.fell_stopping
    forward, left = run.displacement_m()
    assert forward >= 2.0
    assert abs(left) < 0.4 * forward  # it walks forward, not off to a side
    assert min(t.up_z for t in run.truths) > 0.8  # upright all the way, not a near fall
    assert run.settled  # the stop through finalize ends standing still


@pytest.mark.parametrize("name, direction", [("walk_backward", (-1, 0)), ("walk_left", (0, 1)),
                                             ("walk_right", (0, -1))])
def test_other_walks_move_their_way(library, name, direction):
    run = run_walk(library, name, 5.0, position_m=(0.0, 0.0), x_limit_m=None)
    assert not run.fell and not run.fell_stopping
    forward, left = run.displacement_m()
    along = forward * direction[0] + left * direction[1]
    across = abs(forward * direction[1] - left * direction[0])
    assert along >= 0.4 and across < along
    assert run.settled


def test_full_lean_curves_the_walk_to_its_side(library):
    runs = {lean: run_walk(library, "walk_forward", 6.0, position_m=(-8.0, 0.0), lean=lean, x_limit_m=None)
            for lean in (1.0, 0.0, -1.0)}
    assert not any(r.fell for r in runs.values())
    change = {lean: r.heading_change_deg for lean, r in runs.items()}
    assert change[1.0] > change[0.0] + 10.0
    assert change[-1.0] < change[0.0] - 10.0


def test_walk_to_reaches_a_point_three_metres_away_by_localization():
    skill = WalkTo(-2.3, 1.0)
    scenario = Scenario(skill, position_m=(-5.0, 0.0), heading_deg=0.0, recover_falls=False)
    truths = scenario.run(25 * CYCLES_PER_S, stop=lambda t: skill.done or t.fallen)
    end = truths[-1]
    assert not end.fallen
    assert skill.done and skill.reached
    assert math.dist(end.torso_m[:2], (-2.3, 1.0)) <= 0.3


def test_walk_to_a_point_behind_turns_round_and_gets_there():
    skill = WalkTo(-6.5, -1.0)
    scenario = Scenario(skill, position_m=(-5.0, 0.0), heading_deg=0.0, recover_falls=False)
    truths = scenario.run(35 * CYCLES_PER_S, stop=lambda t: skill.done or t.fallen)
    assert not truths[-1].fallen and skill.done
    assert math.dist(truths[-1].torso_m[:2], (-6.5, -1.0)) <= 0.3


def test_walk_direction_left_moves_left_without_turning():
    # ball out of the way: at the centre spot the robot would be beamed onto it
    scenario = Scenario(WalkDirection(90.0), position_m=(0.0, 0.0), heading_deg=30.0, recover_falls=False,
                        ball_m=(5.0, 5.0))
    truths = scenario.run(5 * CYCLES_PER_S)
    assert not any(t.fallen for t in truths)
    dx, dy = truths[-1].torso_m[0] - truths[0].torso_m[0], truths[-1].torso_m[1] - truths[0].torso_m[1]
    heading = math.radians(30.0)
    left = -math.sin(heading) * dx + math.cos(heading) * dy
    assert left >= 0.4
    assert abs(truths[-1].heading_deg - 30.0) < 15.0


def test_walk_direction_picks_the_nearest_walk():
    assert [WalkDirection.walk_for(a) for a in (0, 40, 60, 170, -170, -100, 360)] == \
        ["walk_forward", "walk_forward", "walk_left", "walk_backward", "walk_backward", "walk_right", "walk_forward"]
    with pytest.raises(ValueError):
        WalkDirection(float("nan"))


def test_walk_to_ball_ends_with_the_ball_close_in_front():
    skill = WalkToBall()
    scenario = Scenario(skill, position_m=(-4.0, 0.0), heading_deg=20.0, ball_m=(-2.0, -0.6), recover_falls=False)
    truths = scenario.run(25 * CYCLES_PER_S, stop=lambda t: skill.done or t.fallen)
    end = truths[-1]
    assert not end.fallen and skill.done
    heading = math.radians(end.heading_deg)
    dx, dy = end.ball_m[0] - end.torso_m[0], end.ball_m[1] - end.torso_m[1]
    forward = math.cos(heading) * dx + math.sin(heading) * dy
    left = -math.sin(heading) * dx + math.cos(heading) * dy
    assert 0.0 < forward <= 0.4 and abs(left) <= 0.15
