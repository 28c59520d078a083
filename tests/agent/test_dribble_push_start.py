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
    dribble._aim_point(robot_m[0], robot_m[1], heading, ball_m)
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
