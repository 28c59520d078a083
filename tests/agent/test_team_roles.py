"""Role choice: REFERENCE §7.10's on-ball cost with holder hysteresis, goalkeeper rules, support spots."""

from __future__ import annotations

import math

import pytest

from agent.team import roles
from agent.team.roles import (FIELD_X_MIN_M, HOLDER_STALL_S, SUPPORT_CLEARANCE_M, Candidate, HolderWatch,
                              around_ball_deg, choose_on_ball, keeper_spot, on_ball_cost, support_spot)


def test_the_nearest_player_behind_the_ball_plays_it():
    ball = (0.0, 0.0)
    players = [Candidate(2, -1.0, 0.0), Candidate(3, -3.0, 0.0), Candidate(4, 1.2, 0.0)]
    # unum 4 is 0.2 m nearer-ish but in front of the ball: 180 deg around it costs 1.8 m.
    assert around_ball_deg(1.2, 0.0, ball) == pytest.approx(180.0)
    assert on_ball_cost(players[2], ball, None) == pytest.approx(1.2 + 1.8)
    assert choose_on_ball(players, ball, holder=None) == 2


def test_the_holder_keeps_the_ball_unless_another_is_clearly_better():
    ball = (0.0, 0.0)
    players = [Candidate(2, -1.5, 0.0), Candidate(3, -1.0, 0.0)]
    assert choose_on_ball(players, ball, holder=None) == 3
    assert choose_on_ball(players, ball, holder=2) == 2          # 0.5 m worse: keeps it (bonus 1 m)
    players[0] = Candidate(2, -2.5, 0.0)
    assert choose_on_ball(players, ball, holder=2) == 3          # 1.5 m worse: hands it over


def test_equal_costs_go_to_the_lower_unum_so_every_player_agrees():
    ball = (0.0, 0.0)
    players = [Candidate(5, -1.0, 1.0), Candidate(4, -1.0, -1.0)]
    assert choose_on_ball(players, ball, None) == 4
    assert choose_on_ball(list(reversed(players)), ball, None) == 4


def test_the_goalkeeper_plays_only_in_its_penalty_area():
    keeper, field_player = Candidate(1, -14.0, 0.0), Candidate(2, -8.0, 0.0)
    assert choose_on_ball([keeper, field_player], (-10.0, 0.0), None) == 2
    assert choose_on_ball([keeper, field_player], (-13.8, 1.0), None) == 1
    assert choose_on_ball([keeper], (0.0, 0.0), None) is None


def test_support_spots_keep_clear_of_the_ball_and_out_of_the_own_penalty_area():
    for unum in range(2, 12):
        for ball in [(-14.0, 0.0), (0.0, 0.0), (10.0, 5.0), (-6.0, -8.0)]:
            x, y = support_spot(unum, ball)
            assert x >= FIELD_X_MIN_M - 1e-9
            assert math.hypot(x - ball[0], y - ball[1]) >= SUPPORT_CLEARANCE_M - 1e-9 or x == FIELD_X_MIN_M
    # Spots move up the field with the ball.
    assert support_spot(9, (8.0, 0.0))[0] > support_spot(9, (-8.0, 0.0))[0]


def test_the_keeper_follows_the_ball_within_the_goal():
    assert keeper_spot(None) == (-14.2, 0.0)
    assert keeper_spot((0.0, 2.0))[1] == pytest.approx(0.6)
    assert keeper_spot((-10.0, -9.0))[1] == pytest.approx(-0.8)


def _sense(text: str, now_s: float = 10.0) -> bytes:
    return (f"(time (now {now_s:.2f}))(GS (sl 0) (sr 0) (t 5.00) (pm PlayOn))"
            f"(hear Mine {now_s:.2f} self {text})").encode()


def test_the_own_position_in_team_decisions_is_the_one_the_teammates_heard():
    """Every player must decide with the same data: the own echoed message, not the fresher own pose."""
    from agent.communication.messages import TeamMessage, encode
    from agent.protocol import parse_sense
    from agent.team.roles import candidates
    from agent.world_model import WorldModel

    world = WorldModel("Mine", 2)
    text = encode(TeamMessage("c", 2, position=(-3.0, 1.0), ball=(0.0, 0.0)), "Mine")
    world.update(parse_sense(_sense(text)))
    assert world.own_report is not None and world.own_report.position == (-3.0, 1.0)
    # Garbage heard as "self" is ignored, the last good echo stays.
    world.update(parse_sense(_sense("zz", 10.02)))
    assert world.own_report.position == (-3.0, 1.0)
    # Not localized: no candidate at all (a player that does not know where it is does not claim the ball).
    assert candidates(world) == []


