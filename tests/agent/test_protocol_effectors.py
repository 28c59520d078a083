"""Effector commands: exact bytes, say rules (REFERENCE §3.8), and the server-side parser."""

from __future__ import annotations

import math

import pytest
from hypothesis import given
from hypothesis import strategies as st

from agent.protocol.effectors import (
    SAY_MAX_CHARS,
    Beam,
    Init,
    InvalidAction,
    JointVelocity,
    PassMode,
    Say,
    Scene,
    Syn,
    UnknownAction,
    check_say_message,
    format_actions,
    format_joint_velocities,
    parse_actions,
)
from agent.protocol.errors import ProtocolError
from tests.agent.protocol_samples import sent


@pytest.mark.parametrize(
    ("action", "wire"),
    [
        (Scene("rsg/agent/nao/nao.rsg"), b"(scene rsg/agent/nao/nao.rsg)"),
        (Scene("rsg/agent/nao/nao_hetero.rsg", 3), b"(scene rsg/agent/nao/nao_hetero.rsg 3)"),
        (Init(7, "Mine"), b"(init (unum 7)(teamname Mine))"),
        (JointVelocity("lle3", -1.25), b"(lle3 -1.25)"),
        (JointVelocity("he1", 0.5), b"(he1 0.5)"),
        (JointVelocity("rle7", 1e-6), b"(rle7 0)"),  # below the 4 written decimals
        (Beam(-3.5, 1.0, 0.0), b"(beam -3.5 1 0)"),
        (Say("b,7,3,-12"), b"(say b,7,3,-12)"),
        (PassMode(), b"(pass)"),
        (Syn(), b"(syn)"),
    ],
)
def test_each_command_has_its_exact_bytes(action: object, wire: bytes) -> None:
    assert format_actions([action]) == wire  # type: ignore[list-item]
    assert format_actions(parse_actions(wire)) == wire  # type: ignore[arg-type]


def test_commands_concatenate_without_separator() -> None:
    assert format_actions([JointVelocity("he1", 0.5), JointVelocity("lle3", -1.2), Syn()]) == (
        b"(he1 0.5)(lle3 -1.2)(syn)"
    )


def test_every_sample_action_round_trips_byte_for_byte() -> None:
    messages = sent()
    assert len(messages) == 304
    for message in messages:
        actions = parse_actions(message)
        assert not any(isinstance(a, (UnknownAction, InvalidAction)) for a in actions)
        assert format_actions(actions) == message  # type: ignore[arg-type]


def test_sample_actions_parse_to_typed_values() -> None:
    messages = sent()
    assert parse_actions(messages[0]) == [Scene("rsg/agent/nao/nao_hetero.rsg", 0)]
    assert parse_actions(b"(init (unum 1)(teamname CapL))") == [Init(1, "CapL")]
    beams = [a for m in messages for a in parse_actions(m) if isinstance(a, Beam)]
    assert beams == [Beam(-2.5, 0.0, 0.0)] * 2
    said = {a.message for m in messages for a in parse_actions(m) if isinstance(a, Say)}
    assert said == {"Hello123", "Reply456"}


def test_body_command_helper_matches_the_typed_commands() -> None:
    velocities = {"he1": 0.5, "he2": -0.25, "lle1": 0.0, "rae4": 3.14159}
    assert format_joint_velocities(velocities) == format_actions(
        [JointVelocity(name, value) for name, value in velocities.items()]
    )
    assert format_joint_velocities(velocities) == b"(he1 0.5)(he2 -0.25)(lle1 0)(rae4 3.1416)"
    with pytest.raises(ProtocolError):
        format_joint_velocities({"llj1": 1.0})  # a perceptor name, not an effector
    with pytest.raises(ProtocolError):
        format_joint_velocities({"he1": math.nan})


@given(st.sampled_from(["he1", "lae3", "rle6"]), st.floats(min_value=-1e6, max_value=1e6))
def test_joint_velocities_read_back_within_the_written_precision(effector: str, velocity: float) -> None:
    wire = format_actions([JointVelocity(effector, velocity)])
    (parsed,) = parse_actions(wire)
    assert isinstance(parsed, JointVelocity) and parsed.effector == effector
    assert abs(parsed.velocity_rad_s - velocity) <= 5e-5
    assert format_actions([parsed]) == wire  # the format is a fixed point


# --- say rules --------------------------------------------------------------------------------------
def test_say_accepts_twenty_printable_characters() -> None:
    message = "!\"#$%&'*+,-./0123:;<"
    assert len(message) == SAY_MAX_CHARS
    assert check_say_message(message) == message
    assert Say("~" * 20).to_text() == "(say " + "~" * 20 + ")"


@pytest.mark.parametrize(
    ("message", "offset"),
    [
        ("x" * 21, 20),  # too long: offset of the first character past the limit
        ("hello world", 5),  # space
        ("a(b", 1),
        ("ab)", 2),
        ("tab\t", 3),
        ("del\x7f", 3),
        ("caf\u00e9", 3),  # not ASCII
        ("", 0),
    ],
)
def test_say_refuses_what_the_server_would_drop(message: str, offset: int) -> None:
    with pytest.raises(ProtocolError) as error:
        Say(message)
    assert error.value.offset == offset
    assert isinstance(error.value, ValueError)


