"""Sense messages: typed values per perceptor (REFERENCE §3.4 examples), byte round trips over the real
sample, the fast and general parsing paths agreeing, located errors, and server-order formatting."""

from __future__ import annotations

import dataclasses

import pytest

from agent.protocol.errors import ProtocolError
from agent.protocol.perceptors import (
    Accelerometer,
    AgentState,
    ForceResistance,
    GameState,
    Gyro,
    Hear,
    Polar,
    See,
    Sense,
    TimePerceptor,
    VisibleLine,
    VisibleObject,
    VisiblePlayer,
)
from agent.protocol.sense import format_sense, parse_sense
from tests.agent.protocol_samples import received, vision_message

BOTH_PATHS = pytest.mark.parametrize("fast_path", [True, False], ids=["fast", "general"])


def parse_both(message: bytes) -> Sense:
    """Parse with both paths, check they agree (values and order), return the result."""
    fast, general = parse_sense(message), parse_sense(message, fast_path=False)
    assert fast == general
    assert fast.order == general.order
    assert (fast.see and fast.see.order) == (general.see and general.see.order)
    return fast


# --- One literal message per perceptor (REFERENCE §3.4) ------------------------------------------------
def test_time() -> None:
    sense = parse_both(b"(time (now 104.36))")
    assert sense.time == TimePerceptor(now_s=104.36)
    assert sense.order == ("time",)


def test_game_state_with_and_without_the_init_fields() -> None:
    first = parse_both(b"(GS (unum 3) (team right) (sl 0) (sr 0) (t 0.00) (pm BeforeKickOff))")
    assert first.game_state == GameState(3, "right", 0, 0, 0.0, "BeforeKickOff")
    later = parse_both(b"(GS (sl 1) (sr 0) (t 41.22) (pm PlayOn))")
    assert later.game_state == GameState(None, None, 1, 0, 41.22, "PlayOn")


def test_game_state_without_scores() -> None:
    message = b"(GS (t 12.00) (pm PlayOn))"
    sense = parse_both(message)
    assert sense.game_state == GameState(None, None, None, None, 12.0, "PlayOn")
    assert format_sense(sense) == message


def test_gyro() -> None:
    sense = parse_both(b"(GYR (n torso) (rt 0.57 -12.40 3.06))")
    assert sense.gyro == Gyro("torso", (0.57, -12.40, 3.06))


def test_accelerometer() -> None:
    sense = parse_both(b"(ACC (n torso) (a 0.12 -0.33 9.79))")
    assert sense.acc == Accelerometer("torso", (0.12, -0.33, 9.79))


def test_hinge_joint() -> None:
    sense = parse_both(b"(HJ (n llj4) (ax -61.93))")
    assert sense.joints == {"llj4": -61.93}


def test_force_resistance() -> None:
    sense = parse_both(b"(FRP (n rf) (c 0.01 -0.03 -0.01) (f -0.41 0.96 23.18))")
    assert sense.frp == {"rf": ForceResistance("rf", (0.01, -0.03, -0.01), (-0.41, 0.96, 23.18))}


def test_hear_self_and_from_a_direction() -> None:
    sense = parse_both(b"(hear Mine 41.26 self c,4,-3,2,1,0)(hear Rivals 41.28 -47.50 xk29)")
    assert sense.hears == (
        Hear("Mine", 41.26, None, "c,4,-3,2,1,0"),
        Hear("Rivals", 41.28, -47.50, "xk29"),
    )
    assert sense.hears[0].is_self and not sense.hears[1].is_self


def test_hear_without_team_label() -> None:
    message = b"(hear 3.10 -12.50 hello)"
    sense = parse_both(message)
    assert sense.hears == (Hear(None, 3.10, -12.5, "hello"),)
    assert format_sense(sense) == message


REFERENCE_SEE = (
    b"(See (G1R (pol 9.12 12.40 4.71)) (F1R (pol 12.05 47.93 -2.40)) (B (pol 2.31 -8.52 -12.66)) "
    b"(P (team Rivals) (id 4) (head (pol 5.02 20.11 0.93)) (lfoot (pol 5.10 21.37 -5.60))) "
    b"(P (team Mine) (id 2) (rlowerarm (pol 0.19 -35.40 -23.90)) (llowerarm (pol 0.18 35.10 -24.10))) "
    b"(L (pol 8.44 -33.05 -3.51) (pol 10.86 52.20 -2.93)))"
)


