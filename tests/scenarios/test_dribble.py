"""The dribble's push on our simulator with the real agent: the ball goes where the robot walks, for the robot
types whose feet sent it aside (issue 15: pushes that went 20-45 deg off cost 8-10 s each to recover)."""

from __future__ import annotations

import math

import pytest

from agent.protocol.constants import CYCLE_S
from motion_studio.match_agents import SideAgents, make_agent
from sim.engine import SimEngine
from sim.inprocess import InProcessHost
from tests.alone_in_play import alone_in_play

BALL_M = (5.0, 0.0)


@pytest.mark.parametrize("back_m, across_m, heading_deg", [(2.2, -0.10, -10.0), (1.0, 0.10, -10.0)])
def test_a_type_4_robot_pushes_the_ball_along_its_line_to_the_goal(back_m, across_m, heading_deg):
    """Unum 2 as type 4 (toes), behind the ball facing the opponent goal: 0.3 m after the first touch the ball
    runs within 10 deg of the line to the goal, and 8 s later it has gone 2 m within 12 deg of it. Walking at
    the ball itself (before ``DribbleConfig.push_aim_left_m``) these two starts sent it 42 deg aside."""
    engine, host = alone_in_play(make_agent("Left", 2, 4), BALL_M[0] - back_m, across_m, heading_deg)
    engine.world.set_ball((BALL_M[0], BALL_M[1], 0.042))
    first_deg = None
    for _ in range(round(10.0 / CYCLE_S)):
        host.run(1)
        x, y, _ = engine.world.ball_position()
        if first_deg is None and math.hypot(x - BALL_M[0], y - BALL_M[1]) > 0.3:
            first_deg = math.degrees(math.atan2(y - BALL_M[1], x - BALL_M[0]))
    x, y, _ = engine.world.ball_position()
    assert first_deg is not None and abs(first_deg) < 10.0, first_deg
    assert x - BALL_M[0] > 2.0 and abs(math.degrees(math.atan2(y, x - BALL_M[0]))) < 12.0, (x, y)


def _striker_against_a_standing_keeper(seed: int, robot_m: tuple[float, float, float], ball_m: tuple[float, float],
                                       keeper_m: tuple[float, float, float] | None = None):
    """Our unum 2 (type 0) and the other side's goalkeeper that only stands, in PlayOn: keeper on its beam spot
    (14.86, 0) in our frame unless ``keeper_m`` moves it, the ball and our robot set down as given [m, m, deg]."""
    engine = SimEngine(seed=seed)
    host = InProcessHost(engine)
    factory = SideAgents("ours", "standing")
    ours = host.add(factory("Left", 2, 0))
    host.run(2)
    keeper = host.add(factory("Right", 1, 0))
    host.run(60)
    engine.referee.kick_off("Left")
    engine.referee.set_play_mode("PlayOn")
    engine.world.place_robot(ours, *robot_m)
    if keeper_m is not None:
        engine.world.place_robot(keeper, *keeper_m)
    engine.world.set_ball((ball_m[0], ball_m[1], 0.042))
    return engine, host


def _play_until_scored(engine, host, within_s: float) -> None:
    """Play until our side scored, at most ``within_s`` of game time; fails unless it scored exactly once."""
    for _ in range(round(within_s / CYCLE_S)):
        host.run(1)
        if engine.referee.score_left > 0:
            break
    assert engine.referee.score_left == 1, engine.world.ball_position()


def test_a_ball_at_a_standing_keepers_feet_is_played_past_it_within_20_s():
    """The ball 0.16 m in front of the keeper, our striker about 1.1 m behind it, 3 starts x seeds 0-3: at least 9
    of the 12 score within 20 s (measured 10 of 12, with ODE's joint drift on the legs and without; the misses
    push the ball out of the goal mouth off the keeper's legs). Before ``DribbleConfig.play_through_m`` none of 6
    scored in 20 s: the robot side-stepped away from the keeper, stepped back to the ball, and so on (for up to 90 s
    in matches)."""
    scored = 0
    for seed in range(4):
        for robot_m in [(13.6, 0.3, 0.0), (13.5, -0.5, 20.0), (13.55, 0.0, 0.0)]:
            engine, host = _striker_against_a_standing_keeper(seed, robot_m, (14.7, -0.05))
            for _ in range(round(20.0 / CYCLE_S)):
                host.run(1)
                if engine.referee.score_left > 0:
                    scored += 1
                    break
    assert scored >= 9, scored


@pytest.mark.parametrize("robot_m", [(14.6, -0.2, -20.0), (14.55, 0.35, -40.0)])
def test_a_ball_in_the_goal_mouth_beside_a_standing_keeper_is_pushed_over_the_line(robot_m):
    """The real server's seed-16 stall (3 v 3, 120 s): the ball at rest 4 cm before the goal line, 0.19 m beside
    the keeper's torso, which stands nearer to our robot than the ball. ``DribbleConfig.goal_mouth_m`` plays the
    ball on; before it the robot side-stepped away from the keeper and back for the last 76 s of that match."""
    engine, host = _striker_against_a_standing_keeper(0, robot_m, (14.96, -0.17))
    _play_until_scored(engine, host, 15.0)


def test_a_ball_half_a_metre_before_the_line_behind_the_keeper_is_pushed_in():
    """11 v 11 against the baseline on ours (seed 0): the ball 0.52 m before the goal line, the keeper beside our
    robot and nearer to it than the ball; with ``DribbleConfig.goal_mouth_m`` 0.5 the robot side-stepped for 50 s.
    Measured with 1.0: scored after 17.2 s (the first 13 s the robot, set down facing away, looks for the ball)."""
    engine, host = _striker_against_a_standing_keeper(0, (14.32, -0.31, -64.0), (14.48, -0.26), (14.24, -0.03, 180.0))
    _play_until_scored(engine, host, 25.0)


def test_a_ball_rolling_past_is_approached_where_it_will_stop():
    """Our kick-off as the receiver sees it: unum 2 waits beside the centre circle facing the goal, the ball rolls
    past it at 4.5 m/s and stops 3.1 m on, 5.4 s later. Walking at the rolling ball's sightings the robot had
    pushed it 0.5 m on from there 12.4 s after the launch; walking at its rest point (``DribbleConfig.rolling_m_s``)
    6.4 s after it."""
    engine, host = alone_in_play(make_agent("Left", 2, 0), 1.05, 1.1, -13.0)
    engine.world.set_ball((0.3, 0.0, 0.042), (4.5, -0.5, 0.0))
    rest, pushed_s = None, None
    for cycle in range(round(9.0 / CYCLE_S)):
        host.run(1)
        x, y, _ = engine.world.ball_position()
        if rest is None and cycle > 50 and math.hypot(*engine.world.ball_velocity()[:2]) < 0.01:
            rest = (x, y)
        if rest is not None and math.hypot(x - rest[0], y - rest[1]) > 0.5:
            pushed_s = cycle * CYCLE_S
            break
    assert rest is not None and 2.5 < rest[0] < 4.0, rest
    assert pushed_s is not None and pushed_s < 7.0, pushed_s