def test_other_builders_validate_their_names() -> None:
    for build in (lambda: Init(1, "two words"), lambda: Init(-1, "A"), lambda: Scene("a b"),
                  lambda: JointVelocity("hj1", 1.0)):
        with pytest.raises(ProtocolError):
            build()


def test_non_finite_values_are_never_written() -> None:
    for action in (JointVelocity("he1", math.inf), Beam(math.nan, 0.0, 0.0)):
        assert not action.finite
        with pytest.raises(ProtocolError):
            format_actions([action])


# --- server side ------------------------------------------------------------------------------------
def test_unknown_and_invalid_commands_are_kept_not_fatal() -> None:
    actions = parse_actions(b"(he1 0.5)(dance 1)(beam 1 2)(say too_long_for_the_server_x)(syn)(pass 1)()")
    assert actions == [
        JointVelocity("he1", 0.5),
        UnknownAction("dance", 9),
        InvalidAction("beam", 18, "(beam ...) takes 3 atom(s)"),
        InvalidAction("say", 28, "say message has 25 characters, max 20"),
        Syn(),
        InvalidAction("pass", 64, "(pass ...) takes 0 atom(s)"),
        UnknownAction("", 72),
    ]


def test_non_finite_values_parse_and_are_flagged() -> None:
    joint, beam = parse_actions(b"(he1 nan)(beam inf 0 0)")
    assert isinstance(joint, JointVelocity) and not joint.finite
    assert isinstance(beam, Beam) and not beam.finite


def test_a_bad_number_is_an_invalid_command_with_its_reason() -> None:
    (action,) = parse_actions(b"(lle1 0x10)")
    assert isinstance(action, InvalidAction) and "0x10" in action.reason


@pytest.mark.parametrize(("data", "offset"), [(b"(he1 0.5)(syn", 13), (b"(syn))", 5), (b"(say \x80)", 5)])
def test_broken_syntax_is_fatal_with_the_offset(data: bytes, offset: int) -> None:
    with pytest.raises(ProtocolError) as error:
        parse_actions(data)
    assert error.value.offset == offset


def test_parsing_gives_the_typed_command_back() -> None:
    wire = b"(scene rsg/agent/nao/nao_hetero.rsg 3)(init (unum 7)(teamname Mine))(lle3 -1.25)(beam -3.5 1 0)"
    assert parse_actions(wire + b"(say b,7,3,-12)(pass)(syn)") == [
        Scene("rsg/agent/nao/nao_hetero.rsg", 3),
        Init(7, "Mine"),
        JointVelocity("lle3", -1.25),
        Beam(-3.5, 1.0, 0.0),
        Say("b,7,3,-12"),
        PassMode(),
        Syn(),
    ]


@given(st.lists(st.tuples(st.sampled_from(["he1", "lae4", "rle6", "syn"]),
                          st.floats(min_value=-50, max_value=50)), max_size=25))
def test_the_joint_command_fast_path_agrees_with_the_general_reader(commands: list[tuple[str, float]]) -> None:
    actions = [Syn() if name == "syn" else JointVelocity(name, value) for name, value in commands]
    wire = format_actions(actions)  # type: ignore[arg-type]
    fast = parse_actions(wire)  # only joints and syn: the fast path
    general = parse_actions(wire + b"(pass)")  # a (pass) sends the whole message down the general path
    assert general[-1] == PassMode()
    assert fast == general[:-1]
    assert all(type(a) is type(b) for a, b in zip(fast, general))
    assert format_actions(fast) == wire  # type: ignore[arg-type]


def test_the_usual_message_is_split_without_action_objects() -> None:
    from agent.protocol.effectors import split_joint_commands
    assert split_joint_commands("(he1 0.5)(lle3 -1.25)(syn)") == (["he1", "lle3"], [0.5, -1.25], True)
    assert split_joint_commands("(he1 2)") == (["he1"], [2.0], False)
    assert split_joint_commands("(syn)") == ([], [], True)
    assert split_joint_commands("") == ([], [], False)
    for other in ("(syn)(he1 1)", "(he1 1)(syn)(syn)", "(he1 1) (he2 2)", "(he1 1e3)", "(he1 nan)", "(he9 1)",
                  "(lae7 1)", "(say hi)(syn)", "(he1 1", "(he1 1.2.3)", "(he1 .)", "(he1 -)", "(he1 +1)"):
        assert split_joint_commands(other) is None, other
    # What the split accepts, the general reader reads alike (a (pass) sends a message down that path).
    for usual in ("(he1 1.)(syn)", "(lle7 -.5)", "(rae4 007)(he2 -0)"):
        assert parse_actions(usual) == parse_actions(usual + "(pass)")[:-1], usual


def test_the_whole_body_template_writes_what_the_server_reads() -> None:
    from agent.protocol.effectors import joint_velocity_template, split_joint_commands
    names = ["he1", "lae3", "rle7"]
    wire = joint_velocity_template(names) % (0.5, -1.23456, -1e-6) + b"(syn)"
    assert wire == b"(he1 0.5000)(lae3 -1.2346)(rle7 -0.0000)(syn)"
    assert split_joint_commands(wire.decode()) == (names, [0.5, -1.2346, -0.0], True)
    assert parse_actions(wire) == [JointVelocity("he1", 0.5), JointVelocity("lae3", -1.2346),
                                   JointVelocity("rle7", 0.0), Syn()]
    with pytest.raises(ProtocolError):
        joint_velocity_template(["he1", "hx9"])
