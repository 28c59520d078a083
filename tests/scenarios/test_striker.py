"""The team's on-ball play on our simulator with the real agent: a striker alone scores on an empty goal,
and the kick-off is played at once (issue 15)."""

from __future__ import annotations

import logging

import pytest

from agent.protocol.constants import CYCLE_S
from motion_studio.match_agents import make_agent
from sim.engine import SimEngine
from sim.inprocess import InProcessHost
from tests.alone_in_play import alone_in_play
from tests.standing_opponents import our_team_against_standing


def _one_striker(seed: int, robot_m: tuple[float, float], ball_m: tuple[float, float]) -> tuple[SimEngine, InProcessHost]:
    """Unum 2 of the left team alone on the field, in PlayOn, at ``robot_m`` facing the opponent goal."""
    engine, host = alone_in_play(make_agent("Left", 2, 0), robot_m[0], robot_m[1], seed=seed)
    engine.world.set_ball((ball_m[0], ball_m[1], 0.042))
    return engine, host


def _our_kick_off_against_standing_robots(within_s: float) -> tuple[SimEngine, InProcessHost, dict]:
    """3 v 3 of our agents (types 0, 2, 4) against robots that only stand, seed 0: our kick-off, played until
    PlayOn or ``within_s`` of game time; returns the engine, the host and the robot keys by (team, unum)."""
    engine, host, keys = our_team_against_standing(seed=0)
    engine.referee.kick_off("Left")
    for _ in range(round(within_s / CYCLE_S)):
        host.run(1)
        if engine.referee.play_mode == "PlayOn":
            break
    return engine, host, keys


@pytest.mark.parametrize("seed", [0, 1])
def test_a_striker_alone_scores_on_an_empty_goal_within_40_s(seed):
    """Ball 4 m before the goal, the striker 1.5 m behind it: it dribbles the ball over the line."""
    engine, host = _one_striker(seed, (9.5, 0.5), (11.0, 0.0))
    for _ in range(round(40.0 / CYCLE_S)):
        host.run(1)
        if engine.referee.score_left > 0:
            break
    assert engine.referee.score_left == 1, engine.world.ball_position()


def test_the_kick_off_is_played_within_8_s():
    """3 v 3 against robots that only stand, our kick-off: the ball leaves the centre within 8 s of the
    kick-off (it waited out the 15 s before issue 15) and nobody touched it twice. The taker, unum 2, is type
    2: before its ankle pitch was capped at type 0's speed (``agent.motion.controller``) this kick grazed the
    ball (0.24 m), now 0.77 m. Over kick-off seeds 0-7 (a measurement script, not kept) the ball lies 2.70 m out 3 s
    after PlayOn on average (2.88 m before): the set-piece window still lets some kicks graze it (issue 15)."""
    engine, host, _ = _our_kick_off_against_standing_robots(8.0)
    host.run(50)
    x, y, _ = engine.world.ball_position()
    assert engine.referee.play_mode == "PlayOn"
    assert (x * x + y * y) ** 0.5 > 0.5


def test_the_kick_off_taker_never_plays_the_ball_again_before_a_teammate_did():
    """Our kick-off against robots that only stand: from the cycle the kick ends the set piece (PlayOn) the taker
    is no on-ball player for the next 3 s. Before, it was, for that first cycle (its memory was updated after the
    on-ball choice) and asked for a dribble 0.02 s after its kick; on the real server a kick-off ended in a free
    kick for the opponents 0.1 s after the kick (a second touch) in 2 of 8 kick-offs."""
    engine, host, keys = _our_kick_off_against_standing_robots(15.0)
    assert engine.referee.play_mode == "PlayOn"
    taker = host.agents[keys["Left", 2]].behavior
    roles = [taker.role]
    for _ in range(round(3.0 / CYCLE_S)):
        host.run(1)
        roles.append(taker.role)
    assert "on_ball" not in roles, roles.index("on_ball")
    assert engine.referee.play_mode == "PlayOn"   # no free kick for a second touch


def test_at_our_kick_off_the_second_attacker_waits_near_the_centre_to_go_for_the_kicked_ball():
    """3 v 3 against robots that only stand, our kick-off: when the taker plays it, unum 3 stands by
    ``KICK_OFF_FOLLOW_SPOT_M`` ahead of the halfway line inside the centre circle (the referee leaves it there),
    so the next touch comes sooner (the taker may not touch the ball again). Before, it walked back from its
    beam spot (-2.2, 1.2) to its usual spot 2.5 m behind the ball (here (-2.49, 1.43); on the real server
    across to (-2.5, -1.5), turned sideways for it, and it reached the kicked ball 12 s after the kick); seeds
    0-5 on ours: 12.6 s on average from PlayOn to unum 3 at the ball, 11.5 s from (-1.0, 0.9); on the real
    server the ball reached x = 5 m 2.2 s sooner from here."""
    import math

    from agent.team.soccer_behavior import KICK_OFF_FOLLOW_SPOT_M

    engine, _, keys = _our_kick_off_against_standing_robots(15.0)
    assert engine.referee.play_mode == "PlayOn"
    x, y, _ = engine.world.torso_position(keys["Left", 3])
    assert x > 0.0 and math.dist((x, y), KICK_OFF_FOLLOW_SPOT_M) < 0.6, (x, y)
    assert math.hypot(x, y) < 2.0 - 0.3  # wholly inside the circle: the footprint's corners too


def test_the_decision_log_records_each_change_of_role_skill_and_dribble_mode(caplog):
    """With ``agent.decisions`` at DEBUG (``motion-studio real match --decisions``) every change of what the
    striker does is one line with time, pose and ball; the same decision on the next cycle is not repeated."""
    caplog.set_level(logging.DEBUG, logger="agent.decisions")
    engine, host = _one_striker(0, (9.5, 0.5), (11.0, 0.0))
    host.run(round(8.0 / CYCLE_S))
    lines = [record.getMessage() for record in caplog.records if record.name == "agent.decisions"]
    assert any(" #2 on_ball ('dribble',) push pose (" in line for line in lines), lines
    assert all(line.startswith("t=") and " ball ego " in line for line in lines)
    decisions = [line.split(" pose ")[0].split(" ", 1)[1] for line in lines]
    assert all(a != b for a, b in zip(decisions, decisions[1:])), decisions
    assert 2 <= len(lines) < 100
