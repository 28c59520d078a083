"""A robot whose physics blows up (a joint driven far past its stop, a non-finite acceleration) never
scrambles the match: it goes back to the cycle's start at rest, inside its stops; the others play on."""

from __future__ import annotations

import numpy as np

from tests.sim.test_world_physics import cycle, standing


def _robot_slices(world, key):
    robot = world.by_key[key]
    n = len(robot.spec.joints)
    return slice(robot.root_qadr, robot.root_qadr + 7 + n), slice(robot.root_dof, robot.root_dof + 6 + n)


def test_a_joint_spinning_past_its_stop_is_reset_and_the_other_robot_keeps_its_step():
    world = standing(2)
    cycle(world, 5)
    q0, v0 = _robot_slices(world, 0)
    q1, _ = _robot_slices(world, 1)
    start_other = world.data.qpos[q1].copy()
    motors = world.motors
    ankle = int(np.flatnonzero(motors.dof == world.by_key[0].root_dof + 6 + 10)[0])  # llj5, ankle pitch
    # What a blow-up looks like a cycle before it runs away: 57 deg past the stop, spinning at 400 rad/s.
    world.data.qpos[motors.qadr[ankle]] = motors.max_rad[ankle] + 1.0
    world.data.qvel[motors.dof[ankle]] = 400.0
    cycle(world)
    assert world.divergences == 1
    assert np.all(world.data.qvel[v0] == 0.0)
    angles = world.data.qpos[motors.qadr]
    assert np.all(angles >= motors.min_rad - 1e-9) and np.all(angles <= motors.max_rad + 1e-9)
    assert np.allclose(world.data.qpos[q1], start_other, atol=1e-3)  # the other robot stood on
    cycle(world, 50)
    assert world.divergences == 1 and world.data.qpos[q0][2] > 0.3  # and it stands again


def test_mujoco_reset_on_a_bad_acceleration_is_undone():
    world = standing(2)
    cycle(world, 5)
    q1, _ = _robot_slices(world, 1)
    before = world.data.qpos[q1].copy()
    _, v0 = _robot_slices(world, 0)
    world.data.qvel[v0.start + 6] = np.nan  # MuJoCo resets the whole world to qpos0 on this
    cycle(world)
    assert world.divergences >= 1
    assert np.all(np.isfinite(world.data.qpos))
    # Not at the model's origin pose: every robot is where it was.
    assert np.allclose(world.data.qpos[q1][:3], before[:3], atol=1e-2)


def test_a_ball_touched_by_a_robot_blowing_up_goes_back_with_it():
    world = standing(1)
    cycle(world, 5)
    foot = world.data.xpos[world.by_key[0].foot_bodies["lf"]]
    # The ball against the top front edge of the left foot (foot half length 8 cm, top 1.8 cm above the
    # ground; the ball's surface is 3.4 cm ahead of its centre at that height), 2 mm into it.
    world.set_ball((foot[0] + 0.08 + 0.034 - 0.002, foot[1], 0.042))
    world.end_cycle()
    start_q = world.data.qpos[world.ball_qadr:world.ball_qadr + 7].copy()
    start_v = world.data.qvel[world.ball_dof:world.ball_dof + 6].copy()
    motors = world.motors
    ankle = int(np.flatnonzero(motors.dof == world.by_key[0].root_dof + 6 + 10)[0])  # llj5: swings the foot
    world.data.qvel[motors.dof[ankle]] = -400.0        # the foot still touches the ball when the step starts
    cycle(world)
    assert world.divergences == 1 and world.ball_touchers() == [("left", 1)]
    assert np.array_equal(world.data.qpos[world.ball_qadr:world.ball_qadr + 7], start_q)
    assert np.array_equal(world.data.qvel[world.ball_dof:world.ball_dof + 6], start_v)
