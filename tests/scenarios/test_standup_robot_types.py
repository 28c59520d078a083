"""The other robot types our team fields (agent.team.composition: 0, 2, 4) stand up on our simulator too:
type 4 with its own stand-ups (motions/files/type4/), type 2 with type 0's."""

from __future__ import annotations

import pytest

from agent.skills.base import PlayMotion
from motion_studio.scenarios import Scenario, Truth

LIMIT_S = 8.0
HOLD_CYCLES = 25


def _standing(scenario: Scenario, truth: Truth) -> bool:
    feet = scenario.world.foot_forces(scenario.key)
    loaded = sum(force[2] for _, force in feet.values()) if feet else 0.0
    return truth.torso_m[2] > 0.28 and truth.up_z > 0.85 and loaded > 30.0


@pytest.mark.parametrize("robot_type", [2, 4])
@pytest.mark.parametrize("side,yaw_deg", [("back", 30.0), ("front", -120.0)])
def test_a_robot_of_our_other_types_laid_down_stands_up(robot_type, side, yaw_deg):
    scenario = Scenario(PlayMotion("stand"), seed=1, robot_type=robot_type)
    scenario.run(25)
    scenario.lay_down(side, yaw_deg)
    assert all(t.fallen for t in scenario.run(10))
    run = 0
    for _ in range(round(LIMIT_S / 0.02)):
        truth = scenario.run(1)[0]
        run = run + 1 if _standing(scenario, truth) else 0
        if run >= HOLD_CYCLES:
            break
    assert run >= HOLD_CYCLES, f"type {robot_type} still not standing {LIMIT_S} s after the lay-down on its {side}"
    assert not any(t.fallen for t in scenario.run(25))
