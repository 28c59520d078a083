"""The real match's second half (``motion_studio.realserver.match_play.second_half_kick_off``): at half time the
real rcssserver3d 0.7.3 goes back to BeforeKickOff and waits for the monitor's ``(kickOff <side>)``; a 600 s
real match stood still there before this. Pure decision, no server."""

from __future__ import annotations

import pytest

from agent.protocol.constants import CYCLE_S
from motion_studio.realserver.match_play import (KICK_OFF_RESEND_S, KICK_OFF_RESENDS, KICK_OFF_WAIT_S, kick_off_lost,
                                                 second_half_kick_off)

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


RESEND = round(KICK_OFF_RESEND_S / CYCLE_S)


def test_a_first_kick_off_the_server_did_not_take_is_sent_again():
    """Once the real server never left BeforeKickOff (its monitor connection backed up): the harness sends the
    kick-off again while the game time stays 0, a few times at most."""
    assert kick_off_lost("BeforeKickOff", 0.0, RESEND, 0)
    assert kick_off_lost("BeforeKickOff", 0.0, RESEND, KICK_OFF_RESENDS - 1)
    assert not kick_off_lost("BeforeKickOff", 0.0, RESEND, KICK_OFF_RESENDS)


@pytest.mark.parametrize("play_mode, game_time_s, since", [
    ("BeforeKickOff", 0.0, RESEND - 1),   # the server may still be about to take it
    ("KickOff_Left", 0.0, RESEND),        # taken (a kickOff now would restart the kick-off)
    ("PlayOn", 12.0, RESEND),
    ("BeforeKickOff", 300.0, RESEND)])    # half time: second_half_kick_off's business
def test_a_kick_off_is_not_sent_again_otherwise(play_mode, game_time_s, since):
    assert not kick_off_lost(play_mode, game_time_s, since, 0)
