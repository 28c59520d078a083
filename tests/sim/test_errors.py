"""sim's errors derive from the toolkit's base and say which agent or which cycle (issue 16 item 7)."""

from __future__ import annotations

import pytest

from kinematics import ToolkitError
from sim.engine import SimEngine
from sim.errors import RuleError, SimError, UnknownRobotError, WorldError
from sim.referee import Referee


def test_world_errors_name_the_agent():
    engine = SimEngine(seed=0)
    engine.world.add_robot(3, 0)
    with pytest.raises(WorldError, match=r"^agent 3: robot key already in the world") as caught:
        engine.world.add_robot(3, 0)
    assert isinstance(caught.value, ToolkitError) and isinstance(caught.value, ValueError)
    assert caught.value.agent == 3
    with pytest.raises(UnknownRobotError, match="no robot left 9") as missing:
        engine.world.robot_of("left", 9)
    assert isinstance(missing.value, KeyError) and isinstance(missing.value, SimError)


def test_referee_errors_name_the_cycle():
    referee = Referee(seed=0)
    referee.cycle = 42
    with pytest.raises(RuleError, match=r"^cycle 42: unknown play mode 'Halftime'; known: BeforeKickOff"):
        referee.set_play_mode("Halftime")
