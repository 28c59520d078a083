"""The referee moves players as SimSpark's SoccerBase::MoveAgent does: a translation of the robot as it stands
(posture, orientation and height kept, velocities zeroed). Placed upright at 0.4 m instead, a robot in its
walk stance (torso pitched 17 deg) was set on its toes: the right team's falls in the first 15 s of an 11 v 11
kick-off on our simulator (seed 0) went from 5 to 2 with the translation."""

from __future__ import annotations

import numpy as np
import pytest

from motion_studio.match_agents import make_agent, make_idle_agent
from sim.engine import SimEngine
from sim.inprocess import InProcessHost


def _robot(engine: SimEngine, team: str, unum: int):
    return next(r for r in engine.world.robots() if r.team == team and r.unum == unum)


def test_shift_keeps_posture_orientation_and_height_and_zeroes_velocities():
    engine = SimEngine(seed=0)
    host = InProcessHost(engine)
    host.add(make_idle_agent("Left", 1, 0))  # the first team to connect plays left
    host.run(2)
    key = host.add(make_idle_agent("Right", 2, 0))
    host.run(150)  # beamed and crouched into the walk stance
    world = engine.world
    before_rotation = world.torso_rotation(key).copy()
    before_z = float(world.torso_position(key)[2])
    joints_before = world.data.qpos.copy()
    world.shift_robot("right", 2, 3.0, -2.0)
    assert world.torso_position(key)[:2] == pytest.approx((3.0, -2.0))
    assert world.torso_position(key)[2] == pytest.approx(before_z)
    np.testing.assert_allclose(world.torso_rotation(key), before_rotation, atol=1e-12)
    robot = world.by_key[key]
    hinge = slice(robot.root_qadr + 7, robot.root_qadr + 7 + len(robot.spec.joints))
    np.testing.assert_allclose(world.data.qpos[hinge], joints_before[hinge])
    assert not np.any(world.data.qvel[robot.root_dof:robot.root_dof + 6])


def test_a_player_cleared_from_the_centre_circle_keeps_standing():
    """Our right player crouched in its walk stance inside the circle at the left team's kick-off: the referee
    moves it out (x = 2.5) as it stands, torso pitched as before, and it still stands 3 s later."""
    engine = SimEngine(seed=0)
    host = InProcessHost(engine)
    host.add(make_idle_agent("Left", 1, 0))  # the first team to connect plays left
    host.run(2)
    key = host.add(make_agent("Right", 2, 0))
    host.run(150)
    engine.world.shift_robot("right", 2, 0.6, 0.0)  # into the circle, as it stands (BeforeKickOff: it waits)
    host.run(50)
    pitch_before = engine.world.torso_rotation(key)[2, 1]
    assert abs(pitch_before) > 0.1  # the walk stance leans the torso
    engine.referee.kick_off("Left")
    host.run(2)
    robot = _robot(engine, "right", 2)
    assert robot.torso_pos_m[0] >= 2.0  # cleared from the circle
    assert engine.world.torso_rotation(key)[2, 1] == pytest.approx(pitch_before, abs=0.02)  # not set upright
    host.run(150)
    assert _robot(engine, "right", 2).torso_pos_m[2] > 0.3
