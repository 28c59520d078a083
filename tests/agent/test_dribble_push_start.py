"""When the dribble starts pushing (``agent.skills.dribble.Dribble._aim_point``): pure geometry, team frame [m].

The robot walks at the ball once it pushes, so the ball leaves along the line robot -> ball whatever the
robot's heading; a push that starts with that line far off the line to the target sends the ball aside.
"""

from __future__ import annotations

import math

import pytest

from agent.skills.dribble import Dribble, DribbleConfig


def _starts_pushing(robot_m: tuple[float, float], ball_m: tuple[float, float], target_m=(15.5, 0.0)) -> bool:
    """A fresh dribble toward ``target_m``, the robot at ``robot_m`` facing the ball: does it push?"""
    dribble = Dribble(*target_m)
    heading = math.atan2(ball_m[1] - robot_m[1], ball_m[0] - robot_m[0])
    dribble._aim_point(robot_m[0], robot_m[1], heading, ball_m, dribble.line_rad(robot_m[0], robot_m[1], ball_m))
    return dribble.pushing


def test_a_robot_behind_the_ball_on_its_line_to_the_target_pushes():
    assert _starts_pushing((4.6, 0.0), (5.0, 0.0))
    assert _starts_pushing((4.5, -0.08), (5.0, 0.0))


@pytest.mark.parametrize("across_m", [0.25, -0.3])
def test_a_robot_walking_at_the_ball_from_well_off_its_line_does_not_push_yet(across_m):
    """0.5 m behind and 0.25-0.3 m across: the line robot -> ball is 27-31 deg off the line to the target.
    Before ``push_line_deg`` this pushed (the approach point was within ``push_start_m`` of the ball)."""
    assert not _starts_pushing((4.5, across_m), (5.0, 0.0))
    assert math.degrees(math.atan2(abs(across_m), 0.5)) > DribbleConfig().push_line_deg


def test_near_the_goal_the_push_waits_for_a_straighter_line():
    """13.5 deg off the line: a push in midfield, not 3 m before the goal (a standing keeper and the posts)."""
    assert _starts_pushing((4.5, -0.12), (5.0, 0.0))
    assert not _starts_pushing((12.0, -0.12), (12.5, 0.0))
    assert _starts_pushing((12.0, -0.05), (12.5, 0.0))


FREE = DribbleConfig(free_line_deg=40.0, free_line_out_deg=10.0)


def _line_deg(robot_m: tuple[float, float], ball_m: tuple[float, float], config: DribbleConfig = FREE,
              target_m=(15.5, 0.0)) -> float:
    return math.degrees(Dribble(*target_m, config).line_rad(robot_m[0], robot_m[1], ball_m))


def test_far_from_the_goal_a_robot_within_the_cone_pushes_along_its_own_line():
    """Ball at y = -1 m, 10.5 m from the target; the robot's line to it 26 deg off the line to the target,
    toward the field's long axis: the match dribble pushes at once, along robot -> ball."""
    robot, ball = (4.5, -1.3), (5.0, -1.0)
    dribble = Dribble(15.5, 0.0, FREE)
    heading = math.atan2(ball[1] - robot[1], ball[0] - robot[0])
    dribble._aim_point(robot[0], robot[1], heading, ball, dribble.line_rad(robot[0], robot[1], ball))
    assert dribble.pushing
    assert _line_deg(robot, ball) == pytest.approx(math.degrees(heading))
    assert not _starts_pushing(robot, ball)  # the default (the skill benchmark's) still lines up first


def test_away_from_the_long_axis_the_cone_is_narrow():
    """The same robot mirrored to the outer side: 36 deg off outward, the line stops at ``free_line_out_deg``."""
    to_target = math.degrees(math.atan2(1.0, 10.5))
    assert _line_deg((4.5, -0.7), (5.0, -1.0)) == pytest.approx(to_target - 10.0)
    assert _line_deg((4.5, 0.7), (5.0, 1.0)) == pytest.approx(-to_target + 10.0)  # mirrored field side
    assert _line_deg((4.5, 0.3), (5.0, 0.0)) == pytest.approx(-10.0)  # on the axis: narrow both ways
    assert _line_deg((4.5, -0.3), (5.0, 0.0)) == pytest.approx(10.0)


def test_outside_the_cone_the_robot_lines_up_on_its_nearer_edge():
    to_target = math.degrees(math.atan2(2.0, 10.5))
    assert _line_deg((5.0, -3.0), (5.0, -2.0)) == pytest.approx(to_target + 40.0)  # 90 deg off, inward edge
    assert _line_deg((5.0, -1.0), (5.0, -2.0)) == pytest.approx(to_target - 10.0)  # outward edge


def test_the_cone_narrows_near_the_target_and_closes_within_free_line_none_m():
    def line_at(ball_x_m: float) -> float:
        ball = (ball_x_m, -1.0)
        robot = (ball_x_m - 0.5, -1.0 - 0.866)  # 60 deg off the x axis, inward
        return _line_deg(robot, ball) - math.degrees(math.atan2(1.0, 15.5 - ball_x_m))
    assert line_at(15.5 - FREE.free_line_full_m - 0.5) == pytest.approx(40.0)
    x = 15.5 - (FREE.free_line_full_m + FREE.free_line_none_m) / 2.0
    share = (math.hypot(15.5 - x, 1.0) - FREE.free_line_none_m) / (FREE.free_line_full_m - FREE.free_line_none_m)
    assert line_at(x) == pytest.approx(40.0 * share)  # about half (the ball's distance counts, not its x)
    assert line_at(15.5 - FREE.free_line_none_m + 0.3) == pytest.approx(0.0)


def test_a_line_toward_the_touch_line_turns_back_to_the_target():
    """Ball at y = 8 m, the robot's line 45 deg toward the touch line: even the outward edge (10 deg) would
    reach y = 8.5 within 3 m with a wide cone; past ``free_line_field_y_m`` the line to the target is kept."""
    wide = DribbleConfig(free_line_deg=40.0, free_line_out_deg=40.0)
    ball = (0.0, 8.0)
    to_target = math.degrees(math.atan2(-8.0, 15.5))
    assert _line_deg((-0.5, 7.5), ball, wide) == pytest.approx(to_target)
    assert _line_deg((-0.5, 8.5), ball, wide) == pytest.approx(-45.0)  # away from the touch line: its own line
