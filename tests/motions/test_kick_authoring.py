"""The kick generator: phases and flags, walk-stance compatibility, CoM over the support sole, mirror,
reach clamping, parameter file errors, and the shipped files equal a fresh generation."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

import motions
from kinematics.fk import NaoKinematics
from motions.authoring.common import FootPose, KeyframeSolver
from motions.authoring.gait import STANCE_FLAG, build_stance
from motions.authoring import kick_steps
from tests.motions.conftest import assert_shipped_as_generated
from motions.authoring.kick import (FILES_DIR, JOINT_OFFSETS, STRIKE_PHASES, KickParams, Pose, PoseSolver,
                                    ball_constants, build_all, build_kick, kick_params, kick_poses, parse_kick_params,
                                    stance_params)

SINGLE_SUPPORT = ("lift", "windup", "swing", "strike", "follow", "retract")


@pytest.fixture(scope="module")
def kicks():
    return build_all()


@pytest.fixture(scope="module")
def fk():
    return NaoKinematics(0)


def _angles(keyframe) -> dict[str, float]:
    return {wire: target.angle_rad for wire, target in keyframe.targets.items()}


def test_four_kicks_with_their_names_and_valid_angles(kicks):
    assert set(kicks) == {"kick", "kick_strong", "kick_left", "kick_strong_left"}
    for name, motion in kicks.items():
        assert motion.name == name
        motion.validate()  # joint limits, durations, phase names
        assert {"ball_forward_m", "ball_left_m"} <= set(motion.constants)
        assert any("motions.authoring.kick" in line for line in motion.header_comments)


def test_phase_chain_and_flags(kicks):
    motion = kicks["kick"]
    order = [k.name for k in motion.play_order()]
    assert order[0] == "stance" and order[-1] == "recover"
    assert {"shift", "lift", "windup", "strike", "follow", "retract", "land"} <= set(order)
    stance, shift, recover = motion.phase("stance"), motion.phase("shift"), motion.phase("recover")
    assert stance.skip_if_flag == STANCE_FLAG
    assert shift.set_flag_false == STANCE_FLAG
    assert recover.set_flag_true == STANCE_FLAG and recover.is_final and recover.next is None


def test_starts_and_ends_in_the_walk_stance(kicks):
    stand = build_stance("stand", stance_params())
    stand_angles = _angles(stand.keyframes[0])
    for phase in ("stance", "recover"):
        angles = _angles(kicks["kick"].phase(phase))
        assert max(abs(angles[w] - stand_angles[w]) for w in stand_angles) < math.radians(0.02), phase


def test_com_over_the_support_sole_on_one_foot(kicks, fk):
    """In every single-support keyframe the CoM lies over the support sole (left for the right-foot kick),
    at the target inset/forward offset within 3 mm (5 mm at the strike and follow-through, whose kicking
    ankle and hip yaw-pitch are offset after the IK), and the kicking sole is off the ground."""
    for name, support, kicking, side in (("kick", "lsole", "rsole", 1.0), ("kick_left", "rsole", "lsole", -1.0)):
        motion = kicks[name]
        params = kick_params(name.removesuffix("_left"))
        for phase in SINGLE_SUPPORT:
            keyframe = motion.find_phase(phase)
            if keyframe is None:
                continue
            angles = _angles(keyframe)
            sole = fk.frame_pose(support, angles)
            com = sole.rotation.T @ (fk.com(angles) - sole.position_m)
            tolerance = 0.005 if phase in STRIKE_PHASES else 0.003
            assert abs(com[0] - side * params.com_inset_m) < tolerance, (name, phase, com)
            assert abs(com[1] - params.com_forward_m) < tolerance, (name, phase, com)
            other = fk.frame_pose(kicking, angles)
            height = (sole.rotation.T @ (other.position_m - sole.position_m))[2]
            assert height > 0.01, (name, phase, height)


def test_left_kick_is_the_mirror_image(kicks):
    right, left = kicks["kick"], kicks["kick_left"]
    assert [k.name for k in right.keyframes] == [k.name for k in left.keyframes]
    strike_r, strike_l = right.phase("strike"), left.phase("strike")
    assert strike_l.angle_rad("llj3") == pytest.approx(strike_r.angle_rad("rlj3"))  # pitch keeps its sign
    assert strike_l.angle_rad("llj2") == pytest.approx(-strike_r.angle_rad("rlj2"))  # roll flips
    assert left.constants["ball_left_m"] == pytest.approx(-right.constants["ball_left_m"])
    assert left.constants["ball_forward_m"] == pytest.approx(right.constants["ball_forward_m"])
    # the measured ball direction (motions/params/kick.toml: the real kick 7.6-8.5 deg to the kicking foot's side)
    assert right.constants["ball_direction_deg"] == pytest.approx(-8.0)
    assert left.constants["ball_direction_deg"] == pytest.approx(8.0)
    assert "ball_direction_deg" not in kicks["kick_strong"].constants   # the long kick goes straight: 0, not written


def test_strike_moves_the_foot_forward_through_the_ball_spot(kicks, fk):
    """The kicking sole goes from behind the support sole at the windup to ahead of it at the strike (the
    IK's kick; kick_strong's strike targets carry joint-space offsets the leg never reaches before the contact,
    and its physics is checked in tests/scenarios/test_kick.py)."""
    motion = kicks["kick"]
    params = kick_params("kick")

    def forward(phase: str) -> float:
        angles = _angles(motion.phase(phase))
        support, kicking = fk.frame_pose("lsole", angles), fk.frame_pose("rsole", angles)
        return float((support.rotation.T @ (kicking.position_m - support.position_m))[1])

    assert forward("windup") < -0.02
    assert forward("strike") > 0.05
    toe_reach = forward("strike") + 0.08  # sole centre + half the foot length
    assert toe_reach > params.ball_ahead_m - 0.042  # the toe passes the ball's back (support-sole frame)


def test_far_target_is_clamped_to_reach_not_an_error():
    stance = stance_params()
    params = replace(KickParams(), strike_forward_m=0.40)
    solver = PoseSolver(stance)
    half = stance.foot_spacing_m / 2
    solver.solve(Pose(FootPose(half, 0.0), FootPose(-half, 0.0), None, stance.torso_pitch_deg))
    for _, _, pose in kick_poses(params, stance):
        solver.solve(pose)
    assert min(solver.reached) < 1.0  # the strike was clamped
    strict = PoseSolver(stance, clamp_to_reach=False)
    strict.solve(Pose(FootPose(half, 0.0), FootPose(-half, 0.0), None, stance.torso_pitch_deg))
    with pytest.raises(Exception):
        for _, _, pose in kick_poses(params, stance):
            strict.solve(pose)


def test_parameter_file_errors_name_the_key():
    with pytest.raises(ValueError, match="strike_speed"):
        parse_kick_params("[kick]\nstrike_speed = 3.0\n", "k.toml")
    with pytest.raises(ValueError, match="k.toml"):
        parse_kick_params("[kick\n", "k.toml")
    sections = parse_kick_params("[common]\nstrike_ms = 60\n[kick]\n[kick_strong]\nstrike_ms = 40\n"
                                 "provenance = 'x'\n")
    assert sections["kick"].strike_ms == 60 and sections["kick_strong"].strike_ms == 40


def test_shipped_files_equal_a_fresh_generation(kicks):
    """motions/files/kick*.xml are what the generator makes from the parameter files (regenerate with
    ``python -m motions.authoring.kick`` after changing them)."""
    for name, motion in kicks.items():
        assert_shipped_as_generated(motions.load(FILES_DIR / f"{name}.xml"), motion)


def test_joint_offsets_move_only_their_joint_in_their_phases_within_its_range():
    """Each joint-space offset (the long kick's windup and strike poses beyond the foot-pose IK) adds to one
    joint's IK target in its phases only, and a large one stops at the joint's limit."""
    stance = stance_params()
    plain = replace(kick_params("kick"), **{parameter: 0.0 for parameter in JOINT_OFFSETS})
    base = build_kick("kick", plain, stance)
    limits = {joint.perceptor: (joint.min_rad, joint.max_rad) for joint in KeyframeSolver().ik.spec.joints}
    for parameter, (phases, wire) in JOINT_OFFSETS.items():
        shifted = build_kick("kick", replace(plain, **{parameter: 7.0}), stance)
        for before, after in zip(base.keyframes, shifted.keyframes):
            for joint, target in before.targets.items():
                moved = after.angle_rad(joint) - target.angle_rad
                if before.name in phases and joint == wire:
                    low, high = limits[wire]
                    want = min(high, target.angle_rad + math.radians(7.0)) - target.angle_rad
                    assert moved == pytest.approx(want, abs=1e-9), (parameter, before.name)
                else:
                    assert moved == pytest.approx(0.0, abs=1e-9), (parameter, before.name, joint)
    folded = build_kick("kick", replace(plain, windup_knee_offset_deg=-400.0), stance)
    windup = next(k for k in folded.keyframes if k.name == "windup")
    assert windup.angle_rad("rlj4") == pytest.approx(limits["rlj4"][0], abs=1e-6)


def test_build_kick_reuses_a_solver():
    solver = KeyframeSolver()
    stance = stance_params()
    first = build_kick("kick", KickParams(), stance, solver)
    second = build_kick("kick", KickParams(), stance, solver)
    assert [_angles(k) for k in first.keyframes] == [_angles(k) for k in second.keyframes]
    assert np.isfinite([a for k in first.keyframes for a in _angles(k).values()]).all()


def test_a_ball_direction_is_written_only_where_measured():
    stance = stance_params()
    assert "ball_direction_deg" not in ball_constants(KickParams(), stance)
    assert ball_constants(KickParams(ball_direction_deg=-7.25), stance)["ball_direction_deg"] == pytest.approx(-7.25)


def test_ball_spot_follows_the_stance():
    """The ball spot is fixed to the support sole: a wider stance moves the ego spot, not the kick."""
    stance = stance_params()
    params = KickParams()
    narrow = ball_constants(params, replace(stance, foot_spacing_m=0.10, torso_forward_m=0.0))
    wide = ball_constants(params, replace(stance, foot_spacing_m=0.12, torso_forward_m=0.01))
    assert wide["ball_left_m"] - narrow["ball_left_m"] == pytest.approx(0.01)
    assert narrow["ball_forward_m"] - wide["ball_forward_m"] == pytest.approx(0.01)
    assert narrow["ball_left_m"] == pytest.approx(0.05 - params.ball_side_m)


def test_kick_steps_move_the_feet_by_their_constants(fk):
    """Each kick step ends in the walk stance with both soles moved by its ego displacement (FK of the last
    one-foot keyframe against the first), and the left step mirrors the right one."""
    steps = kick_steps.build_all()
    assert set(steps) == {"kick_step_forward", "kick_step_backward", "kick_step_left", "kick_step_right"}
    for name, motion in steps.items():
        motion.validate()
        assert motion.phase("stance").skip_if_flag == STANCE_FLAG
        assert motion.phase("settle").set_flag_true == STANCE_FLAG
        # place_a: the right foot (left foot for the mirrored left step) has moved, the other is the origin.
        mover, support = ("lsole", "rsole") if name == "kick_step_left" else ("rsole", "lsole")
        before = _angles(motion.phase("shift_a"))
        after = _angles(motion.phase("place_a"))

        def offset(angles):
            s, m = fk.frame_pose(support, angles), fk.frame_pose(mover, angles)
            return s.rotation.T @ (m.position_m - s.position_m)

        moved = offset(after) - offset(before)
        forward, left = motion.constants["step_forward_m"], motion.constants["step_left_m"]
        assert moved[1] == pytest.approx(forward, abs=0.002), name
        assert -moved[0] == pytest.approx(left, abs=0.002), name
    assert steps["kick_step_left"].constants["step_left_m"] == pytest.approx(
        -steps["kick_step_right"].constants["step_left_m"])
