"""Our full soccer agent in a small match on the real rcssserver3d 0.7.3 and on our simulator: the matches as
played (``motion-studio real match``; match_figures.py measures them).

The real match: a fresh server (process.RealServer: sync mode, not real time, a monitor frame every cycle) in a
private network namespace; the agents run in this process, one thread each, through the transport of ``python
-m agent`` (``agent.runner.run``: framing, malformed-message policy, reconnects) with the soccer agent of
``agent.player`` and the robot types of ``--type auto`` (``agent.team.composition``). They connect one after
another (left 1, right 1, left 2, ...; robots built in the same cycle knock each other over), wait
KICK_OFF_WAIT_S of server time in BeforeKickOff, then the monitor sends ``(kickOff <side>)`` (REFERENCE §5.2)
and the game runs for the match's duration of game time (at half time the other side kicks off the second
half the same way, ``second_half_kick_off``); the first agent stops answering then, so the match
ends on that cycle. Our match: ``sim.match.run_match`` with the same players, types, duration and the agents of
``motion_studio.match_agents.make_agent`` (its coin toss picks the kicking side; the real match then kicks off
with the same side). Each agent is wrapped (``Watched``) to count its exceptions (answered with ``(syn)``, as
sim/match.py's CrashGuard does; ``python -m agent`` would have died), the motions it started and its belief.
With ``cli`` the real match is played by ``python -m agent --team T --unum N --type auto`` processes instead.
"""

from __future__ import annotations

import collections
import logging
import re
import signal
import subprocess
import sys
import threading
import time
import traceback
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from motion_studio.realserver.paths import PROJECT_DIR
from motion_studio.realserver.process import AGENT_PORT, MonitorLink, RealServer
from agent.protocol.constants import CYCLE_S

#: Server time the agents get in BeforeKickOff after the last one connected [s] (sim.match.MatchConfig default).
KICK_OFF_WAIT_S = 3.0
#: Cycles each new agent plays before the next connects (sim.match.run_match connects one per 2 cycles).
CONNECT_GAP_CYCLES = 3
#: A ball step longer than this between two monitor frames is a referee placement, not play [m].
BALL_TELEPORT_M = 1.0
LEFT_TEAM, RIGHT_TEAM = "Left", "Right"
#: The motions that kick (kick_step_* are the line-up steps before a kick).
KICK_MOTIONS = frozenset({"kick", "kick_left", "kick_strong", "kick_strong_left"})
#: A kick's effect: the ball's move from the kick's start to this much later [s].
KICK_EFFECT_S = 3.0


# ---- the agents, watched ---------------------------------------------------------------------------------
@dataclass
class Belief:
    game_time_s: float
    x_m: float
    y_m: float
    heading_rad: float


