"""TCP hosting of a simulation: the agent port (3100) and the monitor/trainer port (3200), one thread.

The server owns sockets and the clock, nothing else: any engine-like object with ``connect``,
``disconnect``, ``receive`` and ``step`` runs behind it (sim.engine.SimEngine in practice, a stub in tests).
Frames are agent.protocol's 4-byte big-endian length prefix. Everything runs on one `selectors` loop with
non-blocking sockets, so a client driving several agents can answer them in any order.

Cycle order (REFERENCE §3.9): read sockets and hand actions to the engine at once; step; send what the
step returned. The engine's step hands back the sense messages made at the end of the *previous* step
(sim.engine), which is what makes an action sent in reply to message k show first in message k+2, as on
the real server; the server itself adds no delay.

Sync-mode pacing is the real server's. Measured on rcssserver3d 0.7.3 (sync mode, not real time, one agent on
loopback, `(scene rsg/agent/nao/nao_hetero.rsg 0)` sent on connecting, then `(init ...)` in answer to the first
message), with its source (oxygen's AgentControl::StartCycle and NetControl::ReadTCPMessages): each cycle first
reads the agent sockets, blocking up to 1 s until any agent has sent any bytes (BlockOnReadMessages), drains
what is waiting, and repeats that read until every agent is synced (its `(syn)` read in this cycle, or still in
its first 4 perceptor cycles, counted from the connection); only then does it send the percepts made at the end
of the last cycle and step. So a client that waits for its first message gets it 2.06 s after its scene (the
scene is read at once; then two reads time out after 1 s each: the robot is built in the first cycle, its
first percepts made at the end of the second); from then on each message comes 0.3-1 ms after the client's
answer, one message per answer, through the grace cycles and after, whether the answer holds `(syn)` or only
`(init ...)`; answers sent 0.3 s late bring messages 0.3 s apart; a client that never answers gets 2 messages
1 s apart, then none; a scene sent 2.5 s after connecting gets none (the grace cycles passed while it was
silent). A client that reads all waiting messages and answers once therefore always finds one message.

Here, in sync mode with agents connected, a cycle steps when every agent counts as synced and either some
agent sent bytes since the last step or ``sync_read_wait_s`` (1 s) passed without any. The grace is counted in
sense messages sent instead (a client whose scene comes late still joins). Before this, the grace cycles ran
back to back: 4 messages within 20 ms of the scene, which such a client read as one batch; its `(init ...)`
without `(syn)` then left both sides waiting (tests/sim/test_tcp_join.py: 3 of 3 joins deadlocked).

Bad input never stops the server: a client whose length prefix exceeds ``max_frame_bytes`` (a "negative"
prefix is a huge unsigned one), whose output backlog grows past ``max_backlog_bytes`` or whose socket
fails is logged with its id and dropped; everything inside a frame is the engine's to judge.
"""

from __future__ import annotations

import logging
import re
import selectors
import socket
import threading
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Protocol

from agent.protocol.errors import ProtocolError
from agent.protocol.framing import FrameDecoder, frame
from agent.protocol.constants import CYCLE_S

logger = logging.getLogger(__name__)

DEFAULT_HOST = "127.0.0.1"
DEFAULT_AGENT_PORT = 3100
DEFAULT_MONITOR_PORT = 3200
# REFERENCE §3.9: a new agent counts as synced during its first 4 perceptor cycles. Counted here in sense
# messages sent, so a client that never sends (scene ...) (and so gets no sense) never stalls the server.
SYNC_GRACE_CYCLES = 4
# The real server's read blocks this long for agent data each cycle in sync mode (NetControl::BlockOnReadMessages).
SYNC_READ_WAIT_S = 1.0
# REFERENCE §5.1: monitor updates every 0.04 s = every 2nd cycle.
MONITOR_STEP_CYCLES = 2
# Agents send < 1 kB per cycle; a 64 kB cap still leaves room for the biggest legitimate message and
# drops a client that announces megabytes.
DEFAULT_MAX_AGENT_FRAME_BYTES = 64 * 1024
DEFAULT_MAX_MONITOR_FRAME_BYTES = 64 * 1024
# A client that stops reading gets dropped once this much output is queued for it.
DEFAULT_MAX_BACKLOG_BYTES = 8 * 1024 * 1024
_RECV_BYTES = 65536
_SYN = re.compile(rb"\(\s*syn\s*\)\s*\Z")


class EngineLike(Protocol):
    """What the server needs from a simulation engine (sim.engine.SimEngine implements it)."""

    def connect(self) -> int: ...

    def disconnect(self, agent_id: int) -> None: ...

    def receive(self, agent_id: int, payload: bytes) -> None: ...

    def step(self) -> dict[int, bytes]: ...


