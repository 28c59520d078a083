"""Fuzzing the TCP server on loopback: thousands of mutated, random and malformed frames, bad prefixes,
partial frames and abrupt disconnects on the agent and monitor ports, while one well-behaved agent must keep
getting an intact sense message every cycle. Bounded in count and in time; only 127.0.0.1."""

from __future__ import annotations

import json
import random
import socket
import struct
import threading
import time
from pathlib import Path

import pytest

from agent.protocol import ProtocolError, parse_actions, parse_sense
from agent.protocol.framing import FrameDecoder, frame
from sim.engine import SimEngine
from sim.referee import Referee
from sim.rules.trainer import apply_trainer_message
from sim.tcp_server import SimServer
from tests.sim.test_referee_rules import FakeWorld

SAMPLES = Path(__file__).resolve().parents[3] / "shared" / "samples"  # <project>/../shared/samples
MAX_MESSAGES = 20000
TIME_BUDGET_S = 25.0
# With the MuJoCo engine every fuzz (scene ...) builds a robot (a model recompile), so fewer messages.
MAX_MESSAGES_REAL_ENGINE = 6000
TIME_BUDGET_REAL_ENGINE_S = 20.0


class ParsingEngine:
    """A stub engine that parses every action with agent.protocol (as the real engine must) and
    reports each cycle's number, so the good agent can check that nothing is lost or altered."""

    def __init__(self) -> None:
        self.next_id = 0
        self.connected: set[int] = set()
        self.cycle = 0
        self.rejected = 0
        self.parsed = 0

    def connect(self) -> int:
        self.next_id += 1
        self.connected.add(self.next_id)
        return self.next_id

    def disconnect(self, agent_id: int) -> None:
        self.connected.discard(agent_id)

    def receive(self, agent_id: int, payload: bytes) -> None:
        try:
            parse_actions(payload)
            self.parsed += 1
        except ProtocolError:
            self.rejected += 1

    def step(self) -> dict[int, bytes]:
        self.cycle += 1
        return {i: b"(time (now %.2f))(cyc %d)(for %d)" % (self.cycle * 0.02, self.cycle, i)
                for i in self.connected}


def corpus() -> list[bytes]:
    messages = [b"(syn)", b"(he1 0.5)(syn)", b"(beam -2.5 0 0)(syn)", b"(init (unum 3)(teamname T))",
                b"(say hello)(syn)", b"(pass)(syn)", b"(scene rsg/agent/nao/nao.rsg)"]
    path = SAMPLES / "rcssserver3d-0.7.3_two_agents.jsonl"
    if path.exists():
        for line in path.read_text().splitlines()[:200]:
            messages.append(json.loads(line)["msg"].encode())
    monitor = SAMPLES / "rcssserver3d-0.7.3_monitor_first_frames.txt"
    if monitor.exists():
        messages.extend(line.encode()[:3000] for line in monitor.read_text().splitlines() if line)
    return messages


def mutate(rng: random.Random, message: bytes) -> bytes:
    data = bytearray(message)
    for _ in range(rng.randint(1, 6)):
        choice = rng.random()
        position = rng.randrange(len(data) + 1)
        if choice < 0.2 and data:
            data[rng.randrange(len(data))] = rng.randrange(256)
        elif choice < 0.35:
            data[position:position] = rng.choice([b"(", b")", b"((", b"))", b" ", b"\x00", b"\xff"])
        elif choice < 0.5 and data:
            del data[position:position + rng.randint(1, 20)]
        elif choice < 0.65:
            data[position:position] = rng.choice([b"nan", b"-inf", b"inf", b"1e308", b"-0", b"NaN", b"1e-400",
                                                  b"99999999999999999999"])
        elif choice < 0.75:
            data[position:position] = rng.choice([b"(lle99 1)", b"(foo)", b"(he1)", b"(he1 1 2 3)",
                                                  b"(beam nan nan nan)", b"(say " + b"x" * 40 + b")"])
        elif choice < 0.85:
            data = data[: rng.randrange(len(data) + 1)]
        else:
            data[position:position] = bytes(rng.randrange(256) for _ in range(rng.randint(1, 30)))
    return bytes(data)


class GoodAgent(threading.Thread):
    """Answers every sense message with (syn) and checks the stream: one message per cycle (server time
    up by exactly 20 ms each time), each one a well-formed sense message (the stub's: its own id)."""

    def __init__(self, port: int, real_engine: bool) -> None:
        super().__init__(daemon=True)
        self.sock = socket.create_connection(("127.0.0.1", port), timeout=10.0)
        self.real_engine = real_engine
        self.cycles: list[int] = []
        self.problems: list[str] = []
        self.stop = threading.Event()

    def run(self) -> None:
        decoder = FrameDecoder()
        my_id = None
        try:
            if self.real_engine:
                self.sock.sendall(frame(b"(scene rsg/agent/nao/nao.rsg)"))
            while not self.stop.is_set():
                data = self.sock.recv(65536)
                if not data:
                    if not self.stop.is_set():
                        self.problems.append("server closed the good agent")
                    return
                for payload in decoder.feed(data):
                    cycle = round(float(payload[len(b"(time (now "):payload.index(b")")]) / 0.02)
                    if self.real_engine:
                        parse_sense(payload)  # raises on anything malformed
                        reply = b"(he1 0.1)(syn)" if self.cycles else b"(init (unum 5)(teamname Good))(syn)"
                    else:
                        agent = int(payload.split(b")(")[2].split()[1].rstrip(b")"))
                        my_id = agent if my_id is None else my_id
                        if agent != my_id:
                            self.problems.append(f"someone else's message {payload!r}")
                        reply = b"(he1 0.1)(syn)"
                    if self.cycles and cycle != self.cycles[-1] + 1:
                        self.problems.append(f"cycle {cycle} after {self.cycles[-1]}: {payload[:60]!r}")
                    self.cycles.append(cycle)
                    self.sock.sendall(frame(reply))
        except (OSError, ValueError, IndexError) as error:
            if not self.stop.is_set():
                self.problems.append(f"good agent failed: {error!r}")


