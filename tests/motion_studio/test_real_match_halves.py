"""The real match's second half (``motion_studio.realserver.match_play.second_half_kick_off``): at half time the
real rcssserver3d 0.7.3 goes back to BeforeKickOff and waits for the monitor's ``(kickOff <side>)``; a 600 s
real match stood still there before this. Pure decision, no server."""

from __future__ import annotations

import pytest

from agent.protocol.constants import CYCLE_S
from motion_studio.realserver.match_play import KICK_OFF_WAIT_S, second_half_kick_off

WAITED = round(KICK_OFF_WAIT_S / CYCLE_S)


@pytest.mark.parametrize("first, second", [("Left", "Right"), ("Right", "Left")])
def test_the_other_side_kicks_off_the_second_half_after_the_wait(first, second):
    assert second_half_kick_off("BeforeKickOff", 300.0, first, WAITED) == second


@pytest.mark.parametrize("play_mode, game_time_s, waited", [
    ("BeforeKickOff", 0.0, WAITED),       # before the first kick-off: the match start sends that one
    ("BeforeKickOff", 300.0, WAITED - 1),  # the robots first get the wait they get before the first half
    ("PlayOn", 310.0, WAITED),            # the second half runs
    ("Goal_Left", 150.0, WAITED)])        # the referee restarts after goals by itself
def test_no_kick_off_is_sent_otherwise(play_mode, game_time_s, waited):
    assert second_half_kick_off(play_mode, game_time_s, "Left", waited) is None
