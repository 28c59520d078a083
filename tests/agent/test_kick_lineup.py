"""The kick line-up planner (agent.skills.kick_lineup.plan): one move per standing decision, from the ball's
ego position, the aim and the library's motions."""

from __future__ import annotations

import math

import pytest

from agent.skills.kick_lineup import (KICK_CONFIG_BY_TYPE, KICK_STEP_M, KickConfig, Spot, align, foot_side, plan,
                                    plan_with_fallback, strides_for)

CONFIG = KickConfig()
SPOTS = [Spot("kick", 0.118, 0.021), Spot("kick_left", 0.118, -0.021)]
ALL = frozenset({"kick", "kick_left", "walk_forward", "walk_backward", "walk_left", "walk_right", "turn_left",
                 "turn_right", "kick_step_forward", "kick_step_backward", "kick_step_left", "kick_step_right"})


def decide(ball, aim_deg=0.0, motions=ALL, corrections=0, approaches=0, fine_steps=0, localized=True):
    return plan(CONFIG, ball, math.radians(aim_deg), SPOTS, motions, corrections, approaches, fine_steps,
                localized)[1]


def test_walk_in_distances_follow_the_measured_cycles():
    assert CONFIG.walk_in_m(1) == pytest.approx(0.333)
    assert CONFIG.walk_in_m(2) == pytest.approx(0.441)
    assert CONFIG.walk_in_m(4) == pytest.approx(0.677)


@pytest.mark.parametrize("distance_m", [0.34, 0.45, 0.6, 0.85, 1.3])
def test_strides_leave_the_ball_nearest_to_the_target_without_touching_it(distance_m):
    strides, after = strides_for(CONFIG, distance_m)
    assert after == pytest.approx(distance_m - CONFIG.walk_in_m(strides))
    assert after >= CONFIG.walk_in_min_after_m
    for other in range(1, 12):
        other_after = distance_m - CONFIG.walk_in_m(other)
        if other_after >= CONFIG.walk_in_min_after_m:
            assert abs(after - CONFIG.walk_in_target_m) <= abs(other_after - CONFIG.walk_in_target_m) + 1e-9


def test_ball_on_its_spot_facing_the_aim_kicks_with_that_foot():
    move = decide((0.12, -0.02))
    assert (move.kind, move.motion) == ("kick", "kick_left")


def test_ball_1m_ahead_on_the_kick_line_walks_in_without_stopping_first():
    """The kick challenge's start: one walk-in of counted strides, no turn, no side step."""
    move = decide((0.97, 0.0))
    assert move.kind == "walk_in" and move.motion == "walk_forward"
    after = 0.97 - 0.118 - CONFIG.walk_in_m(move.strides)
    assert CONFIG.loose_forward_min_m <= after <= CONFIG.loose_forward_max_m + 2 * KICK_STEP_M
    # Beyond the loose window (the real kick grazes the ball from 6 cm beyond its spot): kick steps, no back-off.
    move = decide((0.118 + after, 0.0), fine_steps=CONFIG.max_fine_steps)
    assert (move.kind, move.motion) == ("move", "kick_step_forward")


@pytest.mark.parametrize("beyond_m", [0.05, 0.06, 0.08])
def test_a_ball_beyond_the_loose_window_is_stepped_to_not_kicked(beyond_m):
    """On the real server the kick grazed the ball from 5.5-6.3 cm beyond its spot in 9 of 18 kick-off line-ups
    (0.02-0.10 m) when the loose window reached 8 cm; a step (2 cm) or two bring it in."""
    move = decide((0.118 + beyond_m, 0.0), fine_steps=CONFIG.max_fine_steps)
    assert (move.kind, move.motion) == ("move", "kick_step_forward")
    assert CONFIG.loose_forward_max_m <= 0.05


def test_far_ball_off_the_aim_goes_to_the_approach_point_first():
    """Ball 1 m ahead, aim 30° to the left: the approach point lies behind the ball on the kick line, to the
    right; the robot turns toward it (right) rather than to the aim (left)."""
    move = decide((0.97, 0.0), aim_deg=30.0)
    assert (move.kind, move.motion) == ("turn", "turn_right")
    move = decide((0.8, 0.45), aim_deg=58.0)  # facing the approach point now
    assert move.kind == "approach" and move.strides >= 1 and move.goal_ego is not None


def test_approach_goes_round_a_ball_in_the_way():
    """Robot in front of the ball, aim behind the robot: the walk to the kick line must not cross the ball."""
    ball = (0.2, 0.0)
    alignment, move = plan(CONFIG, ball, math.radians(180.0), SPOTS, ALL, 0, 0, 0, True)
    assert move.kind in ("turn", "approach")
    a = align(ball, math.radians(180.0), SPOTS, CONFIG)
    assert a.error_f < 0  # the kick pose lies behind the ball, seen along the aim


