"""ODE's joint drift in our world (`sim.joint_slack`): where it acts (the legs' ball-side twins only), that a still
robot has none, that a beam forgets it, and that switching it off leaves MuJoCo's own rigid joints. Its agreement with
the real server's measured drift is tested in tests/motion_studio/test_joint_slack.py."""

from __future__ import annotations

import mujoco
import numpy as np
import pytest

from sim.physics_params import default_physics_params
from sim.world import BALL_SIDE_BODIES, BALL_TWIN_SUFFIX, World


def _standing_world(**physics: object) -> World:
    world = World(default_physics_params(**physics))
    world.add_robot(1, 0)
    world.set_team(1, "left", 1)
    world.place_robot(1, -2.0, 0.0, 0.0, z_m=0.37)
    return world


def _ball_contacts(world: World) -> list[str]:
    m, d = world.model, world.data
    names = []
    for i in range(d.ncon):
        contact = d.contact[i]
        if world.ball_geom in (contact.geom1, contact.geom2):
            other = contact.geom2 if contact.geom1 == world.ball_geom else contact.geom1
            names.append(m.geom(int(other)).name)
    return names


def test_the_ball_meets_the_legs_ball_side_twins_and_the_ground_meets_the_originals():
    world = _standing_world()
    twins = [world.model.geom(f"r1_{name}{BALL_TWIN_SUFFIX}").id for name in BALL_SIDE_BODIES]
    assert all(world.model.geom_contype[g] == 0 for g in twins)   # nothing but the ball collides with a twin
    for _ in range(30):
        world.step()
    foot = world.body_position(world.by_key[1].body_rows["rfoot"])
    world.set_ball((foot[0] + 0.05, foot[1], 0.042))   # overlapping the right foot's front
    mujoco.mj_forward(world.model, world.data)
    touched = _ball_contacts(world)
    assert "r1_rfoot_ball" in touched and "r1_rfoot" not in touched, touched
    grounds = [world.model.geom(int(c.geom1 if c.geom2 == world.model.geom("field").id else c.geom2)).name
               for c in world.data.contact[:world.data.ncon] if world.model.geom("field").id in (c.geom1, c.geom2)]
    assert "r1_rfoot" in grounds and not any(name.endswith(BALL_TWIN_SUFFIX) for name in grounds), grounds


def test_a_still_robot_has_no_drift_and_a_beam_forgets_it():
    world = _standing_world()
    for _ in range(100):
        world.step()
    robot = world.by_key[1]
    assert np.abs(world.joint_slack.drift_of(robot.body_ids)).max() < 3e-4   # standing: real 0.2 mm, ours ~0.1
    world.joint_slack.drift_m[:] = 0.01
    world.place_robot(1, 3.0, 1.0, 90.0)
    assert np.abs(world.joint_slack.drift_of(robot.body_ids)).max() == 0.0
    twin = world.model.geom("r1_rfoot_ball").id
    original = world.model.geom("r1_rfoot").id
    assert np.allclose(world.model.geom_pos[twin], world.model.geom_pos[original])


def test_switched_off_the_legs_have_no_twins_and_the_ball_meets_them_directly():
    world = _standing_world(joint_slack_erp=None)
    assert world.joint_slack is None
    assert not any(world.model.geom(g).name.endswith(BALL_TWIN_SUFFIX) for g in range(world.model.ngeom))
    for _ in range(30):
        world.step()
    foot = world.body_position(world.by_key[1].body_rows["rfoot"])
    world.set_ball((foot[0] + 0.05, foot[1], 0.042))
    mujoco.mj_forward(world.model, world.data)
    assert "r1_rfoot" in _ball_contacts(world)
    assert world.body_centres() is world.data.xpos


def test_the_rigid_joints_candidate_switches_the_drift_off():
    """``NAO3D_PHYSICS_FILE=sim/physics_candidates/rigid_joints.toml`` gives MuJoCo's own joints back (no twins, the
    monitor's centres where the joints put them), to see what the drift changes."""
    from pathlib import Path

    from sim.physics_params import load_physics_file

    candidate = Path(__file__).parents[2] / "sim" / "physics_candidates" / "rigid_joints.toml"
    world = World(default_physics_params(**load_physics_file(candidate)))
    world.add_robot(1, 0)
    assert world.joint_slack is None
    assert not any(world.model.geom(g).name.endswith(BALL_TWIN_SUFFIX) for g in range(world.model.ngeom))


def test_the_drift_rows_of_tracked_bodies_read_their_drift_and_an_untracked_body_is_refused():
    world = _standing_world()
    robot = world.by_key[1]
    feet = np.array([robot.body_rows["lfoot"], robot.body_rows["rfoot"]])
    world.joint_slack.drift_m[:] = np.arange(world.joint_slack.drift_m.size).reshape(-1, 3)
    rows = world.joint_slack.rows_of(feet)
    assert np.array_equal(world.joint_slack.drift_m[rows], world.joint_slack.drift_of(feet))
    with pytest.raises(ValueError, match="not tracked"):
        world.joint_slack.rows_of(np.array([robot.torso_body]))
