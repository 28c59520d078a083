"""Walk-skill steering, unit level (no simulator): the shipped forward walk played by the motion controller on
an ideal plant; a skill that leaves a leaning walk straightens it first (a full lean dropped to 0 mid-stride
and then stopped toppled a robot in a match)."""

from __future__ import annotations

import math

from agent.motion import MotionController, MotionRequest, default_library, load_dynamic_params
from agent.protocol.constants import CYCLE_S
from agent.skills.walk import FORWARD, WalkConfig, _Steer


def _controller_in_the_cycle(lean: float) -> tuple[MotionController, dict[str, float]]:
    controller = MotionController(default_library(0), load_dynamic_params())
    angles = {j.perceptor: 0.0 for j in controller.joints}
    for _ in range(300):
        controller.request(MotionRequest(FORWARD, lean=lean))
        for effector, omega in controller.update(angles).items():
            wire = effector.replace("e", "j", 1)
            angles[wire] += math.degrees(omega) * 0.02
        if (controller.phase_name or "").startswith("cycle"):
            break
    assert (controller.phase_name or "").startswith("cycle")
    return controller, angles


def test_leaving_a_leaning_walk_straightens_it_first_at_the_lean_rate():
    config = WalkConfig()
    controller, angles = _controller_in_the_cycle(lean=-1.0)
    steer = _Steer(config)
    leans = []
    for _ in range(60):
        request = steer.guard(controller, MotionRequest("turn_right", turn_deg=40.0))
        controller.request(request)
        for effector, omega in controller.update(angles).items():
            angles[effector.replace("e", "j", 1)] += math.degrees(omega) * 0.02
        if request.motion != FORWARD:
            break
        leans.append(request.lean)
    assert leans[0] == -1.0 + config.lean_rate_per_s * 0.02  # continued from the walk's own lean, not from 0
    assert all(b > a for a, b in zip(leans, leans[1:]))  # straightened step by step
    assert abs(leans[-1]) <= config.lean_release + config.lean_rate_per_s * 0.02
    assert request.motion == "turn_right"  # then the turn goes through


def test_a_straight_walk_is_left_at_once():
    controller, _ = _controller_in_the_cycle(lean=0.0)
    request = _Steer(WalkConfig()).guard(controller, MotionRequest(None))
    assert request.motion is None


class _Played:
    """The part of a motion controller a chained turn reads: how often each motion completed."""

    def __init__(self) -> None:
        self.completed = {"turn_left": 0, "turn_right": 0, "stand": 0}
        self.library = {"turn_left", "turn_right", "stand"}


def _after_one_turn_motion(planned_deg: float, bearing_deg: float | None):
    """A chained turn of ``planned_deg`` started, its first turn motion played; the request that follows."""
    steer, played = _Steer(WalkConfig()), _Played()
    steer.turn(played, planned_deg)
    played.completed[steer.turning] += 1
    return steer.turn_step(played, bearing_deg)


def test_a_chained_turn_goes_on_as_planned_without_a_fresh_bearing():
    request = _after_one_turn_motion(150.0, None)
    assert request.motion == "turn_left" and request.turn_deg == 150.0 - WalkConfig().turn_motion_deg


def test_a_chained_turn_ends_when_the_target_now_lies_the_other_way():
    """Planned on a stale sighting (the ball at the centre behind the robot) and turned once, the target is now
    ahead and to the right: no more left turns (before: three more, 3.5 s, then back; ours, kick-off, seed 3)."""
    assert _after_one_turn_motion(150.0, -10.0).motion == "stand"
    assert _after_one_turn_motion(-150.0, 20.0).motion == "stand"


def test_a_chained_turn_keeps_its_plan_unless_the_target_moved_well_short_of_it():
    rest = 150.0 - WalkConfig().turn_motion_deg   # 112 deg still to turn as planned
    assert _after_one_turn_motion(150.0, 50.0).turn_deg == 50.0   # 62 deg short: the target moved
    assert _after_one_turn_motion(150.0, 80.0).turn_deg == rest   # 32 deg short: the plan (the pose lags)
    # the pose may not show the whole turn yet: a bearing beyond the plan's rest keeps the plan
    assert _after_one_turn_motion(-150.0, -170.0).turn_deg == rest
    assert _after_one_turn_motion(150.0, 10.0).motion == "stand"   # within the chain threshold: done


def test_after_a_turn_the_steer_stands_then_settles_then_lets_the_walk_go():
    """turn -> ``stand`` -> ``settle_after_turn_s`` of no motion -> None (the skill walks on). The settle cycles
    no longer look up the completions of "no turn" (a controller stand-in without that key raised KeyError)."""
    steer, played = _Steer(WalkConfig()), _Played()
    steer.turn(played, 30.0)
    played.completed["turn_left"] += 1
    assert steer.turn_step(played).motion == "stand"
    played.completed["stand"] += 1
    settle = [steer.turn_step(played) for _ in range(round(WalkConfig().settle_after_turn_s / CYCLE_S) + 1)]
    assert [r.motion for r in settle[:-1]] == [None] * (len(settle) - 1) and settle[-1] is None
