"""Motion controller on our simulator: the agent's controller, driving joints only by velocity through the
protocol bytes, reaches each keyframe's angles within 2 degrees (issue requirement), with the server's
action delay and motor limits in the loop."""

from __future__ import annotations

import math

from agent.motion import DynamicParams, MotionController, MotionLibrary
from agent.skills.base import PlayMotion
from motion_studio.scenarios import Scenario
from motions import XML, JointTarget, Keyframe, Motion

# A crouch, an arm raise and a deeper crouch with a head turn (SimSpark degrees; hip + ankle = -knee keeps
# the feet flat under a vertical torso).
PHASES = [
    ("crouch", 600, {"llj3": 30.0, "rlj3": 30.0, "llj4": -60.0, "rlj4": -60.0, "llj5": 30.0, "rlj5": 30.0}),
    ("arms", 400, {"laj1": -60.0, "raj1": -30.0, "laj2": 20.0, "raj2": -20.0}),
    ("deeper", 800, {"llj3": 45.0, "rlj3": 45.0, "llj4": -90.0, "rlj4": -90.0, "llj5": 45.0, "rlj5": 45.0,
                     "hj1": 40.0}),
]


def bob_motion() -> Motion:
    keyframes = []
    for i, (name, duration_ms, targets) in enumerate(PHASES):
        following = PHASES[i + 1][0] if i + 1 < len(PHASES) else None
        keyframes.append(Keyframe(name, duration_ms / 1000.0,
                                  {wire: JointTarget.from_deg(deg) for wire, deg in targets.items()},
                                  next=following, is_final=following is None))
    return Motion("bob", keyframes, source_format=XML, first_phase=PHASES[0][0])


def test_the_controller_reaches_every_keyframe_within_two_degrees_on_the_simulator():
    controller = MotionController(MotionLibrary({"bob": bob_motion()}), DynamicParams())
    scenario = Scenario(PlayMotion("bob"), controller=controller, recover_falls=False)
    world = scenario.agent.world
    reached: dict[str, dict[str, float]] = {}
    phase_ends = {}
    time_s = 0.0
    for name, duration_ms, targets in PHASES:
        time_s += duration_ms / 1000.0
        phase_ends[name] = time_s
    start_s = None
    for _ in range(200):
        scenario.run(1)
        if start_s is None and controller.motion_name == "bob":
            start_s = world.now_s - 0.02  # the first command was sent in the previous cycle's reply
        if start_s is None:
            continue
        elapsed = world.now_s - start_s
        for name, end_s in phase_ends.items():
            # The HJ perceptor shows a command two cycles after it was sent (REFERENCE §3.9).
            if name not in reached and elapsed >= end_s + 0.04 - 1e-9:
                reached[name] = {wire: math.degrees(world.body.joints_rad[wire]) for wire in world.body.joints_rad}
        if len(reached) == len(PHASES):
            break
    assert set(reached) == {name for name, _, _ in PHASES}
    for name, _, targets in PHASES:
        # The phase's own joints; unlisted joints get velocity 0 (REFERENCE §6) and may sag under load.
        errors = {wire: abs(reached[name][wire] - target) for wire, target in targets.items()}
        worst = max(errors, key=errors.get)
        assert errors[worst] <= 2.0, f"phase {name}: {worst} off by {errors[worst]:.2f} deg ({errors})"
    assert not scenario.history[-1].fallen
