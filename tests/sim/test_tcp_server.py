"""The TCP server over real loopback sockets, with a stub engine (sync, real time, latency, bad clients)."""

from __future__ import annotations

import re
import selectors
import socket
import struct
import time

import pytest

from agent.protocol.framing import FrameDecoder, frame
from sim.tcp_server import SimServer


class StubEngine:
    """Counts cycles; each sense message says the cycle and the last action received before the step.

    Like sim.engine.SimEngine, `step` returns the messages made at the end of the previous step.
    """

    def __init__(self) -> None:
        self.next_id = 0
        self.connected: set[int] = set()
        self.last_action: dict[int, bytes] = {}
        self.cycle = 0
        self.received: list[tuple[int, bytes]] = []

    def connect(self) -> int:
        self.next_id += 1
        self.connected.add(self.next_id)
        return self.next_id

    def disconnect(self, agent_id: int) -> None:
        self.connected.discard(agent_id)

    def receive(self, agent_id: int, payload: bytes) -> None:
        self.received.append((agent_id, payload))
        self.last_action[agent_id] = payload

    def step(self) -> dict[int, bytes]:
        out = {i: payload for i, payload in getattr(self, "outbox", {}).items() if i in self.connected}
        self.cycle += 1
        self.outbox = {i: b"(time (now %.2f))(cyc %d)(last %s)" % (self.cycle * 0.02, self.cycle,
                                                                   self.last_action.get(i, b"none"))
                       for i in self.connected}
        return out


class Client:
    """A blocking test client on loopback."""

    def __init__(self, port: int) -> None:
        self.sock = socket.create_connection(("127.0.0.1", port), timeout=5.0)
        self.decoder = FrameDecoder()
        self.queue: list[bytes] = []

    def send(self, payload: bytes) -> None:
        self.sock.sendall(frame(payload))

    def recv(self) -> bytes:
        while not self.queue:
            data = self.sock.recv(65536)
            if not data:
                raise ConnectionError("server closed")
            self.queue.extend(self.decoder.feed(data))
        return self.queue.pop(0)

    def close(self) -> None:
        self.sock.close()


def cycle_of(message: bytes) -> int:
    match = re.search(rb"\(cyc (\d+)\)", message)
    assert match, message
    return int(match.group(1))


@pytest.fixture
def server_factory():
    servers: list[SimServer] = []

    def make(**kwargs) -> SimServer:
        engine = kwargs.pop("engine", None) or StubEngine()
        kwargs.setdefault("sync_read_wait_s", 0.2)  # the real 1 s would only slow the joins down
        server = SimServer(engine, agent_port=0, **kwargs).start()
        servers.append(server)
        return server

    yield make
    for server in servers:
        server.stop()


def test_binds_loopback_by_default(server_factory) -> None:
    server = server_factory(sync=True)
    assert server.host == "127.0.0.1" and server.agent_port


def test_sync_mode_waits_for_syn_and_latency_is_two_messages(server_factory) -> None:
    server = server_factory(sync=True, real_time=False)
    client = Client(server.agent_port)
    cycles = []
    for _ in range(30):
        message = client.recv()
        k = cycle_of(message)
        cycles.append(k)
        client.send(b"(act %d)(syn)" % k)
    assert cycles == list(range(cycles[0], cycles[0] + 30))  # one message per cycle, none skipped
    # The 4 grace cycles left a few messages in flight; read them without answering, then the server
    # must stop: it only steps after our (syn).
    client.sock.settimeout(0.3)
    message = b""
    with pytest.raises(socket.timeout):
        for _ in range(10):
            message = client.recv()
    assert message
    stepped = server.stats.cycles
    time.sleep(0.1)
    assert server.stats.cycles == stepped
    # An action sent in reply to message k shows first in message k + 2 (REFERENCE §3.9).
    k = cycle_of(message)
    client.sock.settimeout(5.0)
    client.send(b"(act %d)(syn)" % k)
    nxt = client.recv()
    assert b"(last (act %d)" % k not in nxt
    client.send(b"(syn)")
    after = client.recv()
    assert cycle_of(after) == k + 2 and b"(last (act %d)(syn))" % k in after
    client.close()


def test_one_client_driving_two_agents_in_any_order(server_factory) -> None:
    server = server_factory(sync=True, real_time=False)
    first, second = Client(server.agent_port), Client(server.agent_port)
    selector = selectors.DefaultSelector()
    for client in (first, second):
        client.sock.setblocking(False)
        selector.register(client.sock, selectors.EVENT_READ, client)
    seen = {id(first): [], id(second): []}
    deadline = time.monotonic() + 10.0
    while min(len(v) for v in seen.values()) < 40 and time.monotonic() < deadline:
        for key, _ in selector.select(1.0):
            client = key.data
            try:
                data = client.sock.recv(65536)
            except BlockingIOError:
                continue
            for payload in client.decoder.feed(data):
                seen[id(client)].append(cycle_of(payload))
                client.sock.setblocking(True)
                client.send(b"(syn)")
                client.sock.setblocking(False)
    assert min(len(v) for v in seen.values()) >= 40
    for cycles in seen.values():
        assert cycles == list(range(cycles[0], cycles[0] + len(cycles)))