class Watched:
    """An agent with what the check wants from it: exceptions (the cycle answered with ``(syn)``), motion
    starts, its world-frame belief each cycle of running game time, cycles played. Everything else (``world``,
    ``said``: agent.runner's status line) is the agent's."""

    def __init__(self, make: Any, team: str, unum: int, robot_type: int, catch_protocol: bool) -> None:
        self.make, self.team, self.unum, self.robot_type = make, team, unum, robot_type
        self.catch_protocol = catch_protocol
        self.agent: Any = None
        self.connections = 0
        self.cycles = 0
        self.errors = 0
        self.bad_messages = 0
        self.tracebacks: list[str] = []
        self.motion_starts: collections.Counter[str] = collections.Counter()
        self.kicks: list[tuple[float, str]] = []
        """(game time, motion) of each kick started (KICK_MOTIONS)."""
        self._playing: str | None = None
        self.beliefs: list[Belief] = []
        self.first_localized_s: float | None = None
        """Server time from the first sense message to the first localized cycle [s]."""
        self._first_server_s: float | None = None
        self.hold_at_game_s: float | None = None
        """Game time at which this agent stops answering until ``hold`` is set (the real match ends exactly
        there: in sync mode the server waits for it)."""
        self.hold = threading.Event()
        self.attach()

    @property
    def name(self) -> str:
        return f"{self.team}_{self.unum}"

    def attach(self) -> None:
        self.agent = self.make(self.team, self.unum, self.robot_type)

    def connection(self, _config: Any = None) -> "Watched":
        """agent.runner.run's ``make_agent``: the agent made at construction, then a fresh one per reconnection."""
        if self.connections > 0:
            self.attach()
        self.connections += 1
        return self

    def __getattr__(self, name: str) -> Any:
        return getattr(self.agent, name)

    def connect_message(self) -> bytes:
        return self.agent.connect_message()

    def step(self, sense: bytes) -> bytes:
        from agent.protocol.errors import ProtocolError

        self.cycles += 1
        try:
            reply = self.agent.step(sense)
        except ProtocolError:
            self.bad_messages += 1
            if not self.catch_protocol:
                raise  # agent.runner.serve counts it, logs it and answers (syn)
            return b"(syn)"
        except Exception:  # noqa: BLE001 - the check reports it; python -m agent would have died here
            self.errors += 1
            if len(self.tracebacks) < 3:
                self.tracebacks.append(traceback.format_exc())
            return b"(syn)"
        self._observe()
        if self.hold_at_game_s is not None and self.agent.world.game.game_time_s >= self.hold_at_game_s:
            self.hold.wait(60.0)
        return reply

    def _observe(self) -> None:
        behavior = self.agent.behavior
        motion = getattr(behavior, "motion", None)
        name = motion.motion_name if motion is not None else None
        if name is not None and name != self._playing:
            self.motion_starts[name] += 1
            if name in KICK_MOTIONS:
                self.kicks.append((self.agent.world.game.game_time_s, name))
        self._playing = name
        world = self.agent.world
        if self._first_server_s is None:
            self._first_server_s = world.game.server_time_s
        if world.localized and self.first_localized_s is None:
            self.first_localized_s = world.game.server_time_s - self._first_server_s
        if world.game.game_time_s > 0 and world.localized:
            pose = world.world_pose()
            self.beliefs.append(Belief(world.game.game_time_s, pose.x_m, pose.y_m, pose.heading_rad))


@dataclass(frozen=True)
class MatchSetup:
    """What is played: players per team (1-11), game time [s], robot types by unum (cycled; None: those of
    ``--type auto``), cycles each in-process real agent plays before the next connects."""

    players: int = 3
    duration_s: float = 120.0
    types: tuple[int, ...] | None = None
    connect_gap_cycles: int = CONNECT_GAP_CYCLES
    left: str = "ours"
    """The left team's kind (``motion_studio.match_agents.TEAM_KINDS``: ours, baseline, solo, standing)."""
    right: str = "ours"
    """The right team's kind."""


def second_half_kick_off(play_mode: str, game_time_s: float, first_kick_off: str, waited_cycles: int) -> str | None:
    """The side to send ``(kickOff <side>)`` for now, or None. Why: at half time (300 s) the real server goes back
    to BeforeKickOff and waits for the monitor, as for the first kick-off; without it a 600 s match stood still
    there for good (2026-11-26: 22 robots in BeforeKickOff from game time 300 s on). With 0.7.3's
    ``ChangeSidesInSecondHalf`` false (naosoccersim.rb) the other team kicks off the second half
    (gamestateaspect.cpp), after ``KICK_OFF_WAIT_S`` as the first one."""
    if play_mode != "BeforeKickOff" or game_time_s <= 0.0 or waited_cycles < round(KICK_OFF_WAIT_S / CYCLE_S):
        return None
    return "Right" if first_kick_off == "Left" else "Left"


#: The first ``(kickOff <side>)`` is sent again while the game has not started this long after it [s] ...
KICK_OFF_RESEND_S = 2.0
#: ... at most this many times.
KICK_OFF_RESENDS = 3


def kick_off_lost(play_mode: str, game_time_s: float, cycles_since_sent: int, resends: int) -> bool:
    """True: send the first ``(kickOff <side>)`` again. Why: once (3 v 3 at 1ec7418, seed 26, with the test suite
    running beside it) the real server logged 5,704 "MonitorControl send ... Resource temporarily unavailable",
    the game never left BeforeKickOff and the match was 120 s of robots waiting. Only while the clock agent still
    sees BeforeKickOff at game time 0 ``KICK_OFF_RESEND_S`` after the last send: a kick-off taken starts the game
    clock, and a ``kickOff`` sent in another play mode would restart the game."""
    return (play_mode == "BeforeKickOff" and game_time_s <= 0.0 and resends < KICK_OFF_RESENDS
            and cycles_since_sent >= round(KICK_OFF_RESEND_S / CYCLE_S))


