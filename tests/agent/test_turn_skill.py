"""Turn skills (agent/skills/turn.py) without the simulator: splitting a turn into motions, choosing the side
and the per-motion turn from the beliefs, waiting without a pose, stopping within the tolerance, and TurnBy's
measured turn ignoring a localizer jump."""

from __future__ import annotations

import math
from types import SimpleNamespace

import pytest

from agent.motion import DynamicParams, MotionController, MotionLibrary, TurnGain
from agent.skills.turn import TurnBy, TurnToFace, predicted_turn_deg, split_turn
from agent.world.frames import Pose2D
from motions import WEBOTS, JointTarget, Keyframe, Motion

CURVE = TurnGain(min_gain=0.05, offset_deg=2.0, span_deg=38.0, predicted_base_deg=2.0, predicted_slope_deg=38.0)


def _controller() -> MotionController:
    pose = Keyframe("Pose1", 0.02, {"hj1": JointTarget(0.0)})
    motions = {name: Motion(name, [pose], source_format=WEBOTS) for name in ("turn_left", "turn_right")}
    return MotionController(MotionLibrary(motions), DynamicParams(turn_gain=CURVE))


def _world(pose: Pose2D | None, yaw_rad: float = 0.0) -> SimpleNamespace:
    return SimpleNamespace(pose=pose, orientation=SimpleNamespace(yaw_rad=yaw_rad))


def test_split_turn_uses_the_fewest_equal_motions():
    assert split_turn(30.0, CURVE) == [30.0]
    assert split_turn(40.0, CURVE) == [40.0]
    assert split_turn(-60.0, CURVE) == [-30.0, -30.0]
    assert split_turn(121.0, CURVE) == pytest.approx([121.0 / 4] * 4)


def test_prediction_follows_the_curve_and_the_sign():
    assert predicted_turn_deg(-25.0, CURVE) == pytest.approx(-25.0)
    assert predicted_turn_deg(1.0, CURVE) == pytest.approx(2.0)  # below one motion's smallest turn


def test_turn_to_face_waits_without_a_pose_then_turns_toward_the_point():
    skill, controller = TurnToFace(0.0, -3.0), _controller()
    assert skill.step(_world(None), controller).motion is None and not skill.done
    request = skill.step(_world(Pose2D(0.0, 0.0, 0.0)), controller)  # the point is 90 deg to the right
    assert request.motion == "turn_right" and request.turn_deg == pytest.approx(30.0)
    assert skill.predicted_deg == pytest.approx(-30.0)


def test_turn_to_face_is_done_within_the_tolerance():
    skill = TurnToFace(3.0, 0.2, tolerance_deg=5.0)
    assert skill.step(_world(Pose2D(0.0, 0.0, 0.0)), _controller()).motion is None
    assert skill.done and skill.motions_played == 0


def test_turn_by_dead_reckoning_plays_the_planned_motions_only():
    skill, dynamic = TurnBy(50.0, tolerance_deg=0.5, use_localization=False), _controller().dynamic
    requests = []
    state = SimpleNamespace(motion_name=None, dynamic=dynamic)
    for _ in range(6):
        request = skill.step(_world(None), state)
        if request.motion is not None:
            requests.append((request.motion, request.turn_deg))
            state = SimpleNamespace(motion_name=request.motion, dynamic=dynamic)  # it plays one cycle ...
            skill.step(_world(None), state)
            state = SimpleNamespace(motion_name=None, dynamic=dynamic)  # ... and ends
    assert requests == [("turn_left", 25.0), ("turn_left", 25.0)] and skill.done


def test_turn_by_counts_the_gyro_across_a_localizer_jump():
    skill, controller = TurnBy(90.0), _controller()
    skill.step(_world(Pose2D(0.0, 0.0, 0.0), 0.0), controller)
    skill.step(_world(Pose2D(0.0, 0.0, math.radians(20.0)), math.radians(20.0)), controller)  # a real turn
    skill.step(_world(Pose2D(5.0, 1.0, math.radians(80.0)), math.radians(22.0)), controller)  # relocalized
    skill.step(_world(None, math.radians(30.0)), controller)  # pose lost: the gyro goes on
    assert skill.measured_deg == pytest.approx(30.0)


def test_a_turn_waits_for_the_controller_to_leave_another_motion():
    """While the controller still plays another motion, the pending turn is asked for again, not re-planned
    (no extra motions counted, no extra predicted turn)."""
    skill, controller = TurnBy(30.0, use_localization=False), _controller()
    busy = SimpleNamespace(motion_name="walk_forward", dynamic=controller.dynamic)
    first = skill.step(_world(None), busy)
    for _ in range(10):
        assert skill.step(_world(None), busy) == first
    assert skill.motions_played == 1 and skill.predicted_deg == pytest.approx(30.0)
    playing = SimpleNamespace(motion_name="turn_left", dynamic=controller.dynamic)
    assert skill.step(_world(None), playing) == first
    idle = SimpleNamespace(motion_name=None, dynamic=controller.dynamic)
    assert skill.step(_world(None), idle).motion is None and skill.done
