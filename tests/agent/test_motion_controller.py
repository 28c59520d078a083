"""Motion controller, unit level: phases built in the test, played against an ideal joint plant that has the
server's action delay (a reply to message k acts in the step after the one already running, REFERENCE §3.9)."""

from __future__ import annotations

import math

import pytest

from agent.motion import (ControllerConfig, DynamicParams, MotionController, MotionLibrary, MotionRequest, Slowdown,
                          WalkLean, WebotsTiming)
from agent.motion.dynamic import KickDistance
from motions import WEBOTS, XML, JointTarget, Keyframe, Motion

DT = 0.02


def phase(name, duration_ms, targets_deg=None, **attributes):
    targets = {wire: JointTarget.from_deg(value) if not isinstance(value, JointTarget) else value
               for wire, value in (targets_deg or {}).items()}
    return Keyframe(name, duration_ms / 1000.0, targets, **attributes)


def xml_motion(name, phases, **kwargs):
    return Motion(name, phases, source_format=XML, first_phase=phases[0].name, **kwargs)


class Plant:
    """Ideal joints: velocities persist, the reply to message k acts during step k+1 (seen in message k+2)."""

    def __init__(self, controller, angles_deg=None):
        self.controller = controller
        self.q = {j.perceptor: 0.0 for j in controller.joints}
        self.q.update({k: math.radians(v) for k, v in (angles_deg or {}).items()})
        self.velocity = {j.perceptor: 0.0 for j in controller.joints}
        self.wire = {j.effector: j.perceptor for j in controller.joints}
        self.pending = {}
        self.replies = []

    def cycle(self, request=None):
        for effector, value in self.pending.items():
            self.velocity[self.wire[effector]] = value
        message = {k: round(math.degrees(v), 2) for k, v in self.q.items()}
        for k in self.q:
            self.q[k] += self.velocity[k] * DT
        if request is not None:
            self.controller.request(request)
        self.pending = self.controller.update(message)
        self.replies.append(self.pending)
        return self.pending

    def deg(self, wire):
        return math.degrees(self.q[wire])


def controller_for(*motions, dynamic=None, **library_settings):
    library = MotionLibrary({m.name: m for m in motions})
    for key, value in library_settings.items():
        getattr(library, key).update(value)
    # Blending off unless a test is about it: the targets here are far for their short phases.
    return MotionController(library, dynamic or DynamicParams(), config=ControllerConfig(blend_speed_rad_s=1e3))


def test_a_phase_reaches_its_targets_at_its_end_despite_the_action_delay():
    motion = xml_motion("m", [phase("a", 200, {"llj3": 30.0, "rlj4": -40.0})])
    plant = Plant(controller_for(motion))
    for _ in range(10):
        plant.cycle("m")
    # The 10th reply acts during the 11th step: after it (two more plant steps) the targets are reached.
    plant.cycle(None)
    plant.cycle(None)
    assert plant.deg("llj3") == pytest.approx(30.0, abs=0.05)
    assert plant.deg("rlj4") == pytest.approx(-40.0, abs=0.05)
    assert plant.controller.completed["m"] == 1


def test_velocity_is_the_remaining_distance_over_the_remaining_time():
    motion = xml_motion("m", [phase("a", 100, {"llj3": 10.0})])
    controller = controller_for(motion)
    controller.request("m")
    out = controller.update({"llj3": 0.0})
    assert out["lle3"] == pytest.approx(math.radians(10.0) / 0.1)
    # Next cycle: the previous command is still in flight for one cycle, so the start angle is predicted.
    out2 = controller.update({"llj3": 0.0})
    predicted = out["lle3"] * DT
    assert out2["lle3"] == pytest.approx((math.radians(10.0) - predicted) / 0.08)


def test_unlisted_joints_hold_and_an_empty_phase_holds_everything():
    motion = xml_motion("m", [phase("a", 40, {"llj3": 10.0}, next="b"), phase("b", 40, {})])
    controller = controller_for(motion)
    controller.request("m")
    out = controller.update({j.perceptor: 5.0 for j in controller.joints})
    assert out["lle3"] != 0.0
    assert all(value == 0.0 for effector, value in out.items() if effector != "lle3")
    controller.update({j.perceptor: 5.0 for j in controller.joints})
    out = controller.update({j.perceptor: 5.0 for j in controller.joints})
    assert controller.phase_name == "b"
    assert all(value == 0.0 for value in out.values())