def test_vision() -> None:
    see = parse_both(REFERENCE_SEE).see
    assert see == See(
        objects=(
            VisibleObject("G1R", 9.12, 12.40, 4.71),
            VisibleObject("F1R", 12.05, 47.93, -2.40),
            VisibleObject("B", 2.31, -8.52, -12.66),
        ),
        players=(
            VisiblePlayer("Rivals", 4, {"head": Polar(5.02, 20.11, 0.93), "lfoot": Polar(5.10, 21.37, -5.60)}),
            VisiblePlayer("Mine", 2, {"rlowerarm": Polar(0.19, -35.40, -23.90),
                                      "llowerarm": Polar(0.18, 35.10, -24.10)}),
        ),
        lines=(VisibleLine(Polar(8.44, -33.05, -3.51), Polar(10.86, 52.20, -2.93)),),
    )
    assert see.order == "OOOPPL"
    assert see.objects[2].polar.distance_m == 2.31
    assert format_sense(parse_sense(REFERENCE_SEE)) == REFERENCE_SEE


def test_agent_state() -> None:
    sense = parse_both(b"(AgentState (battery 100.00) (temp 23.00))")
    assert sense.agent_state == AgentState(temperature=23.0, battery=100.0)
    with_camera = parse_both(b"(AgentState (pan_tilt 10 -5) (battery 99.50) (temp 23.10))")
    assert with_camera.agent_state == AgentState(23.1, 99.5, 10, -5)
    assert format_sense(with_camera) == b"(AgentState (pan_tilt 10 -5) (battery 99.50) (temp 23.10))"


# --- The real sample --------------------------------------------------------------------------------
def test_every_sample_message_round_trips_byte_for_byte() -> None:
    messages = received()
    assert len(messages) == 302
    for message in messages:
        sense = parse_both(message)
        assert sense.unknown == 0
        assert format_sense(sense) == message


def test_server_order_reproduces_every_sample_message() -> None:
    """A Sense built without an order (as our server builds them) comes out in the server's order."""
    for message in received():
        assert format_sense(dataclasses.replace(parse_sense(message), order=())) == message


def test_sample_content_is_typed() -> None:
    messages = received()
    first_gs = parse_sense(messages[2]).game_state
    assert first_gs == GameState(1, "left", 0, 0, 0.0, "BeforeKickOff")
    sense = parse_sense(vision_message())
    assert sense.see is not None and sense.time is not None
    assert len(sense.joints) == 22 and set(sense.frp) == {"lf", "rf"}
    assert [p.team for p in sense.see.players] == ["CapL", "CapR"]
    assert sense.time.now_s > 77.0
    heard = [h for m in messages for h in parse_sense(m).hears]
    assert {h.message for h in heard} == {"Hello123", "Reply456"}
    assert any(h.is_self for h in heard) and any(h.direction_deg is not None for h in heard)


# --- Shapes the sample does not show ----------------------------------------------------------------
@pytest.mark.parametrize(
    "message",
    [
        b"(See )",  # nothing in view: SexpParser still writes the space
        b"(See (P (team A) (id 1) (head (pol 1.00 2.00 3.00))) (B (pol 1.00 0.00 0.00)) (L (pol 1.00 2.00 "
        b"3.00) (pol 4.00 5.00 6.00)) (F1L (pol 9.00 8.00 7.00)))",  # interleaved: kept in wire order
        b"(See (P (team A) (rfoot (pol 1.00 2.00 3.00))))",  # player without id
        b"(See (B (pol 1.00 2.00 3.00)) (mypos -1.50 2.00 0.40) (L (pol 1.00 2.00 3.00) (pol 4.00 5.00 6.00)))",
    ],
)
def test_unusual_vision_shapes_round_trip(message: bytes) -> None:
    assert format_sense(parse_both(message)) == message


def test_empty_vision_is_written_with_its_space() -> None:
    sense = Sense(None, None, None, None, {}, see=See((), (), ()))
    assert format_sense(sense) == b"(See )"


def test_unknown_predicates_and_keys_are_skipped_and_counted() -> None:
    message = (b"(time (now 1.00))(foo (bar 1))(GS (sl 0) (sr 0) (t 0.00) (pm PlayOn) (k left))"
               b"(HJ (n hj1) (ax 2.00))(See (B (pol 1.00 2.00 3.00)) (X (odd 1)))(zz)")
    sense = parse_both(message)
    assert sense.unknown == 4  # foo, (k left), (X (odd 1)), zz
    assert sense.game_state is not None and sense.see is not None
    assert sense.game_state.play_mode == "PlayOn"
    assert sense.joints == {"hj1": 2.0}
    assert sense.see.objects == (VisibleObject("B", 1.0, 2.0, 3.0),)
    assert sense.order == ("time", "GS", "HJ", "See")