def test_real_time_mode_never_waits(server_factory) -> None:
    server = server_factory(sync=False, real_time=True)
    client = Client(server.agent_port)
    start = time.monotonic()
    first = cycle_of(client.recv())
    while time.monotonic() - start < 0.5:
        last = cycle_of(client.recv())  # never answering
    rate = (last - first) / (time.monotonic() - start)
    assert 35 <= rate <= 60
    client.close()


def test_sync_with_real_time_is_capped_at_50_hz(server_factory) -> None:
    server = server_factory(sync=True, real_time=True)
    client = Client(server.agent_port)
    client.recv()  # a new agent's first message comes after the read waits (sim.tcp_server docstring)
    client.send(b"(syn)")
    start = time.monotonic()
    count = 0
    while time.monotonic() - start < 0.5:
        client.recv()
        client.send(b"(syn)")
        count += 1
    assert 15 <= count <= 30


@pytest.mark.parametrize("bad", [
    struct.pack(">I", 0xFFFFFFF0) + b"(syn)",       # "negative" / huge prefix
    struct.pack(">I", 10_000_000),                    # above the frame cap
    b"GET / HTTP/1.1\r\nHost: x\r\n\r\n",             # garbage read as a prefix
])
def test_bad_prefix_drops_only_that_client(server_factory, bad: bytes) -> None:
    server = server_factory(sync=True, real_time=False)
    good = Client(server.agent_port)
    bad_client = Client(server.agent_port)
    good.recv()
    good.send(b"(syn)")
    bad_client.sock.sendall(bad)
    bad_client.sock.settimeout(3.0)
    with pytest.raises((ConnectionError, OSError)):
        for _ in range(20):
            bad_client.recv()
    for _ in range(20):
        good.recv()
        good.send(b"(syn)")
    assert server.stats.clients_dropped >= 1


def test_client_vanishing_mid_frame_and_bad_payloads(server_factory) -> None:
    engine = StubEngine()
    server = server_factory(sync=True, real_time=False, engine=engine)
    good = Client(server.agent_port)
    ghost = Client(server.agent_port)
    ghost.sock.sendall(struct.pack(">I", 100) + b"(he1 0.5")
    ghost.close()
    noisy = Client(server.agent_port)
    for payload in (b"((((", b"))(", b"(he1 nan)(lle3 inf)(syn)", b"(unknown 1 2)(syn)", b"\x00\xff\x80",
                    b"", b"(syn)"):
        noisy.send(payload)
    for _ in range(20):
        good.recv()
        good.send(b"(syn)")
        try:
            noisy.sock.setblocking(False)
            noisy.sock.recv(65536)
        except BlockingIOError:
            pass
        noisy.send(b"(syn)")
        noisy.sock.setblocking(True)
    assert server.agent_count == 2
    assert any(payload == b"(he1 nan)(lle3 inf)(syn)" for _, payload in engine.received)


def test_engine_exception_does_not_stop_the_server(server_factory) -> None:
    class Faulty(StubEngine):
        def receive(self, agent_id: int, payload: bytes) -> None:
            if b"boom" in payload:
                raise RuntimeError("engine bug")
            super().receive(agent_id, payload)

    server = server_factory(sync=True, engine=Faulty())
    client = Client(server.agent_port)
    for _ in range(5):
        client.recv()
        client.send(b"(boom)(syn)")
    assert server.stats.engine_errors >= 1


def test_new_agent_counts_as_synced_for_four_cycles(server_factory) -> None:
    server = server_factory(sync=True, real_time=False)
    silent = Client(server.agent_port)
    received = [silent.recv() for _ in range(4)]  # the server steps without our (syn)
    assert [cycle_of(m) for m in received] == list(range(cycle_of(received[0]), cycle_of(received[0]) + 4))
    silent.sock.settimeout(0.3)
    with pytest.raises(socket.timeout):
        for _ in range(3):
            silent.recv()
    cycles = server.stats.cycles
    time.sleep(0.1)
    assert server.stats.cycles == cycles  # now it waits for us
    silent.sock.settimeout(5.0)
    silent.send(b"(syn)")
    assert cycle_of(silent.recv()) == cycle_of(received[0]) + 4


def test_stop_closes_the_ports(server_factory) -> None:
    server = server_factory(sync=True)
    port = server.agent_port
    server.stop()
    with pytest.raises(OSError):
        socket.create_connection(("127.0.0.1", port), timeout=1.0)