def test_support_spots_keep_clear_of_the_on_ball_players_path_and_the_balls_way_to_goal():
    from agent.team.roles import BALL_PATH_M, OPPONENT_GOAL_M, PATH_CLEARANCE_M, clear_of_segment

    def distance_to_segment(p, a, b):
        ax, ay, bx, by = *a, *b
        t = max(0.0, min(1.0, ((p[0] - ax) * (bx - ax) + (p[1] - ay) * (by - ay)) / ((bx - ax) ** 2 + (by - ay) ** 2)))
        return math.dist(p, (ax + t * (bx - ax), ay + t * (by - ay)))

    assert clear_of_segment((1.0, 0.2), (0.0, 0.0), (3.0, 0.0), 1.0) == pytest.approx((1.0, 1.0))
    assert clear_of_segment((1.0, 3.0), (0.0, 0.0), (3.0, 0.0), 1.0) == (1.0, 3.0)
    for unum in (2, 3, 4, 7, 9):
        for ball in ((-5.0, -3.0), (0.0, 0.0), (4.0, 2.0)):
            holder = (ball[0] - 3.0, ball[1] + 0.5)
            spot = support_spot(unum, ball, holder)
            assert distance_to_segment(spot, holder, ball) >= PATH_CLEARANCE_M - 1e-6
            heading = math.atan2(OPPONENT_GOAL_M[1] - ball[1], OPPONENT_GOAL_M[0] - ball[0])
            ahead = (ball[0] + BALL_PATH_M * math.cos(heading), ball[1] + BALL_PATH_M * math.sin(heading))
            assert distance_to_segment(spot, ball, ahead) >= PATH_CLEARANCE_M - 1e-6


def test_the_second_attacker_waits_behind_the_ball_away_from_the_on_ball_players_side():
    from agent.team.roles import SECOND_BEHIND_M, second_attacker, second_attacker_spot

    players = [Candidate(1, -14.0, 0.0), Candidate(2, -6.0, 1.0), Candidate(3, -9.0, -3.0), Candidate(4, -8.0, 2.0)]
    assert second_attacker(players, holder=2) == 3  # lowest field-player unum besides the holder
    assert second_attacker(players, holder=3) == 2
    assert second_attacker([Candidate(1, -14.0, 0.0), Candidate(2, 0.0, 0.0)], holder=2) is None
    ball = (0.0, 0.0)
    spot = second_attacker_spot(ball, holder=(-1.0, 1.0))  # the holder comes from the left
    assert spot[0] < ball[0] - 1.5 and spot[1] < 0.0  # behind the ball, on the right
    assert math.dist(spot, ball) == pytest.approx(math.hypot(SECOND_BEHIND_M, 1.5), abs=0.3)
    near_touch_line = second_attacker_spot((2.0, -9.0), holder=(1.0, -8.0))
    assert abs(near_touch_line[1]) <= 9.5


def test_the_keeper_blocks_a_shot_where_it_will_cross_its_line():
    """A shot crossing the keeper's line within the goal (and a ball's margin) moves the guard spot onto the
    crossing; one going wide, or none, leaves the spot following the ball."""
    assert roles.keeper_spot((-8.0, 3.0), crossing_y_m=-0.5) == (roles.KEEPER_X_M, -0.5)
    assert roles.keeper_spot((-8.0, 3.0), crossing_y_m=1.2) == (roles.KEEPER_X_M, roles.KEEPER_HALF_WIDTH_M)
    assert roles.keeper_spot((-8.0, 3.0), crossing_y_m=2.0) == roles.keeper_spot((-8.0, 3.0))
    assert roles.keeper_spot((-8.0, 3.0)) == (roles.KEEPER_X_M, 0.8)


