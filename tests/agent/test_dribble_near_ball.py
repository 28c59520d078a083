"""The dribble's near-ball line-up (``agent.skills.dribble.Dribble._near_ball``) and its hysteresis: robot frame [m].

The stop before a short walk pushes the ball on; on the real server it rolled just past ``near_ball_m`` and the
approach then turned 40-55 deg away from the target line and back. Once lining up, the robot keeps lining up while
the ball stays within ``near_ball_keep_m``.
"""

from __future__ import annotations

from agent.motion import MotionController, default_library
from agent.skills.dribble import Dribble, DribbleConfig

#: The ball 0.54 m ahead and 0.28 m to the left (0.61 m away), where the real dribble's first push left it.
ROLLED_ON = (0.54, 0.28)


def _near(mode: str, ball_ego: tuple[float, float], config: DribbleConfig | None = None):  # noqa: ANN202
    """The near-ball request of a dribble toward +x whose last cycle's mode was ``mode``, the robot standing and
    facing the target."""
    dribble = Dribble(15.0, 0.0, config)
    dribble.mode = mode
    motion = MotionController(default_library(0))
    return dribble._near_ball(motion, 0.0, 0.0, ball_ego, (0.0, 0.0))


def test_a_fresh_approach_leaves_a_ball_beyond_near_ball_m_to_the_approach():
    assert _near("approach", ROLLED_ON) is None


def test_lining_up_goes_on_with_a_side_walk_toward_a_ball_that_rolled_past_near_ball_m():
    request = _near("near:stop", ROLLED_ON)
    assert request is not None and request.motion == "walk_left"


def test_lining_up_ends_beyond_near_ball_keep_m():
    assert _near("near:stop", (0.75, 0.3)) is None
    assert _near("near:stop", ROLLED_ON, DribbleConfig(near_ball_keep_m=0.6)) is None