def lineup(setup: MatchSetup) -> list[tuple[str, int, int]]:
    """(team, unum, robot type) in connection order, the types of ``python -m agent --type auto`` (or
    ``setup.types``)."""
    from agent.team.composition import robot_type_for

    def robot_type(unum: int) -> int:
        return robot_type_for(unum) if setup.types is None else setup.types[(unum - 1) % len(setup.types)]

    return [(team, unum, robot_type(unum)) for unum in range(1, setup.players + 1)
            for team in (LEFT_TEAM, RIGHT_TEAM)]


def _soccer(team: str, unum: int, robot_type: int) -> Any:
    from motion_studio.match_agents import make_agent

    return make_agent(team, unum, robot_type)


def _side_factory(setup: MatchSetup) -> Any:
    """The agent factory of the setup's two team kinds (sides told apart by team name)."""
    from motion_studio.match_agents import SideAgents

    return SideAgents(setup.left, setup.right, LEFT_TEAM)


class LogCounter(logging.Handler):
    """Warnings and errors the agents' modules logged (e.g. agent.runner's skipped malformed messages)."""

    def __init__(self) -> None:
        super().__init__(logging.WARNING)
        self.counts: collections.Counter[str] = collections.Counter()
        self.first: list[str] = []

    def emit(self, record: logging.LogRecord) -> None:
        self.counts[f"{record.levelname} {record.name}"] += 1
        if len(self.first) < 5:
            self.first.append(f"{record.levelname} {record.name}: {record.getMessage()}"[:300])


# ---- the real match ------------------------------------------------------------------------------------
@dataclass
class Played:
    """One match as played: the monitor log, the watched agents and what the host reported."""

    where: str
    monitor_log: Path
    agents: list[Watched]
    wall_s: float
    kick_off: str
    lineup: list[tuple[str, int, int]]
    until_s: float
    """Game time the match was meant to last: later monitor frames are left out (a server whose agents
    stopped runs on as fast as it can until it is stopped)."""
    notes: dict[str, Any] = field(default_factory=dict)