def test_foreign_spacing_parses_to_the_same_values() -> None:
    canonical = parse_sense(b"(time (now 1.00))(HJ (n hj1) (ax 2.00))(See (B (pol 1.00 2.00 3.00)))")
    spaced = parse_sense(b" (time (now 1.00))\n(HJ\t(n hj1)  (ax 2.00) ) (See (B (pol 1.00 2.00 3.00)) ) \n")
    assert spaced == canonical


# --- Malformed messages: ProtocolError at the right byte ---------------------------------------------
@BOTH_PATHS
@pytest.mark.parametrize(
    ("message", "offset"),
    [
        (b"(HJ (n hj1) (ax 1.2.3))", 16),  # bad float: offset of the token
        (b"(HJ (n hj1) (ax nan))", 16),  # perceptor values must be finite
        (b"(HJ (n hj1) (ax 1.00))(HJ (n hj1) (ax 2.00))", 22),  # a joint given twice
        (b"(time (now 1.00))(time (now 2.00))", 17),  # a predicate given twice
        (b"(HJ (n hj1))", 0),  # missing (ax ...)
        (b"(GS (sl x) (sr 0) (t 0.00) (pm PlayOn))", 8),  # bad int
        (b"(GYR (n torso) (rt 1.00 2.00))", 15),  # wrong arity
        (b"(time (now 1.00)))", 17),  # stray ')'
        (b"(time (now 1.00))(HJ (n hj1) (ax 1.00)", 38),  # truncated
        (b"(time (now 1.00))\xff(HJ (n hj1) (ax 1.00))", 17),  # garbage byte
        (b"(hear A 1.00)", 0),  # hear needs 3 or 4 atoms after the name
        (b"(hear A 1.00 self)", 6),  # 3 atoms: no team label, so "A" must be the time
        (b"(See (L (pol 1.00 2.00 3.00)))", 5),  # a line needs two end points
    ],
)
def test_malformed_messages_raise_at_the_offending_byte(message: bytes, offset: int, fast_path: bool) -> None:
    with pytest.raises(ProtocolError) as error:
        parse_sense(message, fast_path=fast_path)
    assert error.value.offset == offset
    assert f"byte {offset}" in str(error.value)


@BOTH_PATHS
def test_a_bad_number_deep_in_a_real_vision_message_is_located(fast_path: bool) -> None:
    message = vision_message()
    offset = message.index(b"(L (pol ") + len(b"(L (pol ")
    token_end = message.index(b" ", offset)
    broken = message[:offset] + b"1.x" + message[token_end:]
    with pytest.raises(ProtocolError) as error:
        parse_sense(broken, fast_path=fast_path)
    assert error.value.offset == offset
    assert b"1.x" in error.value.snippet


@BOTH_PATHS
def test_a_truncated_real_message_reports_the_end(fast_path: bool) -> None:
    message = vision_message()[:-7]
    with pytest.raises(ProtocolError) as error:
        parse_sense(message, fast_path=fast_path)
    assert error.value.offset == len(message)


# --- Formatting a Sense built by a server -------------------------------------------------------------
def test_a_built_sense_is_written_in_the_server_order() -> None:
    joints = {"hj1": 0.0, "hj2": -0.001, "raj1": 1.0, "rlj5": 2.0, "rlj6": 3.0, "llj5": 4.0, "llj6": 5.0}
    sense = Sense(
        time=TimePerceptor(10.0),
        game_state=GameState(None, None, 0, 0, 0.0, "PlayOn"),
        gyro=Gyro("torso", (0.0, 0.0, 0.0)),
        acc=Accelerometer("torso", (0.0, 0.0, 9.81)),
        joints=joints,
        frp={"lf": ForceResistance("lf", (0, 0, 0), (0, 0, 1)), "rf": ForceResistance("rf", (0, 0, 0), (0, 0, 2))},
        hears=(Hear("A", 1.0, None, "hi"),),
        see=See((VisibleObject("B", 1.0, 0.0, -0.004),), (), ()),
    )
    assert format_sense(sense) == (
        b"(time (now 10.00))(GS (sl 0) (sr 0) (t 0.00) (pm PlayOn))(hear A 1.00 self hi)"
        b"(GYR (n torso) (rt 0.00 0.00 0.00))(ACC (n torso) (a 0.00 0.00 9.81))"
        b"(HJ (n hj1) (ax 0.00))(HJ (n hj2) (ax -0.00))(See (B (pol 1.00 0.00 -0.00)))(HJ (n raj1) (ax 1.00))"
        b"(HJ (n rlj5) (ax 2.00))(FRP (n rf) (c 0.00 0.00 0.00) (f 0.00 0.00 2.00))(HJ (n rlj6) (ax 3.00))"
        b"(HJ (n llj5) (ax 4.00))(FRP (n lf) (c 0.00 0.00 0.00) (f 0.00 0.00 1.00))(HJ (n llj6) (ax 5.00))"
    )