def play(controller, request, cycles, angles=None):
    names = []
    for _ in range(cycles):
        controller.request(request)
        controller.update(angles or {"llj3": 0.0})
        names.append(controller.phase_name)
    return names


def test_next_loops_while_requested_and_finalize_leaves_when_another_motion_is_requested():
    walk = xml_motion("walk", [
        phase("w1", 40, {"llj3": 10}, next="w2"),
        phase("w2", 40, {"llj3": 20}, next="w1", finalize="stop"),
        phase("stop", 40, {"llj3": 0}, next="stop2"),
        phase("stop2", 40, {"llj3": 5})])
    other = xml_motion("other", [phase("o1", 40, {"llj3": 5})])
    controller = controller_for(walk, other)
    assert play(controller, "walk", 9) == ["w1", "w1", "w2", "w2"] * 2 + ["w1"]
    # Another motion requested during w1: w1 goes on to w2 (it has no finalize), w2 leaves through its
    # finalize, and the stop chain follows its own next links to its end before the new motion starts.
    names = play(controller, "other", 9)
    assert names == ["w1", "w2", "w2", "stop", "stop", "stop2", "stop2", "o1", "o1"]
    assert controller.completed["walk"] == 1
    assert controller.completed["other"] == 1


def test_finalize_naming_the_phase_itself_ends_the_motion_there():
    motion = xml_motion("m", [phase("a", 40, {"llj3": 10}, next="b", finalize="a"), phase("b", 40, {"llj3": 20})])
    other = xml_motion("o", [phase("o1", 40, {"llj3": 5})])
    controller = controller_for(motion, other)
    play(controller, "m", 1)
    assert play(controller, "o", 3) == ["a", "o1", "o1"]


def test_is_final_without_finalize_ends_the_motion_when_another_is_requested():
    motion = xml_motion("m", [phase("a", 40, {"llj3": 10}, next="b", is_final=True), phase("b", 40, {"llj3": 20})])
    other = xml_motion("o", [phase("o1", 40, {"llj3": 5})])
    controller = controller_for(motion, other)
    play(controller, "m", 1)
    assert play(controller, "o", 3) == ["a", "o1", "o1"]
    # While the same motion stays requested, isFinal does not end it.
    controller = controller_for(motion, other)
    assert play(controller, "m", 4) == ["a", "a", "b", "b"]


def test_skip_if_flag_and_set_flags():
    walk = xml_motion("walk", [
        phase("stance", 40, {"llj3": 30}, next="step", skip_if_flag="ready"),
        phase("step", 40, {"llj3": 40}, next="rest", set_flag_false="ready"),
        phase("rest", 40, {"llj3": 30}, set_flag_true="ready")])
    controller = controller_for(walk)
    assert play(controller, "walk", 6) == ["stance", "stance", "step", "step", "rest", "rest"]
    assert controller.flags["ready"] is True
    play(controller, None, 1)
    # The flag is set: the stance phase is skipped on the next start; "step" clears it.
    assert play(controller, "walk", 2) == ["step", "step"]
    assert controller.flags["ready"] is False


def test_computed_values_walk_lean_and_named_values():
    # One-cycle phases with small angles, so no velocity reaches the joints' speed limit (6.14 rad/s).
    lean_target = JointTarget.from_deg(1.0, "left_walk_lean_lle3")
    head_target = JointTarget.from_deg(0.0, "headAngle1")
    motion = xml_motion("walk", [phase("a", 20, {"llj3": lean_target, "hj1": head_target}, next="a")],
                        constants={"speed_m_s": 0.3})
    dynamic = DynamicParams(walk_lean=WalkLean({"le3": 4.0}))
    controller = controller_for(motion, dynamic=dynamic)
    zero = {"llj3": 0.0, "hj1": 0.0}
    controller.request(MotionRequest("walk", lean=1.0))
    out = controller.update(zero)
    assert out["lle3"] == pytest.approx(math.radians(5.0) / DT)
    assert out["he1"] == 0.0  # no value known: the end fallback (0)
    controller.computed_deg["headAngle1"] = 3.0
    controller.request(MotionRequest("walk", lean=-1.0))  # a right lean leaves the left values alone
    out = controller.update(zero)
    assert out["lle3"] == pytest.approx((math.radians(1.0) - math.radians(5.0)) / DT)
    assert out["he1"] == pytest.approx(math.radians(3.0) / DT)