def run_real(setup: MatchSetup, kick_off: str, scripts: Path, out: Path) -> Played:
    """The real match with the agents in this process (this process inside netns.sh's namespace)."""
    from agent.agent import AgentConfig
    from agent.runner import ConnectionPolicy, run

    duration_s = setup.duration_s
    counter = LogCounter()
    logging.getLogger().addHandler(counter)
    server = RealServer(scripts, out / "real_server.log")
    stop = threading.Event()
    agents: list[Watched] = []
    outcomes: dict[str, Any] = {}
    threads: list[threading.Thread] = []
    notes: dict[str, Any] = {}
    started = time.perf_counter()
    monitor = None
    try:
        time.sleep(1.0)
        monitor = MonitorLink()
        factory = _side_factory(setup)
        for team, unum, robot_type in lineup(setup):
            watched = Watched(factory, team, unum, robot_type, catch_protocol=False)
            config = AgentConfig(team=team, unum=unum, robot_type=robot_type)

            def play(watched: Watched = watched, config: AgentConfig = config) -> None:
                try:
                    outcomes[watched.name] = run(config, "127.0.0.1", AGENT_PORT, ConnectionPolicy(connect_attempts=10),
                                                 stop, make_agent=watched.connection)
                except Exception as error:  # noqa: BLE001 - reported
                    outcomes[watched.name] = error

            thread = threading.Thread(target=play, name=watched.name, daemon=True)
            agents.append(watched)
            threads.append(thread)
            thread.start()
            deadline = time.monotonic() + 30.0
            while watched.cycles < setup.connect_gap_cycles and time.monotonic() < deadline and thread.is_alive():
                time.sleep(0.001)
            if watched.cycles < setup.connect_gap_cycles:
                notes.setdefault("connect problems", []).append(f"{watched.name}: {watched.cycles} cycles after 30 s")
        clock = agents[0]
        clock.hold = stop
        clock.hold_at_game_s = duration_s
        wait_until = clock.cycles + round(KICK_OFF_WAIT_S / CYCLE_S)
        deadline = time.monotonic() + 120.0
        while clock.cycles < wait_until and time.monotonic() < deadline:
            time.sleep(0.02)
        notes["before kick-off"] = {w.name: w.world.game.play_mode for w in agents}
        monitor.send(f"(kickOff {kick_off})")
        kick_off_sent, resends = clock.cycles, 0
        wall_limit = time.monotonic() + max(600.0, 30.0 * duration_s)
        last_cycles, last_change = -1, time.monotonic()
        half_time_since: int | None = None  # clock cycle the second half's BeforeKickOff was first seen
        while time.monotonic() < wall_limit:
            game = clock.world.game
            if game.game_time_s >= duration_s or game.play_mode == "GameOver":
                break
            if kick_off_lost(game.play_mode, game.game_time_s, clock.cycles - kick_off_sent, resends):
                monitor.send(f"(kickOff {kick_off})")
                kick_off_sent, resends = clock.cycles, resends + 1
                notes["kick-off resent"] = f"{resends} time(s): still BeforeKickOff at game time 0"
            if half_time_since is None and game.play_mode == "BeforeKickOff" and game.game_time_s > 0.0:
                half_time_since = clock.cycles
            side = (second_half_kick_off(game.play_mode, game.game_time_s, kick_off, clock.cycles - half_time_since)
                    if half_time_since is not None and "second half" not in notes else None)
            if side is not None:
                monitor.send(f"(kickOff {side})")
                notes["second half"] = f"(kickOff {side}) at game time {game.game_time_s:.2f}"
            if clock.cycles != last_cycles:
                last_cycles, last_change = clock.cycles, time.monotonic()
            elif time.monotonic() - last_change > 20.0:
                notes["stalled"] = f"no cycle for 20 s at game time {game.game_time_s:.2f}"
                break
            time.sleep(0.05)
        else:
            notes["wall limit"] = f"stopped at game time {clock.world.game.game_time_s:.2f}"
        wall_s = time.perf_counter() - started
        played_log_bytes = (out / "real_server.log").stat().st_size  # what follows is the shutdown's
        stop.set()
    finally:
        stop.set()
        if monitor is not None:
            monitor.close()   # before the server ends: its end is no monitor failure
        server.stop()
        for thread in threads:
            thread.join(15)
        logging.getLogger().removeHandler(counter)
    log_path = out / "real_monitor.log"
    log_path.write_bytes(b"\n".join(monitor.frames) + b"\n" if monitor is not None else b"")
    if monitor is not None and monitor.failure:
        notes["monitor"] = monitor.failure  # the log (the match's truth) ends there
    notes["runner"] = {name: (f"{type(o).__name__}: {o}" if isinstance(o, Exception) else
                              {"cycles": o.cycles, "connections": o.connections, "malformed": o.bad_messages,
                               "lost connections": o.lost_connections}) for name, o in outcomes.items()}
    notes["logged warnings"] = dict(counter.counts)
    notes["first warnings"] = counter.first
    headless = ("OpenGLServer", "TextureServer", "FPSController")  # a server without a display says these
    played_log = (out / "real_server.log").read_bytes()[:played_log_bytes].decode(errors="replace")
    notes["server errors"] = dict(collections.Counter(
        line.strip()[:160] for line in played_log.splitlines()
        if "error" in line.lower() and not any(h in line for h in headless)))
    return Played("real", log_path, agents, wall_s, kick_off, lineup(setup), duration_s, notes)