def test_an_order_that_does_not_match_the_content_is_refused() -> None:
    sense = Sense(TimePerceptor(1.0), None, None, None, {"hj1": 1.0}, order=("time", "HJ", "HJ"))
    with pytest.raises(ProtocolError):
        format_sense(sense)
    see = See((VisibleObject("B", 1.0, 0.0, 0.0),), (), (), order="OL")
    with pytest.raises(ProtocolError):
        format_sense(Sense(None, None, None, None, {}, see=see))


@pytest.mark.parametrize("name", ["two words", "", "par(en"])
def test_a_name_that_is_not_an_atom_is_refused(name: str) -> None:
    with pytest.raises(ProtocolError):
        format_sense(Sense(None, None, None, None, {name: 1.0}))
    with pytest.raises(ProtocolError):
        format_sense(Sense(None, None, None, None, {}, hears=(Hear("A", 0.0, None, name),)))


def test_foot_sensors_without_their_anchor_joint_follow_the_joints() -> None:
    toe = ForceResistance("rf1", (0.0, 0.0, 0.0), (0.0, 0.0, 1.0))
    odd = ForceResistance("xx", (0.0, 0.0, 0.0), (0.0, 0.0, 2.0))
    with_toe = Sense(None, None, None, None, {"rlj6": 1.0, "rlj7": 2.0}, frp={"rf1": toe, "xx": odd})
    assert format_sense(with_toe) == (  # type 4: the toe sensor before the toe joint (by analogy)
        b"(HJ (n rlj6) (ax 1.00))(FRP (n rf1) (c 0.00 0.00 0.00) (f 0.00 0.00 1.00))(HJ (n rlj7) (ax 2.00))"
        b"(FRP (n xx) (c 0.00 0.00 0.00) (f 0.00 0.00 2.00))"
    )
    without_anchor = Sense(None, None, None, None, {"hj1": 0.5}, frp={"rf1": toe})
    assert format_sense(without_anchor) == (
        b"(HJ (n hj1) (ax 0.50))(FRP (n rf1) (c 0.00 0.00 0.00) (f 0.00 0.00 1.00))"
    )


def test_a_real_nan_line_end_parses_and_round_trips() -> None:
    """The real 0.7.3 server sent ``(L (pol 12.93 -60.32 -26.81) (pol nan nan nan))`` for a robot lying on
    its front: the message parses (the agent keeps its joints for that cycle), the values stay as sent."""
    import math
    from pathlib import Path

    from agent.protocol import format_sense

    data = (Path(__file__).parent / "fixtures" / "real_0.7.3_see_pol_nan.txt").read_bytes().strip()
    sense = parse_sense(data)
    assert any(math.isnan(line.end.distance_m) for line in sense.see.lines)
    assert sense.joints and format_sense(sense) == data


def test_the_world_model_drops_non_finite_sightings() -> None:
    import math
    from pathlib import Path

    from agent.world_model import WorldModel

    data = (Path(__file__).parent / "fixtures" / "real_0.7.3_see_pol_nan.txt").read_bytes().strip()
    world = WorldModel("Check", 1)
    world.update(parse_sense(data))
    frame = world.last_vision
    assert frame is not None
    assert len(frame.lines) == len(parse_sense(data).see.lines) - 1
    assert all(all(map(math.isfinite, (*a, *b))) for a, b in frame.lines)


@pytest.mark.parametrize("cls", [Sense, TimePerceptor, GameState, Gyro, Accelerometer, ForceResistance, Hear, See,
                                 VisiblePlayer])
def test_record_builders_make_what_the_constructors_make(cls: type) -> None:
    """The parsers' fast builders (perceptors.record_builder) give equal objects with the same repr and every
    field set, for the classes the parsers build."""
    from agent.protocol.perceptors import record_builder

    values = [f"value {i}" for i, _ in enumerate(dataclasses.fields(cls))]
    built, constructed = record_builder(cls)(*values), cls(*values)
    assert type(built) is cls
    assert built == constructed
    assert repr(built) == repr(constructed)
    assert [getattr(built, item.name) for item in dataclasses.fields(cls)] == values
    with pytest.raises(dataclasses.FrozenInstanceError):
        setattr(built, dataclasses.fields(cls)[0].name, 0)