class MonitorFeed(Protocol):
    """Monitor output: one `new_stream()` per monitor client, fed one shared snapshot per monitor step."""

    def snapshot(self) -> object: ...

    def new_stream(self) -> MonitorStreamLike: ...


class MonitorStreamLike(Protocol):
    def message(self, snapshot: object, full: bool = False) -> str: ...


@dataclass
class _Client:
    sock: socket.socket
    peer: str
    decoder: FrameDecoder
    backlog: bytearray = field(default_factory=bytearray)
    closed: bool = False


@dataclass
class _Agent(_Client):
    agent_id: int = -1
    synced: bool = False
    cycles: int = 0  # sense messages sent to this agent
    waited_since: float | None = None


@dataclass
class _Monitor(_Client):
    stream: MonitorStreamLike | None = None
    want_full: bool = True


@dataclass
class ServerStats:
    """Counters for logs and tests: cycles stepped, clients accepted and dropped, frames seen."""

    cycles: int = 0
    agents_accepted: int = 0
    monitors_accepted: int = 0
    clients_dropped: int = 0
    agent_frames: int = 0
    monitor_frames: int = 0
    engine_errors: int = 0
    sync_timeouts: int = 0
    loop_errors: int = 0


class SimServer:
    """Serve an engine over TCP.

    Args:
        engine: the simulation (see `EngineLike`).
        host: bind address; loopback by default.
        agent_port: agent port (0 = any free port; read `agent_port` after `bind()`).
        monitor_port: monitor/trainer port, None = no monitor port.
        sync: wait each cycle until every agent sent a frame ending with ``(syn)`` (REFERENCE §3.9).
        real_time: cap the cycle rate at 50 Hz of wall clock; without ``sync`` the server steps every
            20 ms whatever the agents do. Sync without real time runs as fast as the agents answer.
        monitor: monitor output for the monitor port (None = the port only takes trainer commands).
        trainer: called with each frame a monitor client sends (trainer commands); exceptions are logged.
        on_cycle: called after every step with the cycle number (e.g. a monitor log writer).
        sync_timeout_s: in sync mode, stop waiting for an agent after this long (logged, counted);
            None = wait forever, like the real server.
        sync_read_wait_s: in sync mode, with every agent counted as synced (the grace cycles), a cycle waits
            this long for bytes from any agent before it steps anyway [s]; the real server's 1 s (module
            docstring). Capped by ``sync_timeout_s``.
        max_agent_frame_bytes / max_monitor_frame_bytes: largest accepted payload per frame.
        max_backlog_bytes: unsent output per client before it is dropped.
    """

    def __init__(self, engine: EngineLike, *, host: str = DEFAULT_HOST, agent_port: int = DEFAULT_AGENT_PORT,
                 monitor_port: int | None = None, sync: bool = True, real_time: bool = False,
                 monitor: MonitorFeed | None = None, trainer: Callable[[bytes], None] | None = None,
                 on_cycle: Callable[[int], None] | None = None, sync_timeout_s: float | None = None,
                 sync_read_wait_s: float = SYNC_READ_WAIT_S,
                 max_agent_frame_bytes: int = DEFAULT_MAX_AGENT_FRAME_BYTES,
                 max_monitor_frame_bytes: int = DEFAULT_MAX_MONITOR_FRAME_BYTES,
                 max_backlog_bytes: int = DEFAULT_MAX_BACKLOG_BYTES) -> None:
        self.engine = engine
        self.host = host
        self.requested_agent_port = agent_port
        self.requested_monitor_port = monitor_port
        self.sync = sync
        self.real_time = real_time
        self.monitor = monitor
        self.trainer = trainer
        self.on_cycle = on_cycle
        self.sync_timeout_s = sync_timeout_s
        self.sync_read_wait_s = (sync_read_wait_s if sync_timeout_s is None
                                 else min(sync_read_wait_s, sync_timeout_s))
        self.max_agent_frame_bytes = max_agent_frame_bytes
        self.max_monitor_frame_bytes = max_monitor_frame_bytes
        self.max_backlog_bytes = max_backlog_bytes
        self.stats = ServerStats()
        self.agent_port: int | None = None
        self.monitor_port: int | None = None

        self._selector = selectors.DefaultSelector()
        self._listeners: list[socket.socket] = []
        self._agents: dict[socket.socket, _Agent] = {}
        self._monitors: dict[socket.socket, _Monitor] = {}
        self._pending: dict[int, bytes] = {}
        self._agent_data = False              # bytes (or a close) from an agent since the last step
        self._last_step_s = time.monotonic()  # when the last cycle ended [s, monotonic]
        self._stop = threading.Event()
        self._wake_r, self._wake_w = socket.socketpair()
        self._wake_r.setblocking(False)
        self._wake_w.setblocking(False)
        self._thread: threading.Thread | None = None
        self._bound = False
        self._closed = False
        self._running = False

    # ---- lifecycle -----------------------------------------------------------------------------------
    def bind(self) -> None:
        """Open the listening sockets (idempotent)."""
        if self._bound:
            return
        self.agent_port = self._listen(self.requested_agent_port, "agent")
        if self.requested_monitor_port is not None:
            self.monitor_port = self._listen(self.requested_monitor_port, "monitor")
        self._selector.register(self._wake_r, selectors.EVENT_READ, ("wake", None))
        self._bound = True
        logger.info("serving agents on %s:%s%s (%s, %s)", self.host, self.agent_port,
                    f", monitors on port {self.monitor_port}" if self.monitor_port is not None else "",
                    "sync" if self.sync else "no sync", "real time" if self.real_time else "as fast as possible")

    def _listen(self, port: int, kind: str) -> int:
        sock = socket.socket(socket.AF_INET, socket.SOCK_STREAM)
        sock.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
        sock.bind((self.host, port))
        sock.listen(64)
        sock.setblocking(False)
        self._selector.register(sock, selectors.EVENT_READ, ("listen", kind))
        self._listeners.append(sock)
        return sock.getsockname()[1]

    def start(self) -> SimServer:
        """Bind and serve in a daemon thread; returns self (ports are known on return)."""
        self.bind()
        self._thread = threading.Thread(target=self.serve_forever, name="sim-tcp-server", daemon=True)
        self._thread.start()
        return self

    def stop(self, timeout_s: float = 5.0) -> None:
        """Ask the loop to end, wait for its thread (if started with `start`), close every socket."""
        self._stop.set()
        try:
            self._wake_w.send(b"x")
        except OSError:
            pass
        if self._thread is not None and self._thread is not threading.current_thread():
            self._thread.join(timeout_s)
        if not self._running:
            self._close_all()

    @property
    def agent_count(self) -> int:
        return len(self._agents)

    # ---- the loop ------------------------------------------------------------------------------------
    def serve_forever(self) -> None:
        """Run until `stop()`: poll sockets, step when the mode allows it. Exceptions from a client are
        caught per client; an exception from the engine's step is logged and the cycle is skipped."""
        self.bind()
        self._running = True
        next_step = time.monotonic()
        try:
            while not self._stop.is_set():
                try:
                    next_step = self._iterate(next_step)
                except Exception:  # last resort: a bug in the loop must not end the server
                    self.stats.loop_errors += 1
                    logger.exception("server loop error (continuing)")
                    time.sleep(0.01)
        finally:
            self._running = False
            self._close_all()

    def _iterate(self, next_step: float) -> float:
        """One pass of the loop: step if the mode allows it, else wait for sockets; returns the next
        step time."""
        now = time.monotonic()
        if not self._may_step(now, next_step):
            self._poll(self._wait_time(now, next_step))
            return next_step
        self._cycle()
        now = time.monotonic()
        if self.real_time or not self._agents:
            # Without agents nothing paces sync mode: keep 50 Hz instead of spinning a core.
            next_step = max(next_step + CYCLE_S, now - CYCLE_S)
        else:
            next_step = now
        self._poll(0.0)
        return next_step

    def _may_step(self, now: float, next_step: float) -> bool:
        paced = self.real_time or not self._agents
        if paced and now < next_step:
            return False
        if not self.sync:
            return True
        waiting = [agent for agent in self._agents.values() if not self._counts_as_synced(agent)]
        if not waiting:
            # The real server's read: a cycle starts on the agents' data, or after the read wait without any.
            return self._agent_data or not self._agents or now - self._last_step_s >= self.sync_read_wait_s
        if self.sync_timeout_s is None:
            return False
        expired = True
        for agent in waiting:
            if agent.waited_since is None:
                agent.waited_since = now
            if now - agent.waited_since < self.sync_timeout_s:
                expired = False
        if expired:
            self.stats.sync_timeouts += 1
            logger.warning("sync timeout: stepping without (syn) from agent(s) %s",
                           ", ".join(str(agent.agent_id) for agent in waiting))
        return expired

    def _wait_time(self, now: float, next_step: float) -> float | None:
        timeouts = []
        if self.real_time or not self._agents:
            timeouts.append(max(0.0, next_step - now))
        if self.sync and self.sync_timeout_s is not None and self._agents:
            timeouts.append(self.sync_timeout_s / 4.0)
        if (self.sync and self._agents and not self._agent_data
                and all(self._counts_as_synced(agent) for agent in self._agents.values())):
            timeouts.append(max(0.0, self._last_step_s + self.sync_read_wait_s - now))
        if not self.sync and not self.real_time:
            timeouts.append(0.0)
        return min(timeouts) if timeouts else None

    @staticmethod
    def _counts_as_synced(agent: _Agent) -> bool:
        return agent.synced or agent.cycles < SYNC_GRACE_CYCLES

    def _cycle(self) -> None:
        """Step, send what the step returned, count."""
        for agent in self._agents.values():
            agent.synced = False
            agent.waited_since = None
        self._agent_data = False
        try:
            self._pending = self.engine.step()
        except Exception:  # the loop must survive an engine bug; it is logged with its traceback
            self.stats.engine_errors += 1
            logger.exception("engine step failed; cycle skipped")
            self._pending = {}
        self._send_percepts()
        self._last_step_s = time.monotonic()
        self.stats.cycles += 1
        if self.on_cycle is not None:
            try:
                self.on_cycle(self.stats.cycles)
            except Exception:
                logger.exception("on_cycle callback failed")
        if self.stats.cycles % MONITOR_STEP_CYCLES == 0:
            self._send_monitors()

    def _send_percepts(self) -> None:
        pending, self._pending = self._pending, {}  # sending may drop a client, which edits _pending
        if not pending:
            return
        by_id = {agent.agent_id: agent for agent in self._agents.values()}
        for agent_id, payload in pending.items():
            agent = by_id.get(agent_id)
            if agent is not None and not agent.closed:
                agent.cycles += 1
                self._queue(agent, frame(payload))

    def _send_monitors(self) -> None:
        if self.monitor is None or not self._monitors:
            return
        try:
            snapshot = self.monitor.snapshot()
        except Exception:
            logger.exception("monitor snapshot failed")
            return
        for monitor in list(self._monitors.values()):
            self._send_monitor_message(monitor, snapshot)

    def _send_monitor_message(self, monitor: _Monitor, snapshot: object) -> None:
        assert self.monitor is not None
        if monitor.stream is None:
            monitor.stream = self.monitor.new_stream()
        try:
            text = monitor.stream.message(snapshot, full=monitor.want_full)
        except Exception:
            logger.exception("monitor message for %s failed", monitor.peer)
            return
        monitor.want_full = False
        self._queue(monitor, frame(text.encode("ascii", "replace")))

    # ---- sockets -------------------------------------------------------------------------------------
    def _poll(self, timeout: float | None) -> None:
        for key, events in self._selector.select(timeout):
            kind, info = key.data
            if kind == "wake":
                try:
                    self._wake_r.recv(4096)
                except OSError:
                    pass
            elif kind == "listen":
                self._accept(key.fileobj, info)  # type: ignore[arg-type]
            else:
                client = info
                if events & selectors.EVENT_READ and not client.closed:
                    self._read(client)
                if events & selectors.EVENT_WRITE and not client.closed:
                    self._flush(client)

    def _accept(self, listener: socket.socket, kind: str) -> None:
        try:
            sock, address = listener.accept()
        except (BlockingIOError, InterruptedError):
            return
        except OSError as error:
            logger.warning("accept on the %s port failed: %s", kind, error)
            return
        sock.setblocking(False)
        sock.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
        peer = f"{address[0]}:{address[1]}"
        client: _Client
        if kind == "agent":
            try:
                agent_id = self.engine.connect()
            except Exception:
                logger.exception("engine refused a connection from %s", peer)
                sock.close()
                return
            client = _Agent(sock, peer, FrameDecoder(self.max_agent_frame_bytes), agent_id=agent_id)
            self._agents[sock] = client  # type: ignore[assignment]
            self.stats.agents_accepted += 1
            logger.info("agent %d connected from %s", agent_id, peer)
        else:
            client = _Monitor(sock, peer, FrameDecoder(self.max_monitor_frame_bytes))
            self._monitors[sock] = client  # type: ignore[assignment]
            self.stats.monitors_accepted += 1
            logger.info("monitor connected from %s", peer)
        self._selector.register(sock, selectors.EVENT_READ, ("client", client))
        if isinstance(client, _Monitor) and self.monitor is not None:
            # A full state at once, as the real server does; a sync-mode server may be waiting for agents.
            try:
                snapshot = self.monitor.snapshot()
            except Exception:
                logger.exception("monitor snapshot failed")
                return
            self._send_monitor_message(client, snapshot)

    def _read(self, client: _Client) -> None:
        try:
            data = client.sock.recv(_RECV_BYTES)
        except (BlockingIOError, InterruptedError):
            return
        except ConnectionResetError:
            self._drop(client, "connection reset by the peer", level=logging.INFO)
            return
        except OSError as error:
            self._drop(client, f"receive failed: {error}")
            return
        if isinstance(client, _Agent):
            self._agent_data = True
        if not data:
            if client.decoder.pending_bytes:
                self._drop(client, f"closed the connection inside a frame ({client.decoder.pending_bytes} bytes "
                                   "of it received)")
            else:
                self._drop(client, "closed the connection", level=logging.INFO)
            return
        try:
            payloads = client.decoder.feed(data)
        except ProtocolError as error:
            self._drop(client, f"bad frame: {error}")
            return
        for payload in payloads:
            if client.closed:
                return
            if isinstance(client, _Agent):
                self._on_agent_frame(client, payload)
            else:
                self._on_monitor_frame(client, payload)  # type: ignore[arg-type]

    def _on_agent_frame(self, agent: _Agent, payload: bytes) -> None:
        self.stats.agent_frames += 1
        try:
            self.engine.receive(agent.agent_id, payload)
        except Exception:  # the engine promises not to raise; a bug there must not take the server down
            self.stats.engine_errors += 1
            logger.exception("engine.receive raised for agent %d (payload %r)", agent.agent_id, payload[:80])
        if _SYN.search(payload):
            agent.synced = True

    def _on_monitor_frame(self, monitor: _Monitor, payload: bytes) -> None:
        self.stats.monitor_frames += 1
        text = payload.strip()
        if text == b"(reqfullstate)":
            monitor.want_full = True
        elif text == b"(killsim)":
            logger.info("killsim from monitor %s", monitor.peer)
            self._stop.set()
            return
        if self.trainer is None:
            return
        try:
            self.trainer(payload)
        except ProtocolError as error:
            logger.warning("trainer message from %s rejected: %s", monitor.peer, error)
        except Exception:
            logger.exception("trainer command from %s failed: %r", monitor.peer, payload[:80])

    def _queue(self, client: _Client, data: bytes) -> None:
        if client.closed:
            return
        client.backlog += data
        if len(client.backlog) > self.max_backlog_bytes:
            self._drop(client, f"not reading: {len(client.backlog)} bytes queued")
            return
        self._flush(client)

    def _flush(self, client: _Client) -> None:
        while client.backlog and not client.closed:
            try:
                sent = client.sock.send(client.backlog)
            except (BlockingIOError, InterruptedError):
                break
            except OSError as error:
                self._drop(client, f"send failed: {error}")
                return
            del client.backlog[:sent]
        if client.closed:
            return
        events = selectors.EVENT_READ | (selectors.EVENT_WRITE if client.backlog else 0)
        try:
            self._selector.modify(client.sock, events, ("client", client))
        except (KeyError, ValueError, OSError):
            pass

    def _drop(self, client: _Client, reason: str, level: int = logging.WARNING) -> None:
        if client.closed:
            return
        client.closed = True
        if isinstance(client, _Agent):
            logger.log(level, "agent %d (%s) dropped: %s", client.agent_id, client.peer, reason)
            self._agent_data = True   # a closed socket ends the real server's read too
            self._agents.pop(client.sock, None)
            self._pending.pop(client.agent_id, None)
            try:
                self.engine.disconnect(client.agent_id)
            except Exception:
                logger.exception("engine.disconnect(%d) failed", client.agent_id)
        else:
            logger.log(level, "monitor %s dropped: %s", client.peer, reason)
            self._monitors.pop(client.sock, None)
        if level >= logging.WARNING:
            self.stats.clients_dropped += 1
        try:
            self._selector.unregister(client.sock)
        except (KeyError, ValueError):
            pass
        client.sock.close()

    def _close_all(self) -> None:
        if self._closed:
            return
        self._closed = True
        for client in list(self._agents.values()) + list(self._monitors.values()):
            self._drop(client, "server stopped", level=logging.INFO)
        for sock in self._listeners:
            try:
                self._selector.unregister(sock)
            except (KeyError, ValueError):
                pass
            sock.close()
        self._listeners.clear()
        for sock in (self._wake_r, self._wake_w):
            try:
                sock.close()
            except OSError:
                pass
        self._selector.close()