def test_small_heading_error_at_the_ball_turns_in_place():
    move = decide((0.12, 0.02), aim_deg=8.0)
    assert (move.kind, move.motion) == ("turn", "turn_left")
    assert move.turn_deg == pytest.approx(8.0)


def test_ball_in_the_loose_window_late_is_kicked_at_once_not_stepped():
    ball = (0.118 + 0.03, 0.021)
    assert decide(ball).kind == "move" and decide(ball).fine  # one kick step first while there is time
    move = decide(ball, fine_steps=CONFIG.max_fine_steps)
    assert move.kind == "kick"


def test_large_sideways_offset_walks_sideways_by_counted_strides():
    move = decide((0.4, 0.45))
    assert (move.kind, move.motion) == ("walk_side", "walk_left")
    assert move.strides == 3


def test_place_and_kick_without_walks_or_turns():
    kicks_only = frozenset({"kick", "kick_left"})
    assert decide((0.14, -0.02), aim_deg=20.0, motions=kicks_only).kind == "kick"  # cannot turn: heading ignored
    move = decide((0.5, 0.0), motions=kicks_only)
    assert move.kind == "give_up" and "no motion" in move.why


def test_not_localized_never_approaches():
    move = decide((1.5, 0.8), aim_deg=40.0, localized=False)
    assert move.kind == "turn"


def test_corrections_used_up_kick_in_the_loose_window_or_give_up():
    assert decide((0.118 + 0.04, 0.0), corrections=CONFIG.max_corrections).kind == "kick"
    assert decide((0.4, 0.2), corrections=CONFIG.max_corrections).kind == "give_up"
    # Beyond the loose window even then: a kick from there grazes the ball on the real server.
    assert decide((0.118 + 0.06, 0.0), corrections=CONFIG.max_corrections).kind == "give_up"


def test_ball_at_the_feet_far_off_the_aim_backs_off_first():
    """Turning 60° or walking round with the ball 0.2 m ahead would kick it: back off by counted cycles."""
    move = decide((0.2, 0.0), aim_deg=60.0)
    assert (move.kind, move.motion) == ("walk_back", "walk_backward")
    assert CONFIG.backward_walk_m + (move.strides - 1) * CONFIG.backward_stride_m >= CONFIG.room_m - 0.2


def test_small_heading_error_is_turned_out_only_while_there_is_time():
    ball = (0.118 + 0.005, -0.021)
    assert decide(ball, aim_deg=4.0).kind == "turn"
    assert decide(ball, aim_deg=4.0, fine_steps=CONFIG.max_fine_steps).kind == "kick"


#: The long kick's spot lies 8 mm nearer than the kick's (kick_strong.xml 0.1212 m, kick.xml 0.1294 m).
STRONG_SPOTS = [Spot("kick_strong", 0.110, 0.02), Spot("kick_strong_left", 0.110, -0.02)]
STRONG_CONFIG = CONFIG.for_strong_kick()


def _decide_strong(ball: tuple[float, float], fine_steps: int = 0):
    return plan_with_fallback(STRONG_CONFIG, CONFIG, ball, 0.0, STRONG_SPOTS, SPOTS, ALL, corrections=0,
                              approaches=0, fine_steps=fine_steps, localized=True)[1]


def test_long_kick_on_its_spot_is_played():
    move = _decide_strong((0.110 + 0.005, 0.02))
    assert (move.kind, move.motion) == ("kick", "kick_strong")


def test_long_kick_missing_its_narrow_window_late_plays_the_normal_kick_at_once():
    """3 cm beyond the long kick's spot (where it misses the ball) once the fine steps are used up: the normal
    kick, whose loose window reaches 8 cm, kicks now; earlier a kick step is still worth it for the long one."""
    ball = (0.110 + 0.03, 0.02)
    early = _decide_strong(ball)
    assert early.kind == "move" and early.motion == "kick_step_forward"
    late = _decide_strong(ball, fine_steps=CONFIG.max_fine_steps)
    assert (late.kind, late.motion) == ("kick", "kick")
    assert "fallback" in late.why
    assert plan(STRONG_CONFIG, ball, 0.0, STRONG_SPOTS, ALL, 0, 0, CONFIG.max_fine_steps, True)[1].kind != "kick"


def test_long_kick_far_from_the_ball_walks_in_for_the_long_kick():
    move = _decide_strong((1.0, 0.02))
    assert move.kind == "walk_in"


@pytest.mark.parametrize("beyond_m", [0.30, 0.31, 0.32])
def test_a_walk_in_that_would_end_on_the_ball_steps_back_first(beyond_m):
    """One stride (0.333 m) from 0.30-0.32 m beyond the spot would end 1-3 cm short of it: on the real server that
    walk-in pushed the ball away (the kick-off taker after 1 in 5 beams); a kick step back makes room."""
    move = decide((0.118 + beyond_m, 0.0))
    assert (move.kind, move.motion) == ("move", "kick_step_backward")
    after_step = decide((0.118 + beyond_m + 2 * KICK_STEP_M, 0.0))
    assert after_step.kind == "walk_in" and after_step.strides == 1


