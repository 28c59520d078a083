"""Kicking on our simulator with the real agent and the shipped motions: KickToward from just behind the
ball moves it at least 2 m forward (issue 6) and the kicker stays up; the kick motion alone does the same
from its spot."""

from __future__ import annotations

import math
from dataclasses import replace

import pytest

from agent.motion import MotionLibrary, default_library
from agent.skills.kick import KickConfig, KickToward
from motion_studio.kick_rollout import Placement, ball_spot, run_kick
from motion_studio.realserver.cases import CASES, MotionSource
from motion_studio.realserver.skill_runs import run_sim
from motion_studio.skill_bench.kick import _skill_scenario, challenge_attempt, skill_run

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


def test_kick_toward_from_1m_behind_a_ball_30deg_off_the_aim(library):
    """The robot faces the ball 1 m ahead; the target lies 30° to the left of that line: it walks round to
    the kick line (turn, counted strides, turn back), walks in and kicks within 7 s of the skill's start,
    sending the ball at least 1.5 m toward the target."""
    ball = (-4.0, 0.0)
    aim = math.radians(30.0)
    target = (ball[0] + 10.0 * math.cos(aim), ball[1] + 10.0 * math.sin(aim))
    scenario = _skill_scenario((-5.0, 0.0), 0.0, seed=5, library=library, ball_m=ball)
    start_s = scenario.agent.world.now_s
    skill = KickToward(*target, strong=True)
    result = skill_run(scenario, skill, ball, target, LIMIT_S)
    rest = scenario.history[-1].ball_m
    toward = (rest[0] - ball[0]) * math.cos(aim) + (rest[1] - ball[1]) * math.sin(aim)
    assert skill.kicked, (skill.reason, skill.moves)
    assert skill.kick_started_s is not None and skill.kick_started_s - start_s <= 7.0, (skill.moves, result)
    assert toward >= 1.5, result
    assert abs(result["direction_error_deg"]) < 20.0, result
    assert not result["fell"]


def test_kick_challenge_attempt_kicks_in_time(library):
    """A kick-challenge attempt (REFERENCE §8.2: robot 1 m behind the ball, facing it and the aim (0, 0)):
    the ball leaves the 2 m circle and stops before the 7 s limit, the robot stays up."""
    attempt = challenge_attempt(5.0, -20.0, True, seed=2, library=library)
    assert attempt["end"] == "ball stopped outside the circle", attempt
    assert attempt["kicked"] and not attempt["fell"], attempt
    assert attempt["moved_m"] >= 2.0 and attempt["score_m"] < 3.5, attempt


def test_place_and_kick_with_a_library_without_walks_or_turns(library):
    """Only the stance and the kicks: the robot placed 1 cm off the right foot's spot kicks from there."""
    kicks_only = MotionLibrary({name: library.get(name) for name in library.names
                                if name == "stand" or name.startswith("kick") and "step" not in name})
    spot = library.get("kick").constants
    scenario = _skill_scenario((-4.0, 0.0), 0.0, seed=4, library=kicks_only)
    truth = scenario.truth()
    ball = ball_spot(truth, spot["ball_forward_m"] + 0.01, spot["ball_left_m"], 0.0)
    scenario.place_ball(ball)
    skill = KickToward(ball[0] + 10.0, ball[1] + 3.0)  # 17° off: cannot turn, kicks along its heading
    result = skill_run(scenario, skill, ball, (ball[0] + 10.0, ball[1]), LIMIT_S)
    assert skill.kicked and skill.moves == [f"kick:{skill.foot}"], (skill.reason, skill.moves)
    assert result["distance_m"] >= 1.5 and not result["fell"], result


def test_ball_out_of_sight_gives_up_with_a_reason(library):
    """No ball in view (behind the robot): the skill sweeps its head, then stops with ``ball lost``."""
    scenario = _skill_scenario((-4.0, 0.0), 0.0, seed=6, library=library, ball_m=(-8.0, 0.0))
    scenario.run(int(KickConfig().max_ball_age_s / 0.02) + 10)  # the sighting from before the placement expires
    skill = KickToward(0.0, 0.0)
    scenario.set_skill(skill)
    scenario.run(int((KickConfig().lost_timeout_s + 1.0) / 0.02))
    assert skill.done and not skill.kicked and skill.reason == "ball lost"


def test_the_distance_controlled_kick_from_its_spot_goes_about_as_far_as_asked(library):
    """The kick motion asked for 1.5 m and for 3.2 m (the shipped table's rows 1.53 and 3.17 m, measured on the
    real server; ours went 1.62 and 3.06 m on average): each ball rests within 0.5 m of the request, the kicker
    stays up."""
    for requested in (1.5, 3.2):
        run = run_kick(library, "kick", Placement(), seed=1, max_s=8.0, distance_m=requested)
        assert abs(run.distance_m - requested) < 0.5, (requested, run.figures())
        assert abs(run.direction_error_deg) < 10.0 and not run.fell, run.figures()


def test_kick_toward_with_a_distance_lines_up_and_passes_short(library):
    """KickToward asked for 2 m from 2 cm off the spot: the ball rests within the issue's +-1 m of 2 m (the kick
    at full strength goes 3.9 m here)."""
    spot = library.get("kick").constants
    scenario = _skill_scenario((-4.0, 0.0), 0.0, seed=3, library=library)
    truth = scenario.truth()
    ball = ball_spot(truth, spot["ball_forward_m"] + 0.02, spot["ball_left_m"] - 0.01, 0.0)
    scenario.place_ball(ball)
    skill = KickToward(ball[0] + 2.0, ball[1], distance_m=2.0)
    result = skill_run(scenario, skill, ball, (ball[0] + 2.0, ball[1]), LIMIT_S)
    assert skill.kicked, skill.reason
    assert abs(result["distance_m"] - 2.0) <= 1.0, result
    assert not result["fell"]


