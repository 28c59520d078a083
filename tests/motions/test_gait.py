"""The IK gait generator (motions.authoring.gait): footsteps, keyframes within the joint limits and where
the plan puts the feet, the stance-flag and finalize chain, the walk-lean names, the parameter file, and
the shipped files (they load back and equal what the generator makes from the shipped parameters)."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

from kinematics.fk import NaoKinematics
from kinematics.spec import robot_spec
from motions import XML, load, validate_motion
from motions.authoring.common import FILES_DIR
from motions.authoring.gait import (MOTION_NAMES, STANCE_FLAG, GaitParams, build_named, build_stance, build_walk,
                                    lean_side, plan_steps, write_gait_files)
from motions.authoring.gait_params import GAIT_PARAMS_PATH, load_gait_params, parse_gait_params

LIMITS = {j.perceptor: (j.min_rad, j.max_rad) for j in robot_spec(0).joints}


@pytest.fixture(scope="module")
def shipped_params():
    return load_gait_params()


@pytest.fixture(scope="module")
def forward(shipped_params):
    return build_walk("walk_forward", shipped_params["walk_forward"])


def _phases(motion, prefix):
    return [k for k in motion.keyframes if k.name.startswith(prefix)]


# ---- footsteps -------------------------------------------------------------------------------------------
def test_footsteps_alternate_and_advance_by_the_step_length():
    params = GaitParams(step_length_m=0.07)
    left, right, steps = plan_steps(params, [1.0, 1.0, 1.0, 1.0])
    assert [s.side for s in steps] == ["left", "right", "left", "right"]
    assert steps[0].landing.y_m == pytest.approx(right.y_m + 0.07)
    assert steps[1].landing.y_m == pytest.approx(steps[0].landing.y_m + 0.07)
    assert all(abs(s.landing.x_m) == pytest.approx(params.foot_spacing_m / 2) for s in steps)


def test_sideways_gait_opens_with_the_leading_foot_and_closes_with_the_other():
    params = GaitParams(step_length_m=0.0, side_step_m=-0.04)  # to the left
    left, right, steps = plan_steps(params, [1.0, 1.0])
    assert steps[0].side == "left" and steps[0].landing.x_m == pytest.approx(left.x_m - 0.04)
    spacing = steps[0].landing.x_m - steps[1].landing.x_m
    assert abs(spacing) == pytest.approx(params.foot_spacing_m)


# ---- keyframes ---------------------------------------------------------------------------------------------
@pytest.mark.parametrize("name", MOTION_NAMES)
def test_every_shipped_keyframe_is_within_the_joint_limits(shipped_params, name):
    motion = build_named(name, shipped_params[name])
    validate_motion(motion)
    for keyframe in motion.keyframes:
        for wire, target in keyframe.targets.items():
            low, high = LIMITS[wire]
            assert low - 1e-9 <= target.angle_rad <= high + 1e-9, (keyframe.name, wire, target.angle_deg)


def test_cycle_keyframes_put_the_feet_where_the_plan_says(shipped_params, forward):
    """FK of the solved angles: the swing sole rises to the step height and lands a step ahead."""
    params = shipped_params["walk_forward"]
    fk = NaoKinematics(0)
    cycle = _phases(forward, "cycle_")
    heights, gaps = [], []
    for keyframe in cycle:
        angles = {wire: t.angle_rad for wire, t in keyframe.targets.items()}
        left, right = fk.frame_pose("lsole", angles).position_m, fk.frame_pose("rsole", angles).position_m
        heights.append(left[2] - right[2])
        gaps.append(left[1] - right[1])
    n = params.step_cycles
    # The left foot swings first: its sole is highest in the middle of its swing, by the step height.
    assert max(heights[:n]) == pytest.approx(params.step_height_m, abs=0.004)
    # At the end of the left step the left sole is a step length ahead of the right (torso frame: tilted by
    # the torso pitch, so compare along the tilted forward axis).
    assert gaps[n - 1] * math.cos(math.radians(params.torso_pitch_deg)) == pytest.approx(
        params.step_length_m, abs=0.01)
    assert gaps[2 * n - 1] == pytest.approx(-gaps[n - 1], abs=0.01)


def _largest_step_rad(a, b) -> float:
    return max(abs(b.targets[w].angle_rad - a.targets[w].angle_rad) for w in a.targets)


def test_phase_seams_are_as_smooth_as_the_cycle(forward):
    """The cycle's loop back, the ramp into the cycle and the way into the stop move no joint further in
    one 20 ms keyframe than the cycle itself does (the chains are planned as one footstep sequence)."""
    cycle = _phases(forward, "cycle_")
    within = max(_largest_step_rad(a, b) for a, b in zip(cycle, cycle[1:]))
    seams = [(cycle[-1], cycle[0]), (_phases(forward, "start_")[-1], cycle[0]), (cycle[-1], forward.phase("stop_00"))]
    for a, b in seams:
        assert _largest_step_rad(a, b) <= within + math.radians(0.5), (a.name, b.name)
    stop = _phases(forward, "stop_")
    assert max(_largest_step_rad(a, b) for a, b in zip(stop, stop[1:])) <= within + math.radians(0.5)


# ---- phase chain and flags -------------------------------------------------------------------------------
def test_stance_flag_chain(forward, shipped_params):
    stance = forward.phase("stance")
    assert stance.skip_if_flag == STANCE_FLAG and forward.first_phase == "stance"
    assert forward.phase("start_00").set_flag_false == STANCE_FLAG
    cycle = _phases(forward, "cycle_")
    last = cycle[-1]
    assert last.next == "cycle_00" and last.is_final and last.finalize == "stop_00"
    assert cycle[0].set_flag_false == STANCE_FLAG
    assert all(k.finalize is None for k in cycle[:-1])
    hold = forward.phase("stop_hold")
    assert hold.set_flag_true == STANCE_FLAG and hold.is_final and hold.next is None
    stand = build_stance("stand", shipped_params["stand"])
    assert [k.set_flag_true for k in stand.keyframes] == [STANCE_FLAG]


def test_play_order_while_requested_loops_and_the_stop_reaches_the_hold(forward):
    order = [k.name for k in forward.play_order()]
    assert order[0] == "stance" and order[-1].startswith("cycle_")
    phase = forward.phase(order[-1])
    stop_chain = []
    current = forward.successor(phase, requested_same_motion=False)
    while current is not None:
        stop_chain.append(current.name)
        current = forward.successor(current, requested_same_motion=False)
    assert stop_chain[0] == "stop_00" and stop_chain[-1] == "stop_hold"


def test_stop_ends_in_the_stance_pose(forward):
    stance, hold = forward.phase("stance"), forward.phase("stop_hold")
    for wire, target in stance.targets.items():
        assert hold.targets[wire].angle_rad == pytest.approx(target.angle_rad, abs=math.radians(0.05))


def test_lean_names_sit_on_the_swing_leg_only(forward, shipped_params):
    params = shipped_params["walk_forward"]
    for index, keyframe in enumerate(_phases(forward, "cycle_")):
        side = lean_side(index, params)
        computed = {wire: t.computed for wire, t in keyframe.targets.items() if t.computed}
        prefix, other = side[0], "right" if side == "left" else "left"
        assert computed == {f"{prefix}lj1": f"{other}_walk_lean_{prefix}le1",
                            **{f"{prefix}lj{k}": f"{side}_walk_lean_{prefix}le{k}" for k in (3, 5)}}
    assert not any(t.computed for k in forward.keyframes if not k.name.startswith("cycle_")
                   for t in k.targets.values())


def test_lean_side_follows_the_swing_through_the_next_double_support():
    params = GaitParams(step_cycles=6, double_support_cycles=1)
    sides = [lean_side(i, params) for i in range(12)]
    assert sides == ["right"] + ["left"] * 6 + ["right"] * 5


def test_constants_say_speed_and_step_time(shipped_params):
    params = shipped_params["walk_forward"]
    motion = build_walk("walk_forward", params, measured={"measured_forward_m_s": 0.5})
    assert motion.constants["speed_m_s"] == pytest.approx(params.step_length_m / (params.step_cycles * 0.02), abs=1e-4)
    assert motion.constants["measured_forward_m_s"] == 0.5
    left = build_walk("walk_left", shipped_params["walk_left"])
    assert left.constants["side_speed_m_s"] > 0


# ---- parameter file and shipped files ----------------------------------------------------------------------
def test_parameter_file_errors_name_the_section():
    with pytest.raises(ValueError, match=r"\[walk_forward\].*unknown key 'step_lenght_m'"):
        parse_gait_params("[walk_forward]\nstep_lenght_m = 0.1\n", "gait.toml")
    with pytest.raises(ValueError, match="arm has unknown keys"):
        parse_gait_params("[common]\narm = { elbow = 3.0 }\n[stand]\n", "gait.toml")


def test_common_section_is_the_default_of_every_motion():
    table = parse_gait_params("[common]\ntorso_height_m = 0.33\n[stand]\n[walk_forward]\ntorso_height_m = 0.32\n")
    assert table["stand"].torso_height_m == 0.33 and table["walk_forward"].torso_height_m == 0.32
    assert "common" not in table


@pytest.mark.parametrize("name", MOTION_NAMES)
def test_shipped_files_load_back_and_match_the_generator(tmp_path, name):
    shipped = load(FILES_DIR / f"{name}.xml")
    assert shipped.source_format == XML and shipped.name == name
    assert any("motions.authoring.gait" in line for line in shipped.header_comments)
    fresh = load(write_gait_files(GAIT_PARAMS_PATH, tmp_path, (name,))[0])
    assert [k.name for k in fresh.keyframes] == [k.name for k in shipped.keyframes]
    for a, b in zip(fresh.keyframes, shipped.keyframes):
        assert a.duration_s == b.duration_s and a.next == b.next and a.finalize == b.finalize
        for wire, target in a.targets.items():
            assert b.targets[wire].computed == target.computed
            assert b.targets[wire].angle_rad == pytest.approx(target.angle_rad, abs=math.radians(0.05)), (a.name, wire)


@pytest.mark.parametrize("name", [n for n in MOTION_NAMES if n != "stand"])
def test_every_shipped_walk_starts_from_and_stops_in_the_stance_of_stand(name):
    # The stance flag lets a walk skip its stance phase after ``stand`` or another walk's stop, so both
    # ends of every walk must be stand's pose (a forward walk restarted from its own toe-out stance fell
    # in 10 of 10 trials on our simulator).
    stand = load(FILES_DIR / "stand.xml").keyframes[0]
    walk = load(FILES_DIR / f"{name}.xml")
    for phase in (walk.phase("stance"), walk.phase("stop_hold")):
        for wire, target in stand.targets.items():
            assert phase.targets[wire].angle_rad == pytest.approx(target.angle_rad, abs=math.radians(0.01)), \
                (phase.name, wire)


def test_unreachable_gait_raises_an_ik_error():
    from kinematics.errors import IKError

    with pytest.raises(IKError):
        build_walk("w", replace(GaitParams(), torso_height_m=0.40))
    assert np.isfinite(GaitParams().speed_m_s)
