"""MuJoCo, Pinocchio and PlaCo load one MJCF text and agree on CoM and every frame at random poses."""

import mujoco
import numpy as np
import pinocchio as pin
import pytest

from kinematics.ik import WholeBodyIK
from kinematics.mjcf import robot_mjcf_xml, site_offsets
from kinematics.pinocchio_model import pinocchio_model
from kinematics.spec import robot_spec
from kinematics.urdf import robot_urdf_xml


STANDING_BY_TYPE = {t: np.array([0.0, 0.0, -robot_spec(t).sole_z_m]) for t in range(5)}


def random_pose(spec, rng):
    lo = np.array([j.min_rad for j in spec.joints])
    hi = np.array([j.max_rad for j in spec.joints])
    return rng.uniform(lo, hi)


def random_base(rng):
    quat_wxyz = rng.normal(size=4)
    return rng.uniform(-1, 1, size=3), quat_wxyz / np.linalg.norm(quat_wxyz)


@pytest.mark.parametrize("robot_type", [0, 1, 2, 3, 4])
def test_mujoco_and_pinocchio_agree_on_com_and_every_frame(robot_type):
    spec = robot_spec(robot_type)
    model = mujoco.MjModel.from_xml_string(robot_mjcf_xml(robot_type))
    data = mujoco.MjData(model)
    pin_model = pinocchio_model(robot_type)
    pin_data = pin_model.createData()
    rng = np.random.default_rng(robot_type)
    sites = list(site_offsets(spec))
    for _ in range(25):
        angles = random_pose(spec, rng)
        pos, quat = random_base(rng)
        data.qpos[:] = np.concatenate((pos, quat, angles))
        mujoco.mj_kinematics(model, data)
        mujoco.mj_comPos(model, data)
        # Pinocchio's free flyer is relative to the MJCF torso position; its quaternion is x, y, z, w.
        q = np.concatenate((pos - STANDING_BY_TYPE[robot_type], quat[[1, 2, 3, 0]], angles))
        pin.framesForwardKinematics(pin_model, pin_data, q)
        com = pin.centerOfMass(pin_model, pin_data, q)
        assert np.abs(com - data.subtree_com[1]).max() < 1e-9
        for body in spec.bodies:
            frame = pin_data.oMf[pin_model.getFrameId(body.name)]
            assert np.abs(frame.translation - data.body(body.name).xpos).max() < 1e-9
            assert np.abs(frame.rotation - data.body(body.name).xmat.reshape(3, 3)).max() < 1e-9
        for site in sites:
            frame = pin_data.oMf[pin_model.getFrameId(site)]
            assert np.abs(frame.translation - data.site(site).xpos).max() < 1e-9


@pytest.mark.parametrize("robot_type", [0, 3, 4])
def test_placo_model_agrees_with_mujoco(robot_type):
    spec = robot_spec(robot_type)
    ik = WholeBodyIK(robot_type)
    model = mujoco.MjModel.from_xml_string(robot_mjcf_xml(robot_type))
    data = mujoco.MjData(model)
    rng = np.random.default_rng(10 + robot_type)
    assert ik.robot.total_mass() == pytest.approx(spec.total_mass_kg, abs=1e-12)
    for joint in spec.joints:  # PlaCo sees the spec's hinges and limits too
        assert ik.robot.get_joint_limits(joint.perceptor) == pytest.approx([joint.min_rad, joint.max_rad])
    for _ in range(10):
        angles = random_pose(spec, rng)
        for name, value in zip(spec.joint_names, angles):
            ik.robot.set_joint(name, value)
        ik.robot.state.q[:7] = [0, 0, 0, 0, 0, 0, 1]
        ik.robot.update_kinematics()
        data.qpos[:] = np.concatenate((STANDING_BY_TYPE[robot_type], [1, 0, 0, 0], angles))
        mujoco.mj_kinematics(model, data)
        mujoco.mj_comPos(model, data)
        assert np.abs(ik.robot.com_world() - data.subtree_com[1]).max() < 1e-9
        for frame in ["lsole", "rsole", "lhand", "rhand", "camera", "lfoot", "head"]:
            placement = ik.robot.get_T_world_frame(frame)
            xpos = data.site(frame).xpos if frame in model.names.decode() and frame in site_offsets(spec) \
                else data.body(frame).xpos
            assert np.abs(placement[:3, 3] - xpos).max() < 1e-9


@pytest.mark.parametrize("robot_type", [0, 4])
def test_urdf_export_matches_mjcf(robot_type):
    spec = robot_spec(robot_type)
    urdf_model = pin.buildModelFromXML(robot_urdf_xml(robot_type), pin.JointModelFreeFlyer())
    mjcf_model = pinocchio_model(robot_type, free=False)
    urdf_data, mjcf_data = urdf_model.createData(), mjcf_model.createData()
    angles = random_pose(spec, np.random.default_rng(3))
    by_name = dict(zip(spec.joint_names, angles))
    q_urdf = np.array([0, 0, 0, 0, 0, 0, 1.0] + [by_name[urdf_model.names[i]] for i in range(2, urdf_model.njoints)])
    pin.framesForwardKinematics(urdf_model, urdf_data, q_urdf)
    pin.framesForwardKinematics(mjcf_model, mjcf_data, angles)
    assert mjcf_data.oMf[mjcf_model.getFrameId("torso")].translation == pytest.approx(np.zeros(3))
    for site in set(site_offsets(spec)) - {"imu"}:  # a fixed-base MJCF drops the sites of the welded root
        a = urdf_data.oMf[urdf_model.getFrameId(site)].translation
        b = mjcf_data.oMf[mjcf_model.getFrameId(site)].translation
        assert np.abs(a - b).max() < 1e-12
    assert pin.computeTotalMass(urdf_model) == pytest.approx(spec.total_mass_kg)