def run_real_cli(setup: MatchSetup, kick_off: str, scripts: Path, out: Path) -> Played:
    """The real match with ``python -m agent --team T --unum N --type auto`` processes (the code this process
    runs), as a person would start them; only the monitor measures (the agents' own figures are unknown), the
    notes keep each process's exit code and what its log says about trouble."""
    duration_s = setup.duration_s
    server = RealServer(scripts, out / "real_server.log")
    processes: list[tuple[str, subprocess.Popen, Path]] = []
    notes: dict[str, Any] = {}
    started = time.perf_counter()
    monitor = None
    time_pattern = re.compile(rb"\(time ([0-9.]+)\)")

    def game_time() -> float:
        found = time_pattern.search(monitor.frames[-1][:200]) if monitor and monitor.frames else None
        return float(found.group(1)) if found else 0.0

    try:
        time.sleep(1.0)
        monitor = MonitorLink()
        for team, unum, _ in lineup(setup):
            log = out / f"cli_{team}_{unum}.log"
            command = [sys.executable, "-m", "agent", "--team", team, "--unum", str(unum), "--type", "auto"]
            process = subprocess.Popen(command, cwd=PROJECT_DIR, stdout=subprocess.DEVNULL, stderr=open(log, "w"))
            processes.append((f"{team}_{unum}", process, log))
            deadline = time.monotonic() + 30.0
            while "connected to" not in log.read_text(errors="replace") and time.monotonic() < deadline \
                    and process.poll() is None:
                time.sleep(0.05)
            time.sleep(0.3)  # a few cycles before the next robot is built
        time.sleep(KICK_OFF_WAIT_S)  # wall time: at least as much server time (the server runs faster)
        monitor.send(f"(kickOff {kick_off})")
        wall_limit = time.monotonic() + max(600.0, 30.0 * duration_s)
        while time.monotonic() < wall_limit and game_time() < duration_s:
            time.sleep(0.02)
        wall_s = time.perf_counter() - started
    finally:
        for _, process, _ in processes:  # the agents first: the server's end would make them reconnect
            if process.poll() is None:
                process.send_signal(signal.SIGINT)
        for _, process, _ in processes:
            try:
                process.wait(10)
            except subprocess.TimeoutExpired:
                process.kill()
                process.wait(5)
        if monitor is not None:
            monitor.close()   # before the server ends: its end is no monitor failure
        server.stop()
    log_path = out / "real_monitor.log"
    log_path.write_bytes(b"\n".join(monitor.frames) + b"\n")
    if monitor.failure:
        notes["monitor"] = monitor.failure  # the log (the match's truth) ends there
    trouble = ("Traceback", "WARNING", "ERROR", "lost", "malformed", "timed out")
    notes["processes"] = {}
    for name, process, log in processes:
        text = log.read_text(errors="replace")
        notes["processes"][name] = {"exit code": process.returncode,
                                    "connections": text.count("connected to 127.0.0.1"),
                                    **{word: text.count(word) for word in trouble if word in text}}
    return Played("real (python -m agent)", log_path, [], wall_s, kick_off, lineup(setup), duration_s, notes)


# ---- our match ----------------------------------------------------------------------------------------
def run_ours(setup: MatchSetup, seed: int, out: Path) -> Played:
    """Our match (sim.match.run_match) with the same players, types and duration."""
    from sim.match import MatchConfig, run_match

    players, duration_s = setup.players, setup.duration_s
    agents: list[Watched] = []

    factory = _side_factory(setup)

    def make(team: str, unum: int, robot_type: int) -> Watched:
        watched = Watched(factory, team, unum, robot_type, catch_protocol=True)
        agents.append(watched)
        return watched

    types = tuple(robot_type for _, _, robot_type in lineup(setup)[::2])
    log_path = out / "sim_monitor.log"
    counter = LogCounter()
    logging.getLogger().addHandler(counter)
    try:
        config = MatchConfig(team_left=LEFT_TEAM, team_right=RIGHT_TEAM, players_per_team=players,
                             robot_types=types, duration_s=duration_s, kick_off_wait_s=KICK_OFF_WAIT_S, seed=seed,
                             log_path=str(log_path), match_id="real_match_check")
        result = run_match(config, make)
    finally:
        logging.getLogger().removeHandler(counter)
    kick_off = "Left"
    from sim.replay import read_log

    for frame in read_log(log_path):
        if frame.play_mode in (1, 2):
            kick_off = "Left" if frame.play_mode == 1 else "Right"
            break
    notes = {"run_match": {"score": f"{result.score_left}:{result.score_right}", "falls": result.falls,
                           "agent_errors": result.agent_errors, "final_play_mode": result.final_play_mode,
                           "possession": result.possession},
             "logged warnings": dict(counter.counts), "first warnings": counter.first}
    return Played("ours", log_path, agents, result.wall_s, kick_off, lineup(setup), duration_s, notes)
