"""sim.rules.self_collision: the batched path over the simulator's pose arrays reports what the per-robot path
reports, on random arm and leg poses of every robot type (many of them colliding)."""

from __future__ import annotations

import mujoco
import numpy as np

from sim.rules.self_collision import BodyPoseArrays, SharedPoseBatch, colliding_pairs_many
from sim.world import World


def test_batched_pairs_equal_the_per_robot_pairs() -> None:
    world = World()
    for key, robot_type in enumerate((0, 1, 2, 3, 4, 0, 2), start=1):
        world.add_robot(key, robot_type, position_m=(2.0 * key, 0.0, 0.5))
    rng = np.random.default_rng(0)
    motors, batch = world.motors, SharedPoseBatch()
    reported = 0
    for _ in range(300):
        world.data.qpos[motors.qadr] = rng.uniform(motors.min_rad, motors.max_rad)
        mujoco.mj_kinematics(world.model, world.data)
        data = world.data
        shared = [(r.robot_type, BodyPoseArrays(r.body_rows, data.xpos, data.xmat)) for r in world.by_key.values()]
        plain = [(robot_type, dict(poses.items())) for robot_type, poses in shared]   # copies: per-type path
        batched = colliding_pairs_many(shared, 0.04, batch)
        assert batched == colliding_pairs_many(plain, 0.04)
        reported += sum(map(len, batched))
    assert reported > 20
