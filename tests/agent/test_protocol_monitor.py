"""Monitor messages: the real 0.7.3 frames parse, and write back byte for byte."""

from __future__ import annotations

import re

import pytest

from agent.protocol.errors import ProtocolError
from agent.protocol.monitor import format_game_state, format_monitor, parse_monitor
from agent.protocol.numbers import format_g6
from tests.agent.protocol_samples import monitor_lines

_NUMBER = re.compile(r"-?\d+(?:\.\d+)?(?:e[-+]\d+)?\Z")


def test_the_sample_frames_parse() -> None:
    full, update, update2 = (parse_monitor(line) for line in monitor_lines())
    assert (full.kind, full.kind_arguments, full.is_full) == ("RSG", ("0", "1"), True)
    assert (update.kind, update2.kind, update.is_full) == ("RDS", "RDS", False)
    state = full.game_state
    assert state["FieldLength"] == ("30",) and state["GoalWidth"] == ("2.1",) and state["BallMass"] == ("0.026",)
    assert len(state["play_modes"]) == 21 and state["play_modes"][:2] == ("BeforeKickOff", "KickOff_Left")
    assert state["team_left"] == ("Capture",) and state["play_mode"] == ("0",)
    assert update.game_state == {"time": ("0",)}
    assert full.scene is not None and full.scene[0][:2] == ["nd", "TRF"]
    assert full.fouls == []


def test_every_sample_frame_is_written_back_byte_for_byte() -> None:
    for line in monitor_lines():
        assert format_monitor(parse_monitor(line)) == line
        assert format_monitor(parse_monitor(line, parse_scene=False)) == line


def test_the_game_state_is_written_from_typed_values_like_the_server() -> None:
    for line in monitor_lines():
        message = parse_monitor(line)
        typed = [(key, [_typed(value) for value in values]) for key, values in message.entries]
        assert line.startswith(format_game_state(typed))


def _typed(token: str) -> str | int | float:
    if re.fullmatch(r"-?\d+", token):
        return int(token)
    return float(token) if _NUMBER.match(token) else token


def test_every_scene_number_is_spelled_like_cpp_ostream() -> None:
    numbers: list[str] = []

    def walk(node: list[object]) -> None:
        for item in node:
            if isinstance(item, list):
                walk(item)
            elif isinstance(item, str) and _NUMBER.match(item):
                numbers.append(item)

    for line in monitor_lines():
        walk(parse_monitor(line).scene)  # type: ignore[arg-type]
    assert len(numbers) > 1000 and "-8.74228e-08" in numbers and "-0" in numbers
    assert [format_g6(float(n)) for n in numbers] == numbers


def test_fouls_may_repeat() -> None:
    message = parse_monitor(b"((time 12.3)(foul 1 2 3 1)(foul 2 4 5 2))(RDS 0 1)((nd))")
    assert message.fouls == [("1", "2", "3", "1"), ("2", "4", "5", "2")]
    assert message.game_state == {"time": ("12.3",)}


@pytest.mark.parametrize(
    ("data", "offset"),
    [
        (b"((time 0))(RDS 0 1)", 19),  # no scene graph
        (b"((time 0))", 10),
        (b"((time (0)))(RDS 0 1)((nd))", 1),  # a game-state value that is a list
        (b"((time 0))((RDS) 0 1)((nd))", 10),  # the kind must be atoms
        (b"((time 0))(RDS 0 1)((nd)", 24),  # truncated scene graph
    ],
)
def test_malformed_frames_raise_with_the_offset(data: bytes, offset: int) -> None:
    with pytest.raises(ProtocolError) as error:
        parse_monitor(data)
    assert error.value.offset == offset
