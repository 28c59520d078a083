"""Whole-body IK meets reachable targets, respects limits, and names the task it cannot meet."""

import math

import numpy as np
import pytest

from kinematics import IKError, SpecError
from kinematics.fk import NaoKinematics
from kinematics.ik import PoseTarget, WholeBodyIK
from kinematics.spec import robot_spec

I3 = np.eye(3)


def rot_z(angle_rad: float) -> np.ndarray:
    c, s = math.cos(angle_rad), math.sin(angle_rad)
    return np.array([[c, -s, 0], [s, c, 0], [0, 0, 1.0]])


@pytest.fixture(scope="module")
def ik():
    return WholeBodyIK(0)


def within_limits(angles: dict[str, float], robot_type: int = 0) -> bool:
    spec = robot_spec(robot_type)
    return all(spec.joint(n).min_rad - 1e-9 <= v <= spec.joint(n).max_rad + 1e-9 for n, v in angles.items())


def assert_met(ik, result, targets):
    for task, target in targets.items():
        frame = {"lfoot": "lsole", "rfoot": "rsole", "lhand": "lhand", "rhand": "rhand", "torso": "torso"}[task]
        pose = ik.robot.get_T_world_frame(frame)
        if target.position_m is not None:
            assert np.linalg.norm(pose[:3, 3] - target.position_m) < 1e-3
        if target.rotation is not None:
            angle = math.acos(np.clip((np.trace(target.rotation.T @ pose[:3, :3]) - 1) / 2, -1, 1))
            assert angle < math.radians(1.0)


def test_crouch_with_feet_planted_meets_targets_and_matches_fk(ik):
    targets = {"lfoot": PoseTarget((-0.055, 0.025, 0.0), I3), "rfoot": PoseTarget((0.055, 0.025, 0.0), I3),
               "torso": PoseTarget((0.0, 0.0, 0.33), I3)}
    result = ik.solve(targets, seed_rad=np.zeros(22))
    assert_met(ik, result, targets)
    assert within_limits(result.angles_rad)
    # Independent check with the Pinocchio FK: the torso is 0.33 m above the sole plane.
    assert -NaoKinematics(0).frame_pose("lsole", result.angles_rad).position_m[2] == pytest.approx(0.33, abs=1e-3)
    assert result.angles_rad["llj4"] < -0.5  # the knees bend (negative in SimSpark)


def test_kick_pose_foot_forward_and_hands(ik):
    # The right foot turns outward (yaw < 0): rlj1 can only open the hip outward (max 1 deg).
    legs = {"lfoot": PoseTarget((-0.06, 0.025, 0.0), I3), "rfoot": PoseTarget((0.07, 0.12, 0.05), rot_z(-0.1)),
            "torso": PoseTarget(None, I3)}
    first = ik.solve(legs, com_xy_m=(-0.05, 0.03), seed_rad=np.zeros(22))
    # A hand target known to be reachable: where FK puts the hand for a lowered, bent arm.
    arm = {"laj1": -0.8, "laj2": 0.4, "laj3": -0.5, "laj4": -0.7}
    hand_in_torso = NaoKinematics(0).frame_pose("lhand", arm).position_m
    assert ik.robot.com_world()[:2] == pytest.approx([-0.05, 0.03], abs=1e-3)
    targets = {**legs, "lhand": PoseTarget(first.torso_pose[:3, :3] @ hand_in_torso + first.torso_pose[:3, 3])}
    result = ik.solve(targets)
    assert_met(ik, result, targets)
    assert within_limits(result.angles_rad)


def test_unreachable_target_raises_with_task_and_residual(ik):
    targets = {"lfoot": PoseTarget((-0.055, 0.025, 0.0), I3), "rfoot": PoseTarget((0.055, 0.025, 0.0), I3),
               "rhand": PoseTarget((0.098, 1.0, 0.5))}
    with pytest.raises(IKError) as err:
        ik.solve(targets, seed_rad=np.zeros(22))
    assert err.value.task == "rhand:pos"
    assert err.value.residual > 0.5
    assert "rhand:pos" in str(err.value)
    assert within_limits(ik.angles())


def test_random_reachable_targets_from_fk_are_recovered(ik):
    """Targets made by FK of random in-limit leg poses are reachable by construction."""
    rng = np.random.default_rng(1)
    spec = robot_spec(0)
    kin = NaoKinematics(0)
    for _ in range(5):
        angles = {n: 0.0 for n in spec.joint_names}
        for side in "lr":
            angles[f"{side}lj3"] = rng.uniform(0.2, 0.8)
            angles[f"{side}lj4"] = rng.uniform(-1.4, -0.4)
            angles[f"{side}lj5"] = -(angles[f"{side}lj3"] + angles[f"{side}lj4"]) + rng.uniform(-0.1, 0.1)
        # Express the soles relative to the torso; the torso is the world frame's origin here.
        targets = {"torso": PoseTarget((0.0, 0.0, 0.0), I3)}
        for side, task in (("l", "lfoot"), ("r", "rfoot")):
            pose = kin.frame_pose(f"{side}sole", angles)
            targets[task] = PoseTarget(pose.position_m, pose.rotation)
        result = ik.solve(targets, seed_rad=np.zeros(22))
        assert_met(ik, result, targets)
        assert within_limits(result.angles_rad)


def test_bad_ik_input(ik):
    with pytest.raises(SpecError, match="unknown IK task 'foot'"):
        ik.solve({"foot": PoseTarget((0, 0, 0))})
    with pytest.raises(SpecError, match="non-finite"):
        ik.solve({"lfoot": PoseTarget((0, float("nan"), 0))})
    with pytest.raises(SpecError, match="seed angle must be finite"):
        ik.solve({"lfoot": PoseTarget((0, 0, 0))}, seed_rad={"llj3": float("inf")})