def test_monitor_port_streams_full_state_then_diffs_and_takes_trainer_commands(server_factory) -> None:
    from sim.monitor import GameView, SceneSnapshot, WorldMonitorFeed
    from sim.referee import Referee
    from sim.rules.trainer import apply_trainer_message
    from tests.sim.test_referee_rules import FakeWorld

    referee, world = Referee(seed=0), FakeWorld()

    def snapshot() -> SceneSnapshot:
        return SceneSnapshot(GameView(time_s=referee.game_time_s, play_mode_index=referee.play_mode_index))

    server = server_factory(sync=True, real_time=True, monitor_port=0, monitor=WorldMonitorFeed(snapshot),
                            trainer=lambda payload: apply_trainer_message(payload, referee, world))
    monitor = Client(server.monitor_port)
    first = monitor.recv()
    assert first.startswith(b"((FieldLength 30)") and b"(RSG 0 1)" in first
    assert b"(RDS 0 1)" in monitor.recv()
    monitor.send(b"(playMode PlayOn)")
    deadline = time.monotonic() + 5.0
    while b"(play_mode 3)" not in monitor.recv():
        assert time.monotonic() < deadline
    monitor.send(b"(reqfullstate)")
    while b"(RSG 0 1)" not in monitor.recv():
        assert time.monotonic() < deadline
    monitor.send(b"(kickOff Left")  # broken: logged, ignored
    monitor.send(b"(killsim)")
    monitor.sock.settimeout(5.0)
    with pytest.raises((ConnectionError, OSError)):
        for _ in range(200):
            monitor.recv()


def test_real_engine_over_tcp_with_monitor_and_log(tmp_path) -> None:
    from sim.replay import read_log
    from sim.serve import ServeOptions, build_simulation_server

    log = tmp_path / "match.log"
    server, close_log = build_simulation_server(ServeOptions(agent_port=0, monitor_port=0, seed=5,
                                                             log_path=str(log)))
    server.start()
    try:
        agent = Client(server.agent_port)
        agent.send(b"(scene rsg/agent/nao/nao.rsg)")
        first = agent.recv()
        assert first.startswith(b"(time (now ") and b"(GS (sl 0) (sr 0) (t 0.00) (pm BeforeKickOff))" in first
        agent.send(b"(init (unum 7)(teamname Tcp))(syn)")
        messages = []
        for _ in range(6):
            messages.append(agent.recv())
            agent.send(b"(syn)")
        assert any(b"(GS (unum 7) (team left)" in m for m in messages)
        monitor = Client(server.monitor_port)
        full = monitor.recv()
        assert b"(team_left Tcp)" in full and b"matNum7 matLeft matType0" in full
        monitor.send(b"(kickOff Left)")
        deadline = time.monotonic() + 10.0
        while b"(pm KickOff_Left)" not in agent.recv():
            agent.send(b"(syn)")
            assert time.monotonic() < deadline
        agent.send(b"(syn)")
        monitor.close()
        agent.close()
    finally:
        server.stop()
        close_log()
    frames = list(read_log(log))
    assert frames and any("left_7" in frame.robots for frame in frames)
    # A line every 0.2 s, and the state of the last cycle when the log closes (the agent has left by then).
    assert frames[-1].play_mode in (1, 3) and not frames[-1].robots


def test_real_engine_over_tcp_action_in_reply_to_k_shows_in_k_plus_2() -> None:
    from sim.serve import ServeOptions, build_simulation_server

    server, close_log = build_simulation_server(ServeOptions(agent_port=0, monitor_port=None, seed=6))
    server.start()
    try:
        agent = Client(server.agent_port)
        agent.send(b"(scene rsg/agent/nao/nao.rsg)")

        def head_yaw(message: bytes) -> float:
            match = re.search(rb"\(HJ \(n hj1\) \(ax (-?[\d.]+)\)\)", message)
            assert match, message
            return float(match.group(1))

        for _ in range(10):  # past the 4 grace cycles: from now on one message per (syn)
            agent.recv()
            agent.send(b"(syn)")
        agent.sock.settimeout(0.5)
        with pytest.raises(socket.timeout):  # read what is in flight without answering: the server waits
            for _ in range(20):
                agent.recv()
        agent.sock.settimeout(5.0)
        agent.send(b"(syn)")
        k = agent.recv()
        agent.send(b"(he1 2.0)(syn)")
        k1 = agent.recv()
        agent.send(b"(syn)")
        k2 = agent.recv()
        assert head_yaw(k1) == pytest.approx(head_yaw(k), abs=0.05)
        assert head_yaw(k2) > head_yaw(k) + 0.5
        agent.close()
    finally:
        server.stop()
        close_log()