@pytest.mark.parametrize("beyond_m", [0.415, 0.425])
def test_between_the_one_and_the_two_cycle_walk_in_a_step_back_makes_the_longer_fit(beyond_m):
    """0.415-0.425 m beyond the spot one cycle (0.333 m) leaves the ball 8-9 cm beyond it, past the loose window's
    4.1 cm, two (0.441 m) end 1.6-2.6 cm short: a kick step back, then the two-cycle walk-in, rather than a walk-in
    followed by kick steps (or a back-off that walked in to the same place again, on the real server)."""
    move = decide((0.118 + beyond_m, 0.0))
    assert (move.kind, move.motion) == ("move", "kick_step_backward")
    after_step = decide((0.118 + beyond_m + KICK_STEP_M, 0.0))
    assert after_step.kind == "walk_in" and after_step.strides == 2


def test_a_robot_type_plays_its_own_walk_in_distances_and_windows():
    type3 = CONFIG.for_robot_type(3)
    assert type3.walk_in_m(1) == pytest.approx(KICK_CONFIG_BY_TYPE[3]["walk_in_first_m"])
    assert type3.walk_in_m(1) < CONFIG.walk_in_m(1) - 0.02  # its shorter steps
    assert type3.loose_forward_max_m < CONFIG.loose_forward_max_m
    assert type3.heading_tol_deg == CONFIG.heading_tol_deg  # the rest stays
    assert CONFIG.for_robot_type(0) == CONFIG and CONFIG.for_robot_type(4) == CONFIG
    # 0.37 m beyond the spot: type 0 walks in one cycle to 3.7 cm beyond it (its loose window); type 3's one cycle
    # ends 6.4 cm beyond it, outside its own, and two 4 cm short: it steps back first.
    assert plan(CONFIG, (0.118 + 0.37, 0.0), 0.0, SPOTS, ALL, 0, 0, 0, True)[1].kind == "walk_in"
    assert plan(type3, (0.118 + 0.385, 0.0), 0.0, SPOTS, ALL, 0, 0, 0, True)[1].motion == "kick_step_backward"


# ---- the kick's ball direction (KickConfig.aim_ball_direction) -------------------------------------------------
DIRECTED = KickConfig(aim_ball_direction=True)
DIRECTED_SPOTS = [Spot("kick", 0.118, 0.021, -8.0), Spot("kick_left", 0.118, -0.021, 8.0)]


def test_a_directed_kick_pose_faces_the_aim_turned_back_by_the_ball_direction():
    # The ball straight ahead on the right foot's spot, the aim straight ahead: the right-foot kick sends the ball
    # 8 deg right, so its pose faces 8 deg left of the aim; off (the default) it faces the aim.
    ball = (0.118 + 0.005, 0.021)
    directed = align(ball, 0.0, DIRECTED_SPOTS, DIRECTED, directed=True)
    assert directed.spot.motion == "kick"
    assert directed.aim_deg == pytest.approx(8.0)
    plain = align(ball, 0.0, DIRECTED_SPOTS, CONFIG)
    assert plain.aim_deg == pytest.approx(0.0) and plain.spot.motion == "kick"
    # the default plan ignores the direction: the ball on its spot kicks at once
    assert plan(CONFIG, ball, 0.0, DIRECTED_SPOTS, ALL, 0, 0, 0, True)[1].kind == "kick"
    assert plan(DIRECTED, ball, 0.0, DIRECTED_SPOTS, ALL, 0, 0, 0, True)[1].kind == "turn"


def test_the_foot_is_chosen_in_the_aim_frame_and_kept():
    # A ball in the middle: without a kept foot the choice is the aim frame's (the feet's own frames, 16 deg apart,
    # made it flip as the robot turned); a kept foot stays unless the other fits clearly better.
    ball = (0.30, 0.0)
    first = align(ball, 0.0, DIRECTED_SPOTS, DIRECTED, directed=True)
    other = "left" if first.spot.motion == "kick" else "right"
    kept = align(ball, 0.0, DIRECTED_SPOTS, DIRECTED, directed=True, keep_side=other)
    assert foot_side(kept.spot.motion) == other
    near_right = (0.13, 0.015)   # 6 mm from the right foot's spot, 3.6 cm from the left's
    assert align(near_right, 0.0, DIRECTED_SPOTS, DIRECTED, directed=True).spot.motion == "kick"
    assert align(near_right, 0.0, DIRECTED_SPOTS, DIRECTED, directed=True, keep_side="left").spot.motion == "kick_left"
    far_right = (0.13, 0.021 - 0.25)   # 25 cm right of the right foot's spot: the left foot no longer holds
    assert align(far_right, 0.0, DIRECTED_SPOTS, DIRECTED, directed=True, keep_side="left").spot.motion == "kick"
    assert foot_side("kick_strong_left") == "left" and foot_side("kick") == "right"
