"""The pure core: connection sequence (scene, init, beam once), syn every cycle, bad input, say slots, purity."""

from __future__ import annotations

import math
import subprocess
import sys
from types import SimpleNamespace

import pytest

from agent import Agent, AgentConfig
from agent.agent import GOAL_BEAM_DELAY_CYCLES
from agent.communication import decode
from agent.communication.messages import encode
from agent.errors import ConfigError
from agent.formation import FORMATIONS, beam_spot
from agent.protocol import ProtocolError, parse_actions
from agent.protocol.effectors import Beam, Init, Say, Scene, Syn
from agent.world.frames import Pose2D
from agent.world.objects import Tracked
from tests.agent import synthetic_world as synth
from tests.agent.protocol_samples import records


def left_sample():
    return [str(r["msg"]).encode() for r in records() if r["k"] == "recv" and r["a"] == "L"]


def run(agent, messages):
    return [parse_actions(agent.step(m)) for m in messages]


def test_connect_message_is_the_hetero_scene():
    agent = Agent(AgentConfig("Mine", 4, robot_type=3))
    assert parse_actions(agent.connect_message()) == [Scene("rsg/agent/nao/nao_hetero.rsg", 3)]


def test_real_sample_init_first_beam_once_syn_always():
    outputs = run(Agent(AgentConfig("CapL", 1)), left_sample())
    assert all(actions[-1] == Syn() for actions in outputs)
    assert outputs[0][0] == Init(1, "CapL")
    beams = [(i, a) for i, actions in enumerate(outputs) for a in actions if isinstance(a, Beam)]
    # One beam, as soon as the server confirmed unum and side (3rd message), to the goalkeeper spot.
    assert [i for i, _ in beams] == [2]
    spot = beam_spot(1)
    assert beams[0][1] == Beam(spot.x_m, spot.y_m, spot.rot_deg)
    assert sum(isinstance(a, Init) for actions in outputs for a in actions) == 1


def _sense(now, mode, unum=None, side=None):
    return synth.sense_bytes(now, play_mode=mode, unum=unum, side=side)


def test_beam_again_after_a_goal_never_in_play_on():
    agent = Agent(AgentConfig("Mine", 7))
    goal = GOAL_BEAM_DELAY_CYCLES + 5
    modes = ["BeforeKickOff"] * 5 + ["KickOff_Left"] * 3 + ["PlayOn"] * 5 + ["Goal_Left"] * goal + ["PlayOn"] * 3
    beams = []
    for i, mode in enumerate(modes):
        actions = parse_actions(agent.step(_sense(1.0 + 0.02 * i, mode, 7 if i == 1 else None,
                                                  "left" if i == 1 else None)))
        beams += [(mode, i) for a in actions if isinstance(a, Beam)]
    assert [mode for mode, _ in beams] == ["BeforeKickOff", "Goal_Left"]
    # after a goal the beam waits for the stance: a robot beamed in mid-stride fell
    first_goal_cycle = 5 + 3 + 5
    assert beams[1][1] == first_goal_cycle + GOAL_BEAM_DELAY_CYCLES
    assert 40 <= GOAL_BEAM_DELAY_CYCLES <= 100  # 0.8-2 s: the walk has stopped, the 3 s goal not yet over


def test_at_half_time_the_beam_waits_for_the_stance_too():
    """The second half starts in BeforeKickOff with the game clock at 300 s; a player walking then was set down
    mid-stride and fell (11 v 11 on ours). At the game's start (clock 0) it beams at once, as before."""
    agent = Agent(AgentConfig("Mine", 7))
    modes = [("BeforeKickOff", 0.0)] * 3 + [("PlayOn", 299.96)] * 3 + [("BeforeKickOff", 300.0)] * 60
    beams = []
    for i, (mode, game_s) in enumerate(modes):
        actions = parse_actions(agent.step(synth.sense_bytes(1.0 + 0.02 * i, play_mode=mode, game_time_s=game_s,
                                                             unum=7 if i == 1 else None,
                                                             side="left" if i == 1 else None)))
        beams += [i for a in actions if isinstance(a, Beam)]
    assert beams == [1, 6 + GOAL_BEAM_DELAY_CYCLES]


@pytest.mark.parametrize(("goal", "inside_allowed"), [("Goal_Left", False), ("Goal_Right", True)])
def test_after_a_goal_the_kick_off_spots_beam_outside_the_circle_when_the_opponents_kick_off(goal, inside_allowed):
    """Unum 2's kick-off spot (-0.5, 0) lies in the centre circle: after our goal (the opponents kick off) the
    agent beams outside it (2.5 m from the centre, off the kick-off line); after theirs, to the spot itself."""
    agent = Agent(AgentConfig("Mine", 2))
    modes = ["BeforeKickOff"] * 3 + ["PlayOn"] * 3 + [goal] * (GOAL_BEAM_DELAY_CYCLES + 3)
    beams = []
    for i, mode in enumerate(modes):
        actions = parse_actions(agent.step(_sense(1.0 + 0.02 * i, mode, 2 if i == 1 else None,
                                                  "left" if i == 1 else None)))
        beams += [a for a in actions if isinstance(a, Beam)]
    spot = beam_spot(2)
    assert beams[0] == Beam(spot.x_m, spot.y_m, spot.rot_deg)
    after = beams[1]
    if inside_allowed:
        assert after == beams[0]
    else:
        assert math.hypot(after.x_m, after.y_m) == pytest.approx(2.5, abs=0.01)  # beam text: 2 decimals
        assert after.x_m < 0.0 and abs(after.y_m) >= 1.2


