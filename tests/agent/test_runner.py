"""The TCP runner against a scripted loopback server: handshake, a malformed message, reconnection, no server."""

from __future__ import annotations

import socket
import subprocess
import sys
import threading

import pytest

from agent import AgentConfig
from agent.errors import ServerUnreachable
from agent.protocol import parse_actions, read_frame, write_frame
from agent.protocol.effectors import Init, Scene, Syn
from agent.runner import ConnectionPolicy, run
from tests.agent.protocol_samples import records

FAST = ConnectionPolicy(connect_attempts=3, backoff_s=0.05, backoff_max_s=0.1, read_timeout_s=5.0, max_reconnects=1)


def sample_messages(count):
    return [str(r["msg"]).encode() for r in records() if r["k"] == "recv" and r["a"] == "L"][:count]


class ScriptedServer:
    """Accepts ``sessions`` connections one after another; each sends ``messages`` and records the replies."""

    def __init__(self, sessions):
        self.listener = socket.create_server(("127.0.0.1", 0))
        self.port = self.listener.getsockname()[1]
        self.sessions = sessions
        self.received: list[list[bytes]] = []
        self.thread = threading.Thread(target=self._serve, daemon=True)
        self.thread.start()

    def _serve(self):
        with self.listener:
            for messages in self.sessions:
                conn, _ = self.listener.accept()
                replies: list[bytes] = []
                self.received.append(replies)
                with conn:
                    replies.append(read_frame(conn))  # scene
                    for message in messages:
                        write_frame(conn, message)
                        replies.append(read_frame(conn))


def test_handshake_every_cycle_answered_bad_message_skipped_then_reconnect():
    good = sample_messages(6)
    session = good[:3] + [b"(time (now 1.00))(GS (t 0.00) (pm Play"] + good[3:]
    server = ScriptedServer([session, good[:2]])
    with pytest.raises(ServerUnreachable, match="reconnection"):
        run(AgentConfig("CapL", 1), "127.0.0.1", server.port, FAST)
    server.thread.join(5)
    first, second = server.received
    assert parse_actions(first[0]) == [Scene("rsg/agent/nao/nao_hetero.rsg", 0)]
    assert len(first) == 1 + len(session)  # every message, the malformed one too, got an answer
    assert parse_actions(first[1])[0] == Init(1, "CapL")
    assert all(parse_actions(reply)[-1] == Syn() for reply in first[1:])
    assert first[4] == b"(syn)"  # the malformed message
    # The lost connection was followed by a fresh agent: scene and init again.
    assert parse_actions(second[0])[0] == Scene("rsg/agent/nao/nao_hetero.rsg", 0)
    assert parse_actions(second[1])[0] == Init(1, "CapL")


def test_agent_is_built_before_connecting(monkeypatch):
    """The real server in sync mode stalls when a new connection's (scene ...) comes late (building the soccer
    agent takes 0.1-1 s: every agent then timed out and reconnected), so nothing slow may sit between the
    connection and the scene: each agent, the first and each reconnection's, is made before its connect."""
    import agent.runner as runner
    from agent.agent import Agent

    events: list[str] = []
    real_connect = runner.connect

    def connect(*args, **kwargs):
        events.append("connect")
        return real_connect(*args, **kwargs)

    def make_agent(config):
        events.append("make")
        return Agent(config)

    monkeypatch.setattr(runner, "connect", connect)
    good = sample_messages(2)
    server = ScriptedServer([good, good])
    with pytest.raises(ServerUnreachable):
        run(AgentConfig("CapL", 1), "127.0.0.1", server.port, FAST, make_agent=make_agent)
    server.thread.join(5)
    assert events == ["make", "connect", "make", "connect"]
    assert all(len(replies) == 1 + len(good) for replies in server.received)


def test_stop_event_ends_the_run_cleanly():
    stop = threading.Event()
    messages = sample_messages(4)
    listener = socket.create_server(("127.0.0.1", 0))
    closed = threading.Event()

    def serve():
        with listener:
            conn, _ = listener.accept()
            with conn:
                read_frame(conn)
                for message in messages[:-1]:
                    write_frame(conn, message)
                    read_frame(conn)
                stop.set()  # the agent stops at its next loop turn, before or after this last message
                try:
                    write_frame(conn, messages[-1])
                    while read_frame(conn) is not None:
                        pass
                except OSError:  # reset: the agent closed with the last message unread
                    pass
                closed.set()  # the agent closed the connection

    thread = threading.Thread(target=serve, daemon=True)
    thread.start()
    stats = run(AgentConfig("CapL", 1), "127.0.0.1", listener.getsockname()[1], FAST, stop=stop)
    thread.join(5)
    assert closed.is_set()
    assert stats.cycles in (3, 4) and stats.connections == 1 and stats.lost_connections == 0


def _closed_port():
    with socket.socket() as sock:
        sock.bind(("127.0.0.1", 0))
        return sock.getsockname()[1]


def test_no_server_raises_after_the_bounded_retries():
    with pytest.raises(ServerUnreachable) as info:
        run(AgentConfig("Mine", 2), "127.0.0.1", _closed_port(), FAST)
    assert info.value.attempts == 3


def test_cli_exits_non_zero_with_a_clear_message():
    result = subprocess.run([sys.executable, "-m", "agent", "--port", str(_closed_port()), "--attempts", "1",
                             "--team", "Mine", "--unum", "3"], capture_output=True, text=True, timeout=60)
    assert result.returncode == 2
    assert "no server answered" in result.stderr
    bad = subprocess.run([sys.executable, "-m", "agent", "--unum", "12", "--attempts", "1"],
                         capture_output=True, text=True, timeout=60)
    assert bad.returncode == 2 and "unum" in bad.stderr


def test_motion_studio_agent_subcommand_exits_2_without_a_server():
    from typer.testing import CliRunner

    from motion_studio.cli import _register_commands, app

    _register_commands()
    result = CliRunner().invoke(app, ["agent", "--port", str(_closed_port()), "--attempts", "1", "--team", "Mine"])
    assert result.exit_code == 2


def test_the_status_line_says_how_long_ago_each_teammate_was_heard():
    """Teammates seen and teammates heard are told apart: the line once listed only teammates whose last
    news was a message, so a teammate also seen looked unheard."""
    from agent import Agent
    from agent.communication import TeamMessage, encode
    from agent.protocol import Hear, parse_sense
    from agent.runner import status_line
    from tests.agent import synthetic_world as synth

    agent = Agent(AgentConfig("Mine", 2))
    said = encode(TeamMessage("l", 3, position=(1.0, 2.0)), "Mine")
    agent.world.update(parse_sense(synth.sense_bytes(10.0, unum=2, side="left", play_mode="PlayOn",
                                                     hears=(Hear("Mine", 1.0, 30.0, said),))))
    agent.world.update(parse_sense(synth.sense_bytes(10.5, play_mode="PlayOn")))
    line = status_line(agent)
    assert "last heard {3: '0.5 s ago'}" in line, line
    assert "teammates seen {}" in line, line
