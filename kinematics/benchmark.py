"""Kinematics figures: FK and IK speed, and the largest MuJoCo vs Pinocchio disagreement."""

from __future__ import annotations

import math
import time

import mujoco
import numpy as np
import pinocchio as pin

from kinematics.fk import NaoKinematics
from kinematics.ik import PoseTarget, WholeBodyIK
from kinematics.mjcf import robot_mjcf_xml
from kinematics.pinocchio_model import pinocchio_model
from kinematics.spec import ROBOT_TYPES, robot_spec


def fk_camera_height_us(repeats: int = 20000, seed: int = 0) -> float:
    """Median microseconds per camera-height FK call (batches of 1000 random in-limit poses)."""
    kin = NaoKinematics(0)
    spec = robot_spec(0)
    rng = np.random.default_rng(seed)
    poses = rng.uniform([j.min_rad for j in spec.joints], [j.max_rad for j in spec.joints], size=(1000, 22))
    batches = []
    for _ in range(max(1, repeats // 1000)):
        start = time.perf_counter()
        for q in poses:
            kin.camera_height_m(q)
        batches.append((time.perf_counter() - start) / len(poses) * 1e6)
    return float(np.median(batches))


def ik_keyframe_ms(keyframes: int = 200) -> float:
    """Median milliseconds per whole-body IK keyframe (feet, torso, CoM) solved to 1 mm / 1 deg, warm-started.

    The keyframes walk through a crouch-and-shift sequence, as a motion author's consecutive keyframes do.
    """
    ik = WholeBodyIK(0)
    identity = np.eye(3)
    times = []
    for i in range(keyframes):
        phase = 2 * math.pi * i / 40
        targets = {"lfoot": PoseTarget((-0.055, 0.025, 0.0), identity),
                   "rfoot": PoseTarget((0.055, 0.025 + 0.02 * math.sin(phase), 0.01 + 0.01 * math.cos(phase)),
                                       identity),
                   "torso": PoseTarget((0.0, 0.0, 0.33 + 0.01 * math.sin(phase)), identity)}
        start = time.perf_counter()
        ik.solve(targets)
        times.append((time.perf_counter() - start) * 1e3)
    return float(np.median(times[5:]))


def model_disagreement(poses_per_type: int = 100, seed: int = 0) -> tuple[float, float]:
    """Largest |CoM| and |frame position| difference between MuJoCo and Pinocchio over random poses, all types."""
    rng = np.random.default_rng(seed)
    max_com = max_frame = 0.0
    for robot_type in ROBOT_TYPES:
        spec = robot_spec(robot_type)
        model = mujoco.MjModel.from_xml_string(robot_mjcf_xml(robot_type))
        data = mujoco.MjData(model)
        pin_model = pinocchio_model(robot_type)
        pin_data = pin_model.createData()
        standing = np.array([0.0, 0.0, -spec.sole_z_m])
        frame_ids = [pin_model.getFrameId(b.name) for b in spec.bodies]
        for _ in range(poses_per_type):
            angles = rng.uniform([j.min_rad for j in spec.joints], [j.max_rad for j in spec.joints])
            position = rng.uniform(-1, 1, 3)
            quat = rng.normal(size=4)
            quat /= np.linalg.norm(quat)
            data.qpos[:] = np.concatenate((position, quat, angles))
            mujoco.mj_kinematics(model, data)
            mujoco.mj_comPos(model, data)
            q = np.concatenate((position - standing, quat[[1, 2, 3, 0]], angles))
            pin.framesForwardKinematics(pin_model, pin_data, q)
            com = pin.centerOfMass(pin_model, pin_data, q)
            max_com = max(max_com, float(np.abs(com - data.subtree_com[1]).max()))
            for body, fid in zip(spec.bodies, frame_ids):
                diff = np.abs(pin_data.oMf[fid].translation - data.body(body.name).xpos).max()
                max_frame = max(max_frame, float(diff))
    return max_com, max_frame


def run(poses_per_type: int = 100) -> dict[str, float]:
    max_com, max_frame = model_disagreement(poses_per_type)
    return {"fk_us": round(fk_camera_height_us(), 2), "ik_ms": round(ik_keyframe_ms(), 3),
            "max_com_diff_m": max_com, "max_frame_diff_m": max_frame, "poses_per_type": poses_per_type,
            "robot_types": len(ROBOT_TYPES)}
