"""Joining the TCP server in sync mode the way the real rcssserver3d 0.7.3 lets agents join (sim.tcp_server's
docstring has the measured timings): each cycle waits for data from the agents, so a new agent's first
messages come one per answer, never in a burst, and a client that answers once per batch never deadlocks."""

from __future__ import annotations

import select
import socket
import time

from agent.protocol.framing import FrameDecoder, frame
from sim.engine import FrozenReferee, SimEngine
from sim.tcp_server import SimServer
from tests.sim.test_tcp_server import Client, StubEngine, cycle_of

SCENE = b"(scene rsg/agent/nao/nao_hetero.rsg 0)"


class BatchClient:
    """Reads every message waiting, thinks, answers once, then blocks for the next message.

    Its first answer is ``(init ...)`` without ``(syn)`` (some teams' agents join that way); every later
    answer ends in ``(syn)``. `batches` holds the server times [s] of the messages of each read.
    """

    def __init__(self, port: int, think_s: float, timeout_s: float = 5.0) -> None:
        self.sock = socket.create_connection(("127.0.0.1", port), timeout=timeout_s)
        self.sock.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
        self.decoder = FrameDecoder()
        self.think_s = think_s
        self.batches: list[list[float]] = []

    def _drain(self, block: bool) -> list[bytes]:
        messages: list[bytes] = []
        while True:
            if not block or messages:
                ready, _, _ = select.select([self.sock], [], [], 0.0)
                if not ready:
                    return messages
            data = self.sock.recv(65536)  # blocks (up to the socket timeout) for the first message
            if not data:
                raise ConnectionError("server closed")
            messages.extend(self.decoder.feed(data))

    def read_batch(self) -> list[bytes]:
        messages = self._drain(block=True)
        time.sleep(self.think_s)
        messages += self._drain(block=False)  # what came in while thinking belongs to this batch
        self.batches.append([float(m[len(b"(time (now "):m.index(b")")]) for m in messages])
        return messages

    def play(self, cycles: int) -> None:
        self.sock.sendall(frame(SCENE))
        self.read_batch()
        self.sock.sendall(frame(b"(init (unum 1)(teamname Batch))"))
        while sum(len(batch) for batch in self.batches) < cycles:
            self.read_batch()
            self.sock.sendall(frame(b"(he1 0.5)(lae1 -1.0)(syn)"))


def test_a_client_answering_once_per_batch_joins_and_plays_50_cycles() -> None:
    engine = SimEngine(seed=3, referee=FrozenReferee())
    server = SimServer(engine, agent_port=0, sync=True).start()
    client = BatchClient(server.agent_port, think_s=0.01)
    try:
        client.play(60)  # a deadlock shows as socket.timeout here
        assert any(link.team == "Batch" and link.unum == 1 for link in engine.agents.values())
    finally:
        client.sock.close()
        server.stop()
    times = [t for batch in client.batches for t in batch]
    assert len(times) >= 50
    assert all(len(batch) == 1 for batch in client.batches), client.batches[:6]  # one message per answer
    assert all(abs(b - a - 0.02) < 1e-6 for a, b in zip(times, times[1:]))      # no cycle skipped


def test_each_cycle_waits_for_data_from_the_agents_even_in_the_grace_cycles() -> None:
    wait_s = 0.15
    server = SimServer(StubEngine(), agent_port=0, sync=True, sync_read_wait_s=wait_s).start()
    try:
        silent = Client(server.agent_port)
        arrivals = []
        for _ in range(3):  # never answering: one message per read wait, as the real server's 1 s
            silent.recv()
            arrivals.append(time.monotonic())
        assert all(b - a > 0.6 * wait_s for a, b in zip(arrivals, arrivals[1:])), arrivals
        # Any data ends the wait, (syn) or not: the answer to a grace message brings the next one at once.
        silent.send(b"(init (unum 1)(teamname T))")
        start = time.monotonic()
        message = silent.recv()
        assert time.monotonic() - start < 0.5 * wait_s
        # Past the 4 grace messages nothing but (syn) lets the server step, whatever the wait.
        silent.send(b"(say hi)")
        silent.sock.settimeout(3 * wait_s)
        try:
            extra = silent.recv()
        except socket.timeout:
            extra = None
        assert extra is None, extra
        silent.sock.settimeout(5.0)
        silent.send(b"(syn)")
        assert cycle_of(silent.recv()) == cycle_of(message) + 1
        silent.close()
    finally:
        server.stop()