def test_our_keeper_walks_toward_where_a_shot_on_our_simulator_will_cross_its_line():
    """Our goalkeeper (unum 1) at its spot; a ball rolls from (-10, 1.2) toward the goal's right half: 0.6 s after
    the launch the keeper's target is within 0.2 m of where the ball really crosses its line."""
    from motion_studio.match_agents import make_agent
    from tests.alone_in_play import alone_in_play

    agent = make_agent("Left", 1, 0)
    engine, host = alone_in_play(agent, roles.KEEPER_X_M, 0.0)
    host.run(150)
    engine.world.set_ball((-10.0, 1.2, 0.042), (-8.0, -1.4, 0.0))
    host.run(30)
    role, target = agent.behavior.role, agent.behavior._target
    crossing = None
    for _ in range(200):
        before = engine.world.ball_position()
        host.run(1)
        after = engine.world.ball_position()
        if before[0] >= roles.KEEPER_X_M > after[0]:
            share = (before[0] - roles.KEEPER_X_M) / (before[0] - after[0])
            crossing = before[1] + share * (after[1] - before[1])
            break
    assert crossing is not None and abs(crossing) < roles.KEEPER_HALF_WIDTH_M
    assert role == "keeper"
    assert target is not None and math.isclose(target[0], roles.KEEPER_X_M)
    assert abs(target[1] - crossing) < 0.2


def test_the_second_attacker_keeps_its_side_until_the_holder_clearly_crosses_the_line():
    """The holder circling the ball near the ball->goal line does not send the second attacker across behind
    the ball; a holder 0.5 m over the line onto its side does."""
    ball = (0.0, 0.0)  # the goal line runs along +x from here
    assert roles.second_attacker_side(ball, (-1.0, 0.3)) == -1.0  # holder left -> stand right
    assert roles.second_attacker_side(ball, (-1.0, -0.3), current=-1.0) == -1.0  # 0.3 m over: kept
    assert roles.second_attacker_side(ball, (-1.0, -0.6), current=-1.0) == 1.0  # 0.6 m over: across
    assert roles.second_attacker_side(ball, None, current=-1.0) == -1.0
    right = roles.second_attacker_spot(ball, (-1.0, -0.3), side=-1.0)
    assert right[1] < 0.0


def test_a_believed_holder_that_neither_plays_nor_nears_the_ball_loses_its_bonus_after_the_stall_time():
    ball = (0.0, 0.0)
    me, other = Candidate(2, -2.5, 1.4), Candidate(3, -2.5, -1.4)
    watch = HolderWatch()
    assert watch.keeps_bonus(10.0, 3, 2, [me, other], ball, open_play=True)
    assert watch.keeps_bonus(10.0 + HOLDER_STALL_S - 0.1, 3, 2, [me, other], ball, open_play=True)
    assert not watch.keeps_bonus(10.0 + HOLDER_STALL_S, 3, 2, [me, other], ball, open_play=True)
    # Coming 0.2 m nearer restarts the time; so does a set piece (the holder waits for it by rule).
    nearer = Candidate(3, -2.3, -1.3)
    assert watch.keeps_bonus(20.0, 3, 2, [me, nearer], ball, open_play=True)
    assert watch.keeps_bonus(20.0 + HOLDER_STALL_S - 0.1, 3, 2, [me, nearer], ball, open_play=True)
    assert watch.keeps_bonus(40.0, 3, 2, [me, nearer], ball, open_play=False)
    assert watch.keeps_bonus(40.0 + HOLDER_STALL_S - 0.1, 3, 2, [me, nearer], ball, open_play=True)


def test_a_holder_at_the_ball_or_the_player_itself_keeps_the_bonus():
    ball = (0.0, 0.0)
    at_ball = Candidate(3, -1.0, 0.5)   # going round it, 1.1 m away, for a long time
    watch = HolderWatch()
    assert all(watch.keeps_bonus(t, 3, 2, [at_ball], ball, open_play=True) for t in (0.0, 10.0, 60.0))
    far_me = Candidate(2, -8.0, 0.0)
    assert all(watch.keeps_bonus(t, 2, 2, [far_me], ball, open_play=True) for t in (0.0, 10.0, 60.0))


def test_with_crossed_beliefs_both_players_choose_the_same_holder_once_the_bonus_lapses():
    ball = (0.0, 0.0)
    players = [Candidate(2, -2.5, 1.4), Candidate(3, -2.5, -1.4)]
    assert choose_on_ball(players, ball, holder=3) == 3 and choose_on_ball(players, ball, holder=2) == 2
    assert choose_on_ball(players, ball, holder=None) == 2   # equal costs: the lower unum, for both of them


def test_at_the_opponents_kick_off_every_player_names_the_lowest_field_unum():
    players = [Candidate(1, -14.0, 0.0), Candidate(3, -2.5, -1.2), Candidate(2, -2.5, 1.3)]
    assert roles.kick_off_receiver(players) == 2
    assert roles.kick_off_receiver([Candidate(1, -14.0, 0.0), Candidate(3, -2.5, -1.2)]) == 3  # 2 fallen or silent
    assert roles.kick_off_receiver([Candidate(1, -14.0, 0.0)]) is None