def test_velocities_are_clamped_to_the_joint_speed_limit():
    motion = xml_motion("m", [phase("a", 20, {"llj3": 28.0})])
    controller = controller_for(motion)
    controller.request("m")
    out = controller.update({"llj3": 0.0})
    assert out["lle3"] == pytest.approx(math.radians(351.77), rel=1e-3)


def webots_motion(name, poses):
    keyframes = [Keyframe(f"Pose{i + 1}", 0.04 if i else 0.0,
                          {wire: JointTarget(None if v is None else math.radians(v)) for wire, v in pose.items()})
                 for i, pose in enumerate(poses)]
    return Motion(name, keyframes, source_format=WEBOTS, joint_order=tuple(poses[0]))


def test_webots_duration_pose_step_and_uncommanded_joints():
    poses = [{"llj3": 10.0 * i, "rlj3": None if i == 2 else 0.0} for i in range(5)]
    motion = webots_motion("w", poses)
    controller = controller_for(motion, webots_timing={"w": WebotsTiming(duration_cycles=3, pose_step=2)})
    names, outputs = [], []
    for _ in range(9):
        controller.request("w")
        outputs.append(controller.update({"llj3": 0.0, "rlj3": 0.0}))
        names.append(controller.phase_name)
    assert names == ["Pose1"] * 3 + ["Pose3"] * 3 + ["Pose5"] * 3
    assert "rle3" not in outputs[3]  # Pose3 has '*' for rlj3: not commanded
    assert "rle3" in outputs[0]
    assert controller.completed["w"] == 1


def test_turn_gain_scales_the_deviation_from_the_base_motion():
    turn = webots_motion("turn", [{"llj1": 0.0}, {"llj1": -40.0}])
    base = webots_motion("base", [{"llj1": 0.0}, {"llj1": -10.0}])
    controller = controller_for(turn, base, gain_bases={"turn": "base"},
                                webots_timing={"turn": WebotsTiming(duration_cycles=10)})
    controller.request(MotionRequest("turn", gain=0.5))
    for _ in range(10):
        controller.update({"llj1": 0.0}, None)
    controller._last_command["llj1"] = 0.0  # measure the next command from a known start
    out = controller.update({"llj1": 0.0})
    assert out["lle1"] == pytest.approx(math.radians(-25.0) / (10 * DT), rel=1e-6)  # -10 + 0.5 * (-40 - -10)


def test_slowdown_stretches_walk_phases_after_a_stop_request():
    walk = xml_motion("walk", [phase("w", 40, {"llj3": 10}, next="w", finalize="s"),
                               phase("s", 100, {"llj3": 0})], constants={"speed_m_s": 0.4})
    controller = controller_for(walk, dynamic=DynamicParams(slowdown=Slowdown(stretch=0.4)))
    play(controller, "walk", 2)
    names = play(controller, None, 10)
    assert names.count("s") == 7  # 100 ms x 1.4 = 7 cycles


def test_targets_stay_inside_the_joint_limits():
    motion = xml_motion("m", [phase("a", 20, {"llj1": 5.0})])  # LHipYawPitch max is 1 deg
    controller = controller_for(motion)
    controller.request("m")
    out = controller.update({"llj1": 0.0})
    assert math.degrees(out["lle1"] * DT) == pytest.approx(0.5, abs=1e-9)