@pytest.mark.parametrize("unum", range(2, 12))
def test_kick_off_spots_obey_the_rules(unum):
    """Every spot near the centre becomes legal: own half, and at the opponents' kick-off outside the circle and
    beside the kick-off line; spots far from the centre keep their place."""
    from agent.formation import kick_off_spot

    for x, y in [(-0.5, 0.0), (1.0, 0.3), (-1.2, 1.0), (-2.6, -2.0), (-8.0, 3.0), (3.0, -4.0)]:
        ours = kick_off_spot(x, y, unum, opponents_kick_off=False)
        assert ours == (min(x, -0.4), y)
        theirs = kick_off_spot(x, y, unum, opponents_kick_off=True)
        assert theirs[0] <= -0.4 and math.hypot(*theirs) >= 2.5 - 1e-9
        if math.hypot(min(x, -0.4), y) < 4.0:
            assert abs(theirs[1]) >= 1.2 - 1e-9 and (theirs[1] > 0) == (unum % 2 == 0)
        else:
            assert theirs == (min(x, -0.4), y)


def test_malformed_message_raises_and_changes_nothing():
    agent = Agent(AgentConfig("Mine", 2))
    agent.step(_sense(1.0, "BeforeKickOff", 2, "left"))
    before = (agent.world.game.cycles, agent.world.now_s)
    with pytest.raises(ProtocolError):
        agent.step(b"(time (now 1.02))(GS (t 0.00) (pm PlayOn)")
    assert (agent.world.game.cycles, agent.world.now_s) == before
    assert parse_actions(agent.step(_sense(1.04, "BeforeKickOff")))[-1] == Syn()


def test_step_is_a_pure_function_of_the_messages():
    messages = left_sample()
    a, b = Agent(AgentConfig("CapL", 1)), Agent(AgentConfig("CapL", 1))
    outputs = [a.step(m) for m in messages]
    assert outputs == [b.step(m) for m in messages]
    assert len(set(outputs)) > 3  # not trivially constant


def test_says_only_in_its_own_slot_and_decodably():
    agent = Agent(AgentConfig("Mine", 4))
    said = []
    for i in range(80):
        actions = parse_actions(agent.step(_sense(30.0 + 0.02 * i, "BeforeKickOff", 4 if i == 0 else None,
                                                  "left" if i == 0 else None)))
        said += [(i, a.message) for a in actions if isinstance(a, Say)]
    assert said, "unum 4 has a slot every 33 cycles"
    cycles = [i for i, _ in said]
    assert all(b - a == 33 for a, b in zip(cycles, cycles[1:]))
    assert decode(said[0][1], "Mine").kind == "i"
    assert decode(said[1][1], "Mine").kind == "x"  # no vision in these messages: lost


def test_config_errors_name_the_option():
    for kwargs, field in [({"unum": 12}, "unum"), ({"robot_type": 5}, "type"), ({"team": "a b"}, "team"),
                          ({"localization": "magic"}, "localization")]:
        with pytest.raises(ConfigError) as info:
            AgentConfig(**{"team": "Mine", **kwargs})
        assert info.value.field == field
    with pytest.raises(ConfigError, match="thesis"):
        beam_spot(3, "diamond")


@pytest.mark.parametrize("unum", range(1, 12))
def test_every_beam_spot_is_legal(unum):
    spot = FORMATIONS["thesis"][unum]
    assert -15.0 <= spot.x_m <= 0.0 and -10.0 <= spot.y_m <= 10.0
    assert math.hypot(spot.x_m, spot.y_m) > 2.0  # outside the centre circle at kick-off


def test_agent_imports_no_mujoco():
    code = \
        "import sys, agent, agent.runner\nprint('mujoco' in sys.modules)"
    result = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert result.returncode == 0, result.stderr
    assert result.stdout.strip() == "False"


def test_play_mode_change_restarts_the_slots_at_label_1():
    agent = Agent(AgentConfig("Mine", 1))
    said = []
    modes = ["BeforeKickOff"] * 10 + ["KickOff_Left"] * 40
    for i, mode in enumerate(modes):
        # Server time 7.00 + odd offset, so the old clock's slots and the new one's do not line up.
        actions = parse_actions(agent.step(synth.sense_bytes(7.02 + 0.02 * i, play_mode=mode,
                                                             unum=1 if i == 0 else None,
                                                             side="left" if i == 0 else None)))
        said += [i for a in actions if isinstance(a, Say)]
    assert 10 in said  # the cycle the mode changed opens slot 1
    assert 10 + 33 in said and all(i == 10 or i == 43 or i < 10 for i in said)



@pytest.mark.parametrize("ball_m, localized, kind", [((53.85, 2.0), True, "l"), ((12.0, 2.0), True, "c"),
                                                    ((80.0, 2.0), False, "x"), ((12.0, 2.0), False, "b")])
def test_a_ball_believed_far_off_the_field_is_not_told(ball_m, localized, kind):
    """A robot trying to stand up from its side once believed the ball 53.85 m away: beyond what a message carries
    (±38.72 m), so the encoder raised and the agent's step ended in an error. Such a ball is left out."""
    agent = Agent(AgentConfig("Mine", 4))
    agent.compose_message()  # the hello
    if localized:
        agent.world.localizer = SimpleNamespace(pose=Pose2D(-5.0, 0.0, 0.0), localized=True)
    agent.world.ball = Tracked(ball_m[0], ball_m[1], ball_m[0], ball_m[1], agent.world.now_s)
    message = agent.compose_message()
    assert message.kind == kind
    assert decode(encode(message, "Mine"), "Mine").kind == kind