def test_the_controlled_kick_summary_counts_errors_against_each_request():
    from motion_studio.skill_bench.kick import controlled_summary

    trials = [{"requested_m": 2.0, "distance_m": 2.6, "error_m": 0.6, "fell": False},
              {"requested_m": 2.0, "distance_m": 0.4, "error_m": -1.6, "fell": False},
              {"requested_m": 8.0, "distance_m": 4.1, "error_m": -3.9, "fell": True}]
    figures = controlled_summary(trials)
    assert figures["within_tolerance"] == 1 and figures["falls"] == 1
    assert figures["error_mean_abs_m"] == pytest.approx(2.03, abs=0.01) and figures["error_max_abs_m"] == 3.9
    assert figures["by_request_m"] == {"2": [2.6, 0.4], "8": [4.1]}


def test_a_controlled_kick_steps_up_to_a_ball_6cm_beyond_its_spot(library):
    """The ball 6 cm beyond the right foot's spot, KickToward asked for 2 m: the distance-controlled kick takes
    kick steps first (its table holds for the ball within 2 cm) and the ball rests within 1 m of 2 m. With the
    loose window reaching 8 cm (the full kick's: KickConfig(controlled_loose_forward_max_m=0.08)) it kicked at
    once from there and the ball stopped 0.5 m away."""
    spot = library.get("kick").constants
    scenario = _skill_scenario((-4.0, 0.0), 0.0, seed=0, library=library)
    truth = scenario.truth()
    ball = ball_spot(truth, spot["ball_forward_m"] + 0.06, spot["ball_left_m"], 0.0)
    scenario.place_ball(ball)
    skill = KickToward(ball[0] + 2.0, ball[1], distance_m=2.0)
    result = skill_run(scenario, skill, ball, (ball[0] + 2.0, ball[1]), LIMIT_S)
    assert skill.kicked and abs(result["distance_m"] - 2.0) <= 1.0, result
    assert skill.corrections >= 1 and not result["fell"], result


@pytest.mark.parametrize(("robot_type", "distance_cm", "heading_deg", "min_m"),
                         [(0, 45, 0.0, 1.5), (0, 47, 0.0, 1.5), (0, 50, 0.0, 1.5), (0, 55, -8.0, 1.5),
                          (3, 45, 0.0, 3.0), (3, 55, 0.0, 3.0)])
def test_the_kick_off_line_up_kicks_from_the_whole_range_of_the_beam(robot_type, distance_cm, heading_deg, min_m):
    """The kick-off taker stands 0.45-0.55 m behind the ball (its spot and the beam's +-5 cm): the line-up and kick
    (``motion-studio real skills kick_lineup_<d>cm``, the same case as on the real server) move the ball 1.5 m or
    more: ours kicks 1.9-2.2 m from within 1.5 cm of the spot and about 4 m from 3-4 cm beyond it (18 starts: 1.86-4.1
    m); the real kick 3.1-4.4 m.
    With the loose window reaching 8 cm the real kick grazed the ball from 45 and 55 cm (9 of 18 starts, heading
    -8/0/+8 deg; 0.02-0.10 m) and ours kicked it 0.5-0.7 m from 3 of 18 (47 cm, and 55 cm turned 8 deg right, among
    them).
    Robot type 3 (``--type 3``): planned with type 0's walk-in distances and windows, its walk-ins ended beyond its
    short kick window and it grazed the ball (0.15-0.16 m on ours, 0.09 m on the real server); with its own
    (``KICK_CONFIG_BY_TYPE``) it kicks 5.5-6 m on ours and 5.4-5.5 m on the real server, without falling."""
    case = replace(CASES["kick_lineup_50cm"], ball_m=(-8.0 + distance_cm / 100.0, 0.0), heading_deg=heading_deg,
                   robot_type=robot_type)
    run = run_sim(case, MotionSource())
    truths = [t for t in run.truths if t is not None]
    assert math.dist(truths[0].ball_m[:2], truths[-1].ball_m[:2]) >= min_m, [name for _, name in run.completions]
    assert not any(t.fallen for t in truths)
    assert any(name.startswith("kick") and not name.startswith("kick_step") for _, name in run.completions)


def test_kick_toward_aiming_with_the_ball_direction_sends_the_ball_along_the_aim(library):
    """The kick sends the ball 8-10 deg to the kicking foot's side (motions/params/kick.toml, ball_direction_deg);
    with ``aim_ball_direction`` the line-up faces that much the other way. The robot stands 2 cm off the right
    foot's spot facing a target 10 m straight ahead: measured 2026-11-28, the left foot kicks, +9.6 deg by default, +1.3
    deg with it (3.0 s later)."""
    directions = {}
    for aim_with_direction in (False, True):
        spot = library.get("kick").constants
        scenario = _skill_scenario((-4.0, 0.0), 0.0, seed=3, library=library)
        truth = scenario.truth()
        ball = ball_spot(truth, spot["ball_forward_m"] + 0.005, spot["ball_left_m"], 0.0)
        scenario.place_ball(ball)
        skill = KickToward(ball[0] + 10.0, ball[1], config=KickConfig(aim_ball_direction=aim_with_direction))
        result = skill_run(scenario, skill, ball, (ball[0] + 10.0, ball[1]), 20.0)
        assert skill.kicked and not result["fell"], (skill.reason, result)
        rest = scenario.history[-1].ball_m
        directions[aim_with_direction] = math.degrees(math.atan2(rest[1] - ball[1], rest[0] - ball[0]))
    assert abs(directions[False]) > 6.0, directions
    assert abs(directions[True]) < 4.0, directions

