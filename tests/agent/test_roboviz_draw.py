"""RoboViz drawing (issue 16 item 6): the draw protocol's bytes through a real UDP socket, the agent's beliefs as
shapes, and drawing off unless asked for."""

from __future__ import annotations

import json
import socket
from pathlib import Path

import pytest

from agent import Agent, AgentConfig
from agent.drawing import roboviz
from agent.drawing.beliefs import belief_packets, set_name
from agent.drawing.udp import DEFAULT_DRAW_PORT, ENV_VAR, RoboVizDrawer, drawer_from_env, parse_address
from agent.errors import ConfigError
from agent.runner import build_parser
from agent.skills.walk import WalkTo
from agent.team.soccer_behavior import SoccerBehavior

TRACE = Path(__file__).parent / "fixtures" / "oursim_localization.jsonl"


@pytest.fixture()
def receiver():
    """A UDP socket on loopback standing in for RoboViz's draw port."""
    sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
    sock.bind(("127.0.0.1", 0))
    sock.settimeout(5.0)
    yield sock
    sock.close()


def _received(sock: socket.socket, count: int) -> list[bytes]:
    return [sock.recvfrom(4096)[0] for _ in range(count)]


def test_numbers_are_six_characters_as_roboviz_reads_them() -> None:
    assert [roboviz.number(v) for v in (1.5, -2.0, 15.3, 0.123456789, 0.0, -0.25)] == \
        [b"1.5000", b"-2.000", b"15.300", b"0.1234", b"0.0000", b"-0.250"]
    with pytest.raises(ValueError, match="finite"):
        roboviz.number(float("nan"))


def test_every_packet_kind_arrives_byte_for_byte(receiver: socket.socket) -> None:
    port = receiver.getsockname()[1]
    drawer = RoboVizDrawer("127.0.0.1", port)
    packets = [
        roboviz.circle((1.5, -2.0), 0.3, 2.0, (255, 0, 16), "a.b"),
        roboviz.line((0.0, 1.0, 0.5), (-3.25, 4.0, 0.0), 1.0, (1, 2, 3), "a.b"),
        roboviz.point((2.0, 2.0, 0.0), 8.0, (0, 255, 0), "s"),
        roboviz.sphere((0.0, 0.0, 0.042), 0.06, (255, 140, 0), "s"),
        roboviz.polygon([(0.0, 0.0, 0.0), (1.0, 0.0, 0.0), (0.0, 1.0, 0.0)], (10, 20, 30, 128), "p"),
        roboviz.annotation("hi", (1.0, 2.0, 0.9), (255, 255, 255), "s"),
        roboviz.agent_annotation("right", 3, "3 support", (255, 60, 40)),
        roboviz.agent_annotation_clear("left", 11),
        roboviz.swap_buffers("a.b"),
    ]
    drawer.send(packets)
    drawer.close()
    expected = [
        b"\x01\x00" b"1.5000-2.0000.30002.0000" b"\xff\x00\x10" b"a.b\x00",
        b"\x01\x01" b"0.00001.00000.5000-3.2504.00000.00001.0000" b"\x01\x02\x03" b"a.b\x00",
        b"\x01\x02" b"2.00002.00000.00008.0000" b"\x00\xff\x00" b"s\x00",
        b"\x01\x03" b"0.00000.00000.04200.0600" b"\xff\x8c\x00" b"s\x00",
        b"\x01\x04\x03" b"\x0a\x14\x1e\x80" b"0.00000.00000.0000" b"1.00000.00000.0000" b"0.00001.00000.0000" b"p\x00",
        b"\x02\x00" b"1.00002.00000.9000" b"\xff\xff\xff" b"hi\x00" b"s\x00",
        b"\x02\x01" b"\x82" b"\xff\x3c\x28" b"3 support\x00",   # right team: 128 + unum 3 - 1
        b"\x02\x02" b"\x0a",                                   # left team: unum 11 - 1
        b"\x00\x00" b"a.b\x00",
    ]
    assert _received(receiver, len(expected)) == expected


def _trace_agent() -> Agent:
    """Our soccer agent after the recorded trace of our server (unum 2, left; it localizes and sees the ball)."""
    rows = [json.loads(line) for line in TRACE.read_text().splitlines()][1:]
    agent = Agent(AgentConfig("Ours", 2), SoccerBehavior(0))
    for row in rows:
        agent.step(row["msg"].encode("ascii"))
    return agent


def test_beliefs_self_ball_target_and_role_are_drawn_then_swapped(receiver: socket.socket) -> None:
    agent = _trace_agent()
    agent.behavior.skills.skill = WalkTo(-4.0, 1.5)   # a target in the team frame (left: the field frame)
    packets = belief_packets(agent)
    name = set_name("left", 2).encode() + b"\0"
    assert name == b"nao3d.L02\0"
    kinds = [p[:2] for p in packets]
    assert kinds[0] == b"\x01\x00" and kinds[-1] == b"\x00\x00" and packets[-1] == b"\x00\x00" + name
    assert b"\x01\x03" in kinds                                  # the ball it believes in
    pose = agent.world.world_pose()
    assert packets[0][2:14] == roboviz.number(pose.x_m) + roboviz.number(pose.y_m)
    assert roboviz.point((-4.0, 1.5, 0.0), 8.0, (255, 0, 255), "nao3d.L02") in packets
    role = [p for p in packets if p[:2] == b"\x02\x01"]
    assert role == [roboviz.agent_annotation("left", 2, f"2 {agent.behavior.role}", (40, 110, 255))]
    drawer = RoboVizDrawer("127.0.0.1", receiver.getsockname()[1], every_cycles=1)
    drawer.draw(agent)
    drawer.close()
    assert _received(receiver, len(packets)) == packets and drawer.frames == 1


def test_nothing_is_drawn_before_the_agent_knows_who_it_is() -> None:
    assert belief_packets(Agent(AgentConfig("Ours", 2))) == []


def test_set_names_are_no_prefix_of_each_other() -> None:
    names = [set_name(side, unum) for side in ("left", "right") for unum in range(1, 12)]
    assert not any(a != b and b.startswith(a) for a in names for b in names)


def test_drawing_is_off_by_default_and_on_by_option_or_variable() -> None:
    assert drawer_from_env({}) is None
    assert build_parser().parse_args([]).roboviz_draw is None
    assert build_parser().parse_args(["--roboviz-draw"]).roboviz_draw == f"127.0.0.1:{DEFAULT_DRAW_PORT}"
    drawer = drawer_from_env({ENV_VAR: "localhost:4000"})
    assert drawer is not None and drawer.address == ("localhost", 4000)
    drawer.close()
    option = drawer_from_env({ENV_VAR: "localhost:4000"}, "127.0.0.1")
    assert option is not None and option.address == ("127.0.0.1", DEFAULT_DRAW_PORT)
    option.close()
    assert parse_address(":5000") == ("127.0.0.1", 5000)
    with pytest.raises(ConfigError, match="port must be 1-65535"):
        parse_address("host:70000")