def send_quietly(sock: socket.socket, data: bytes) -> bool:
    try:
        sock.sendall(data)
        return True
    except OSError:
        return False


@pytest.mark.parametrize("real_engine", [False, True], ids=["stub-engine", "sim-engine"])
def test_fuzzed_clients_never_disturb_a_good_agent(real_engine: bool) -> None:
    rng = random.Random(20260 + real_engine)
    messages = corpus()
    if real_engine:
        engine = SimEngine(seed=11)
        referee, world = engine.referee, engine.world
        max_messages, budget_s = MAX_MESSAGES_REAL_ENGINE, TIME_BUDGET_REAL_ENGINE_S
    else:
        engine = ParsingEngine()
        referee, world = Referee(seed=1), FakeWorld()
        world.add("left", 1, -14.0, 0.0)
        max_messages, budget_s = MAX_MESSAGES, TIME_BUDGET_S

    def trainer(payload: bytes) -> None:
        try:
            apply_trainer_message(payload, referee, world)
        except ProtocolError:
            pass

    server = SimServer(engine, agent_port=0, monitor_port=0, sync=True, real_time=False, trainer=trainer,
                       sync_timeout_s=0.05).start()
    good = GoodAgent(server.agent_port, real_engine)
    good.start()
    sent = 0
    start = time.monotonic()
    open_clients: list[socket.socket] = []
    try:
        while sent < max_messages and time.monotonic() - start < budget_s:
            port = server.monitor_port if rng.random() < 0.2 else server.agent_port
            sock = socket.create_connection(("127.0.0.1", port), timeout=2.0)
            if port == server.agent_port and rng.random() < 0.3:
                # A real robot for some fuzzers: scene (any type), maybe init into one of three teams.
                send_quietly(sock, frame(b"(scene rsg/agent/nao/nao_hetero.rsg %d)" % rng.randrange(6)))
                if rng.random() < 0.6:
                    send_quietly(sock, frame(b"(init (unum %d)(teamname %s))(syn)"
                                             % (rng.randrange(13), rng.choice([b"Good", b"Fuzz", b"Third"]))))
            for _ in range(rng.randint(1, 25)):
                kind = rng.random()
                if kind < 0.7:
                    payload = mutate(rng, rng.choice(messages))
                    data = frame(payload)
                elif kind < 0.8:
                    data = frame(bytes(rng.randrange(256) for _ in range(rng.randint(0, 200))))
                elif kind < 0.82:
                    data = struct.pack(">I", rng.choice([0xFFFFFFFF, 0x80000000, 2 ** 31 + 5, 10 ** 8]))
                elif kind < 0.84:
                    data = frame(rng.choice(messages))[: rng.randint(1, 8)]  # a partial frame
                elif kind < 0.86:
                    data = bytes(rng.randrange(256) for _ in range(rng.randint(1, 64)))  # no framing at all
                else:
                    data = frame(rng.choice(messages))
                    if rng.random() < 0.5:  # split into pieces sent separately
                        cut = rng.randrange(len(data) + 1)
                        send_quietly(sock, data[:cut])
                        data = data[cut:]
                sent += 1
                if not send_quietly(sock, data):
                    break
            if rng.random() < 0.15 and len(open_clients) < 20:
                open_clients.append(sock)  # stays connected, silent, while others come and go
            else:
                sock.close()
            if len(open_clients) >= 20:
                open_clients.pop(0).close()
        elapsed = time.monotonic() - start
        cycles_before = len(good.cycles)
        time.sleep(0.3)
        assert len(good.cycles) > cycles_before, "the server stopped stepping"
    finally:
        for sock in open_clients:
            sock.close()
        good.stop.set()
        server.stop()
        good.sock.close()
        good.join(5.0)
    assert sent >= 1000 or elapsed >= budget_s
    assert not good.problems, good.problems[:5]
    # Silent fuzz clients hold each cycle for the 50 ms sync timeout, so expect at least 10 cycles/s.
    assert len(good.cycles) >= min(100, 10 * elapsed), (len(good.cycles), elapsed)
    assert server.stats.clients_dropped > 10 and server.stats.agents_accepted > 100
    if real_engine:
        assert sum(engine.errors.values()) > 100  # logged and counted, never raised
    else:
        assert engine.rejected > 0 and engine.parsed > 0
