"""Ball velocity and rest point from sightings: synthetic rolls with noise, and a real roll seen by our agent
on our simulator (issue 15: ball tracking with velocity and intercept point)."""

from __future__ import annotations

import math
import random

import pytest

from agent.world.ball_track import ROLL_DECAY_PER_S, BallTrack

FRAME_S = 0.06  # SimSpark's vision every 3 cycles


def _roll(track: BallTrack, start: tuple[float, float], v: tuple[float, float], seconds: float,
          noise_m: float = 0.0, seed: int = 0) -> None:
    rng = random.Random(seed)
    t = 0.0
    while t <= seconds + 1e-9:
        share = (1.0 - math.exp(-ROLL_DECAY_PER_S * t)) / ROLL_DECAY_PER_S
        track.add(10.0 + t, start[0] + v[0] * share + rng.gauss(0, noise_m), start[1] + v[1] * share + rng.gauss(0, noise_m))
        t += FRAME_S


def test_the_decay_constant_is_the_real_servers_roll():
    """0.677 m per m/s launched (rcssserver3d 0.7.3), 5/7 of the speed left once rolling."""
    assert (5.0 / 7.0) / ROLL_DECAY_PER_S == pytest.approx(0.677)


@pytest.mark.parametrize("seed", range(3))
def test_a_noisy_roll_gives_its_velocity_and_rest_point(seed):
    track = BallTrack()
    _roll(track, (1.0, -2.0), (3.0, 1.0), seconds=0.6, noise_m=0.02, seed=seed)
    decay = math.exp(-ROLL_DECAY_PER_S * 0.6)
    vx, vy = track.velocity_m_s()
    assert vx == pytest.approx(3.0 * decay, abs=0.15) and vy == pytest.approx(1.0 * decay, abs=0.15)
    rest = track.rest_point()
    assert rest[0] == pytest.approx(1.0 + 3.0 / ROLL_DECAY_PER_S, abs=0.15)
    assert rest[1] == pytest.approx(-2.0 + 1.0 / ROLL_DECAY_PER_S, abs=0.15)


def test_a_lying_ball_has_no_velocity_and_rests_where_it_lies():
    track = BallTrack()
    _roll(track, (4.0, 1.0), (0.0, 0.0), seconds=1.0, noise_m=0.02)
    assert track.velocity_m_s() == (0.0, 0.0)
    assert track.rest_point() == pytest.approx((4.0, 1.0), abs=0.05)


def test_too_few_sightings_say_nothing_and_a_jump_restarts_the_track():
    track = BallTrack()
    track.add(1.0, 0.0, 0.0)
    track.add(1.06, 0.1, 0.0)
    assert track.velocity_m_s() is None and track.rest_point() is None
    _roll(track, (0.0, 0.0), (2.0, 0.0), seconds=0.5)
    assert track.velocity_m_s() is not None
    track.add(10.6, 8.0, 5.0)  # the referee put the ball elsewhere
    assert len(track.samples) == 1 and track.velocity_m_s() is None


def test_the_keeper_intercept_is_where_the_roll_crosses_the_goal_line():
    track = BallTrack()
    _roll(track, (-10.0, 1.0), (-6.0, -0.6), seconds=0.3)
    y = track.crossing_y(-15.0)
    assert y is not None
    # Straight roll: the crossing lies on the line through the start along the velocity.
    assert y == pytest.approx(1.0 + (-0.6 / -6.0) * (-15.0 + 10.0), abs=0.05)
    assert track.crossing_y(-25.0) is None  # it stops before
    assert track.crossing_y(0.0) is None  # behind it


@pytest.mark.parametrize("launch", [(2.0, 0.0), (1.5, 1.0), (3.0, -0.6)])
def test_our_agent_predicts_where_a_ball_rolling_on_our_simulator_stops(launch):
    """A standing agent watches a launched ball: 0.6 s after the launch its estimate of the velocity is within
    0.15 m/s and of the rest point within 0.15 m of the simulator's truth."""
    from motion_studio.match_agents import make_idle_agent
    from tests.alone_in_play import alone_in_play

    agent = make_idle_agent("Left", 2, 0)
    engine, host = alone_in_play(agent, -3.0, 0.0)
    host.run(100)
    engine.world.set_ball((-2.0, 0.0, 0.042), (launch[0], launch[1], 0.0))
    host.run(30)
    velocity = agent.world.ball_track.velocity_m_s()
    rest = agent.world.ball_track.rest_point()
    true_velocity = engine.world.ball_velocity()
    host.run(500)
    true_rest = engine.world.ball_position()
    assert math.dist(velocity, true_velocity[:2]) < 0.15
    assert math.dist(rest, true_rest[:2]) < 0.15