def test_blending_stretches_a_far_first_keyframe():
    motion = xml_motion("m", [phase("a", 20, {"llj3": 60.0})])
    controller = MotionController(MotionLibrary({"m": motion}), config=ControllerConfig(blend_speed_rad_s=1.0))
    names = play(controller, "m", 1) + play(controller, None, 99)
    cycles = len([n for n in names if n == "a"])
    assert cycles == math.ceil(math.radians(60.0) / 1.0 / DT)


def test_a_motion_s_blend_speed_constant_replaces_the_controller_s_bound():
    # The stand-ups carry blend_speed_rad_s = 6 (a robot lying still can move its limbs at full speed); every
    # other motion keeps the controller's bound.
    fast = xml_motion("up", [phase("a", 20, {"llj3": 60.0})], constants={"blend_speed_rad_s": 4.0})
    slow = xml_motion("m", [phase("a", 20, {"llj3": 60.0})])
    for motion, speed in ((fast, 4.0), (slow, 1.0)):
        controller = MotionController(MotionLibrary({motion.name: motion}),
                                      config=ControllerConfig(blend_speed_rad_s=1.0))
        names = play(controller, motion.name, 1) + play(controller, None, 99)
        assert names.count("a") == math.ceil(math.radians(60.0) / speed / DT), motion.name


def test_a_head_the_request_steers_does_not_stretch_the_blend():
    # A turn motion lists the head at 0 deg; a dribbler looking 60 deg aside at the ball keeps looking there
    # (the request's head_deg wins), so only the legs' move sets the first keyframe's length.
    motion = xml_motion("turn", [phase("a", 20, {"llj3": 6.0, "hj1": 0.0})])
    angles = {"llj3": 0.0, "hj1": 60.0}
    for head_deg, cycles in (((60.0, 0.0), math.ceil(math.radians(6.0) / 1.0 / DT)),
                             (None, math.ceil(math.radians(60.0) / 1.0 / DT))):
        controller = MotionController(MotionLibrary({"turn": motion}), config=ControllerConfig(blend_speed_rad_s=1.0))
        request = MotionRequest("turn", head_deg=head_deg)
        names = play(controller, request, 1, angles) + play(controller, MotionRequest(None, head_deg=head_deg), 99,
                                                             angles)
        assert names.count("a") == cycles, head_deg


def test_unknown_motion_names_the_known_ones():
    controller = controller_for(xml_motion("walk", [phase("a", 20, {})]))
    with pytest.raises(KeyError, match="walk"):
        controller.request("kick")


def test_last_request_is_the_request_posted_last():
    from agent.motion import MotionController, MotionLibrary, MotionRequest

    controller = MotionController(MotionLibrary())
    assert controller.last_request == MotionRequest(None)
    controller.request(MotionRequest(None, lean=0.5))
    assert controller.last_request.lean == 0.5


def test_a_kick_distance_request_stretches_only_the_named_phases_of_the_named_kicks():
    def kick(name):
        return xml_motion(name, [phase("windup", 60, {"llj3": 10}, next="swing"),
                                 phase("swing", 40, {"llj3": 20}, next="strike"),
                                 phase("strike", 60, {"llj3": 30}, next="land"),
                                 phase("land", 40, {"llj3": 0})])

    table = KickDistance(motions=("kick",), distance_points_m=(1.0, 4.0), stretch=(2.0, 1.0))
    controller = controller_for(kick("kick"), kick("other"), dynamic=DynamicParams(kick_distance=table))
    short = play(controller, MotionRequest("kick", distance_m=1.2), 15) + play(controller, None, 1)
    assert short == ["windup"] * 3 + ["swing"] * 4 + ["strike"] * 6 + ["land"] * 2 + [None]
    full = play(controller, MotionRequest("kick", distance_m=3.5), 10) + play(controller, None, 1)
    assert full == ["windup"] * 3 + ["swing"] * 2 + ["strike"] * 3 + ["land"] * 2 + [None]  # nearest row: 4 m
    assert play(controller, MotionRequest("kick"), 10) + play(controller, None, 1) == full
    other = play(controller, MotionRequest("other", distance_m=1.2), 10) + play(controller, None, 1)
    assert other == full  # not one of the table's motions
