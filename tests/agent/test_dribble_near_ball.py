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


def _near_facing(heading_deg: float, ball_ego: tuple[float, float], library=None, playing: str | None = None):  # noqa: ANN001, ANN202
    """The near-ball request of a dribble toward +x (the target direction 0) for a robot facing ``heading_deg``,
    lining up already, with ``playing`` under way (None: standing)."""
    import math

    from agent.motion import MotionRequest

    dribble = Dribble(15.0, 0.0)
    dribble.mode = "near:stop"
    motion = MotionController(library or default_library(0))
    if playing is not None:
        motion.request(MotionRequest(playing))
        motion.update({})
    return dribble._near_ball(motion, math.radians(heading_deg), 0.0, ball_ego, (0.0, 0.0))


def test_facing_off_the_target_with_the_ball_ahead_the_robot_orbits_it_toward_the_target():
    request = _near_facing(-40.0, (0.45, 0.0))   # the target direction lies 40 deg to the left
    assert request is not None and request.motion == "orbit_left"
    request = _near_facing(35.0, (0.44, -0.1))
    assert request is not None and request.motion == "orbit_right"


def test_with_the_ball_out_to_the_side_or_without_orbits_the_robot_turns_in_place():
    request = _near_facing(-40.0, (0.3, 0.4))   # the ball 53 deg to the left: beyond orbit_ball_deg
    assert request is not None and request.motion == "turn_left"
    library = default_library(0)
    library.remove("orbit_left")
    request = _near_facing(-40.0, (0.45, 0.0), library)
    assert request is not None and request.motion == "turn_left"


def test_an_orbit_goes_on_until_the_robot_faces_the_target_or_the_ball_leaves_its_cone():
    assert _near_facing(-30.0, (0.45, 0.0), playing="orbit_left").motion == "orbit_left"
    assert _near_facing(-8.0, (0.45, 0.0), playing="orbit_left").motion is None    # within orbit_done_deg: stop
    assert _near_facing(-30.0, (0.3, 0.3), playing="orbit_left").motion is None    # the ball 45 deg aside: stop
    assert _near_facing(30.0, (0.45, 0.0), playing="orbit_left").motion is None    # overshot: stop, then orbit back
