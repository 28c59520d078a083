"""Our full soccer agent in a small match on the real rcssserver3d 0.7.3 and on our simulator, side by side.

A tool for people, never run in CI (it needs the real server built by ../shared/real-server/build.sh). The real
match: a fresh server (tools/real_server.py: sync mode, not real time, a monitor frame every cycle) in a
private network namespace; the agents run in this process, one thread each, through the transport of ``python
-m agent`` (``agent.runner.run``: framing, malformed-message policy, reconnects) with the soccer agent of
``agent.player`` and the robot types of ``--type auto`` (``agent.team.composition``). They connect one after
another (left 1, right 1, left 2, ...; robots built in the same cycle knock each other over), wait
KICK_OFF_WAIT_S of server time in BeforeKickOff, then the monitor sends ``(kickOff <side>)`` (REFERENCE §5.2)
and the game runs for ``--duration`` seconds of game time. Our match: ``sim.match.run_match`` with the same
players, types, duration and the agents of ``motion_studio.match_agents.make_agent`` (its coin toss picks the
kicking side; the real match then kicks off with the same side).

Both are measured the same way: the monitor stream (the real monitor connection; our SimSpark monitor log)
gives play modes, goals, the ball's path and how far it got, falls per robot (torso below 0.25 m, standing
again above 0.30 m, as sim/match.py counts them), where each robot stood at kick-off against its beam spot,
and referee fouls; each agent is wrapped to count its exceptions (answered with ``(syn)``, as
sim/match.py's CrashGuard does; ``python -m agent`` would have died), the motions it started (kicks = starts of
``kick*``), and its belief (``world.world_pose`` while ``world.localized``) against the monitor's torso at the
same game time (localization error).

    .venv/bin/python tools/real_match_check.py --players 3 --duration 120 --json out/real_match_check/figures.json
    .venv/bin/python tools/real_match_check.py --types 0       # every robot type 0 (a diagnosis, not --type auto)
    .venv/bin/python tools/real_match_check.py --only ours     # our simulator only (no namespace needed)
    .venv/bin/python tools/real_match_check.py --cli           # real: python -m agent processes, monitor figures

Kicks are also judged by their effect: the ball's move in KICK_EFFECT_S after the kick motion started and
where the ball lay in the kicker's torso frame then (monitor truth; the kick motions want it at their
``ball_forward_m``/``ball_left_m``). The real server's game time runs as fast as the agents answer (sync mode,
not real time); the first agent stops answering at ``--duration`` so the match ends on that cycle.

(It re-runs itself inside ``netns.sh``.) Code and motions come from a git revision (``--code``, default HEAD,
exported into a temporary folder that is put first on ``sys.path``), so other people's unfinished files in
the working tree do not play; ``--code worktree`` plays the tree as it is. Server log, monitor logs and the
agents' log go to ``--out`` (default out/real_match_check).
"""

from __future__ import annotations

import argparse
import collections
import json
import logging
import math
import os
import re
import signal
import subprocess
import sys
import tempfile
import threading
import time
import traceback
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

REPO = Path(__file__).resolve().parents[1]
CYCLE_S = 0.02
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


#: Robot types by unum (cycled) instead of ``--type auto``'s (``--types``); None = auto.
TYPES: tuple[int, ...] | None = None


def lineup(players: int) -> list[tuple[str, int, int]]:
    """(team, unum, robot type) in connection order, the types of ``python -m agent --type auto`` (or
    ``--types``)."""
    from agent.team.composition import robot_type_for

    def robot_type(unum: int) -> int:
        return robot_type_for(unum) if TYPES is None else TYPES[(unum - 1) % len(TYPES)]

    return [(team, unum, robot_type(unum)) for unum in range(1, players + 1) for team in (LEFT_TEAM, RIGHT_TEAM)]


def _soccer(team: str, unum: int, robot_type: int) -> Any:
    from motion_studio.match_agents import make_agent

    return make_agent(team, unum, robot_type)


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


def run_real(players: int, duration_s: float, kick_off: str, out: Path) -> Played:
    from agent.agent import AgentConfig
    from agent.runner import ConnectionPolicy, run
    from tools.real_server import MonitorLink, RealServer

    counter = LogCounter()
    logging.getLogger().addHandler(counter)
    server = RealServer(out / "real_server.log")
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
        for team, unum, robot_type in lineup(players):
            watched = Watched(_soccer, team, unum, robot_type, catch_protocol=False)
            config = AgentConfig(team=team, unum=unum, robot_type=robot_type)

            def play(watched: Watched = watched, config: AgentConfig = config) -> None:
                try:
                    outcomes[watched.name] = run(config, "127.0.0.1", 3100, ConnectionPolicy(connect_attempts=10),
                                                 stop, make_agent=watched.connection)
                except Exception as error:  # noqa: BLE001 - reported
                    outcomes[watched.name] = error

            thread = threading.Thread(target=play, name=watched.name, daemon=True)
            agents.append(watched)
            threads.append(thread)
            thread.start()
            deadline = time.monotonic() + 30.0
            while watched.cycles < CONNECT_GAP_CYCLES and time.monotonic() < deadline and thread.is_alive():
                time.sleep(0.001)
            if watched.cycles < CONNECT_GAP_CYCLES:
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
        wall_limit = time.monotonic() + max(600.0, 30.0 * duration_s)
        last_cycles, last_change = -1, time.monotonic()
        while time.monotonic() < wall_limit:
            game = clock.world.game
            if game.game_time_s >= duration_s or game.play_mode == "GameOver":
                break
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
        server.stop()
        if monitor is not None:
            monitor.close()
        for thread in threads:
            thread.join(15)
        logging.getLogger().removeHandler(counter)
    log_path = out / "real_monitor.log"
    log_path.write_bytes(b"\n".join(monitor.frames) + b"\n" if monitor is not None else b"")
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
    return Played("real", log_path, agents, wall_s, kick_off, lineup(players), duration_s, notes)


def run_real_cli(players: int, duration_s: float, kick_off: str, out: Path, code_dir: Path) -> Played:
    """The real match with ``python -m agent --team T --unum N --type auto`` processes (the code of
    ``code_dir``), as a person would start them; only the monitor measures (the agents' own figures are
    unknown), the notes keep each process's exit code and what its log says about trouble."""
    from tools.real_server import MonitorLink, RealServer

    server = RealServer(out / "real_server.log")
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
        for team, unum, _ in lineup(players):
            log = out / f"cli_{team}_{unum}.log"
            command = [sys.executable, "-m", "agent", "--team", team, "--unum", str(unum), "--type", "auto"]
            process = subprocess.Popen(command, cwd=code_dir, stdout=subprocess.DEVNULL, stderr=open(log, "w"))
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
        server.stop()
        if monitor is not None:
            monitor.close()
    log_path = out / "real_monitor.log"
    log_path.write_bytes(b"\n".join(monitor.frames) + b"\n")
    trouble = ("Traceback", "WARNING", "ERROR", "lost", "malformed", "timed out")
    notes["processes"] = {}
    for name, process, log in processes:
        text = log.read_text(errors="replace")
        notes["processes"][name] = {"exit code": process.returncode,
                                    "connections": text.count("connected to 127.0.0.1"),
                                    **{word: text.count(word) for word in trouble if word in text}}
    return Played("real (python -m agent)", log_path, [], wall_s, kick_off, lineup(players), duration_s, notes)


# ---- our match ----------------------------------------------------------------------------------------
def run_ours(players: int, duration_s: float, seed: int, out: Path) -> Played:
    from sim.match import MatchConfig, run_match

    agents: list[Watched] = []

    def make(team: str, unum: int, robot_type: int) -> Watched:
        watched = Watched(_soccer, team, unum, robot_type, catch_protocol=True)
        agents.append(watched)
        return watched

    types = tuple(robot_type for _, _, robot_type in lineup(players)[::2])
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
    for frame in _frames(log_path):
        if frame.play_mode in (1, 2):
            kick_off = "Left" if frame.play_mode == 1 else "Right"
            break
    notes = {"run_match": {"score": f"{result.score_left}:{result.score_right}", "falls": result.falls,
                           "agent_errors": result.agent_errors, "final_play_mode": result.final_play_mode,
                           "possession": result.possession},
             "logged warnings": dict(counter.counts), "first warnings": counter.first}
    return Played("ours", log_path, agents, result.wall_s, kick_off, lineup(players), duration_s, notes)


# ---- figures from the monitor stream and the agents ----------------------------------------------------
def _frames(path: Path):  # noqa: ANN202 - Iterator[sim.replay.ReplayFrame]
    from sim.replay import read_log

    return read_log(path)


def _heading(torso: Any) -> float:
    return math.atan2(float(torso[1, 1]), float(torso[0, 1]))


def _wrap(angle_rad: float) -> float:
    return (angle_rad + math.pi) % (2 * math.pi) - math.pi


def _percentile(values: list[float], q: float) -> float:
    if not values:
        return math.nan
    ordered = sorted(values)
    index = q * (len(ordered) - 1)
    low = math.floor(index)
    high = min(low + 1, len(ordered) - 1)
    return ordered[low] + (ordered[high] - ordered[low]) * (index - low)


def figures(played: Played) -> dict[str, Any]:
    from agent.formation import beam_spot
    from sim.match import FALLEN_TORSO_Z_M, STANDING_AGAIN_Z_M
    from sim.rules.params import PLAY_MODES

    modes: list[str] = []
    previous_mode = None
    fallen: dict[str, bool] = {}
    falls: collections.Counter[str] = collections.Counter()
    truth: dict[Any, tuple[float, float, float]] = {}
    balls: dict[int, tuple[float, float]] = {}
    ball_path, ball_far, ball_x = 0.0, 0.0, [math.inf, -math.inf]
    last_ball = None
    score = (0, 0)
    goals = 0
    frames = 0
    at_kick_off: dict[str, tuple[float, float]] = {}
    before: dict[str, tuple[float, float]] = {}
    game_time = 0.0
    first_play_on = None
    seen: set[str] = set()
    for frame in _frames(played.monitor_log):
        if frame.time_s > played.until_s + CYCLE_S / 2:
            break
        frames += 1
        mode = PLAY_MODES[frame.play_mode] if frame.play_mode is not None and frame.play_mode < len(PLAY_MODES) \
            else "unknown"
        if mode != previous_mode:
            modes.append(f"{mode}@{frame.time_s:.1f}")
            goals += mode.startswith("Goal_")
            if previous_mode == "BeforeKickOff" and not at_kick_off:
                at_kick_off = dict(before)
            if mode == "PlayOn" and first_play_on is None:
                first_play_on = frame.time_s
            previous_mode = mode
        score, game_time = frame.score, frame.time_s
        for name, robot in frame.robots.items():
            if robot.side is None:  # a robot being built (no team material yet)
                continue
            seen.add(name)
            torso = robot.bodies.get("torso")
            if torso is None:
                continue
            x, y, z = (float(v) for v in torso[:3, 3])
            if mode == "BeforeKickOff":
                before[name] = (x, y)
            if not fallen.get(name) and z < FALLEN_TORSO_Z_M:
                fallen[name] = True
                falls[name] += 1
            elif fallen.get(name) and z > STANDING_AGAIN_Z_M:
                fallen[name] = False
            if frame.time_s > 0:
                truth[_truth_key(name, frame.time_s)] = (x, y, _heading(torso))
        if frame.ball is not None and frame.time_s > 0:
            bx, by = float(frame.ball[0, 3]), float(frame.ball[1, 3])
            balls[round(frame.time_s / CYCLE_S)] = (bx, by)
            if last_ball is not None:
                step = math.dist(last_ball, (bx, by))
                if step < BALL_TELEPORT_M:
                    ball_path += step
            last_ball = (bx, by)
            ball_far = max(ball_far, math.hypot(bx, by))
            ball_x = [min(ball_x[0], bx), max(ball_x[1], bx)]
    names = sorted({*seen, *(f"{team.lower()}_{unum}" for team, unum, _ in played.lineup)})
    out: dict[str, Any] = {
        "wall [s]": round(played.wall_s, 1),
        "game time [s]": round(game_time, 2),
        "monitor frames": frames,
        "kick-off": played.kick_off,
        "first PlayOn at [s]": first_play_on if first_play_on is not None else math.nan,
        "play modes": " > ".join(modes),
        "goals": goals,
        "score": f"{score[0]}:{score[1]}",
        "ball path [m]": round(ball_path, 2),
        "ball farthest from centre [m]": round(ball_far, 2),
        "ball x min/max [m]": f"{ball_x[0]:.2f}/{ball_x[1]:.2f}" if last_ball else "-",
        "ball at end": f"({last_ball[0]:.2f}, {last_ball[1]:.2f})" if last_ball else "-",
        "falls total": sum(falls.values()),
    }
    for name in names:
        out[f"falls {name}"] = falls.get(name, 0)
    offsets = []
    for team, unum, _ in played.lineup:
        spot = beam_spot(unum)
        sign = 1.0 if team == LEFT_TEAM else -1.0
        where = at_kick_off.get(f"{team.lower()}_{unum}")
        if where is not None:
            offsets.append(math.dist(where, (sign * spot.x_m, sign * spot.y_m)))
    out["beam offset max [m]"] = round(max(offsets), 3) if offsets else math.nan
    fouls = _fouls(played.monitor_log, played.until_s)
    out["referee fouls"] = ", ".join(f"{k} {v}" for k, v in sorted(fouls.items())) or "-"
    if not played.agents:  # python -m agent processes (--cli): what they said is in the notes
        return out
    kicks = {w.name: len(w.kicks) for w in played.agents}
    out["kicks (motion starts)"] = sum(kicks.values())
    for name, count in kicks.items():
        out[f"kicks {name}"] = count
    moved, reach, details = [], [], []
    for watched in played.agents:
        key_name = f"{watched.team.lower()}_{watched.unum}"
        poses = {k[1]: v for k, v in truth.items() if k[0] == key_name}
        for time_s, motion in watched.kicks:
            start, end = _near(balls, time_s), _near(balls, time_s + KICK_EFFECT_S)
            robot = _near(poses, time_s)
            text = f"{watched.name} t={time_s:.1f} {motion}"
            if start is not None and end is not None:
                moved.append(math.dist(start, end))
                text += f" ball moved {moved[-1]:.2f} m"
            if start is not None and robot is not None:
                reach.append(math.dist(start, robot[:2]))
                c, s = math.cos(robot[2]), math.sin(robot[2])
                dx, dy = start[0] - robot[0], start[1] - robot[1]
                text += f", ball at torso +({c * dx + s * dy:.3f} fwd, {-s * dx + c * dy:.3f} left) m"
            details.append(text)
    out[f"kicks moving the ball > 0.5 m in {KICK_EFFECT_S:g} s"] = sum(1 for m in moved if m > 0.5)
    out["ball moved per kick mean [m]"] = round(sum(moved) / len(moved), 2) if moved else math.nan
    out["ball moved per kick max [m]"] = round(max(moved), 2) if moved else math.nan
    out["torso-ball at kick start median [m]"] = round(_percentile(reach, 0.5), 3)
    out["kick details"] = "; ".join(details) or "-"
    starts: collections.Counter[str] = collections.Counter()
    for watched in played.agents:
        starts.update(watched.motion_starts)
    out["motion starts"] = ", ".join(f"{m} {n}" for m, n in sorted(starts.items()))
    position, heading = [], []
    per_robot: dict[str, list[float]] = {}
    for watched in played.agents:
        key_name = f"{watched.team.lower()}_{watched.unum}"
        for belief in watched.beliefs:
            known = truth.get(_truth_key(key_name, belief.game_time_s))
            if known is None:
                continue
            error = math.dist((belief.x_m, belief.y_m), known[:2])
            position.append(error)
            per_robot.setdefault(watched.name, []).append(error)
            heading.append(abs(math.degrees(_wrap(belief.heading_rad - known[2]))))
    out["loc error median [m]"] = round(_percentile(position, 0.5), 3)
    out["loc error p90 [m]"] = round(_percentile(position, 0.9), 3)
    out["loc heading error median [deg]"] = round(_percentile(heading, 0.5), 1)
    out["loc heading error p90 [deg]"] = round(_percentile(heading, 0.9), 1)
    out["loc samples"] = len(position)
    for name, errors in per_robot.items():
        out[f"loc error median {name} [m]"] = round(_percentile(errors, 0.5), 3)
    firsts = [w.first_localized_s for w in played.agents if w.first_localized_s is not None]
    out["slowest first localization [s]"] = round(max(firsts), 2) if firsts else math.nan
    out["never localized"] = ", ".join(w.name for w in played.agents if w.first_localized_s is None) or "-"
    out["agent exceptions"] = sum(w.errors for w in played.agents)
    out["malformed sense messages"] = sum(w.bad_messages for w in played.agents)
    out["agent cycles"] = sum(w.cycles for w in played.agents)
    out["reconnections"] = sum(max(0, w.connections - 1) for w in played.agents)
    return out


def _near(by_cycle: dict[int, Any], time_s: float) -> Any:
    """The value at the cycle of ``time_s`` or the one next to it (our log holds every 2nd cycle)."""
    cycle = round(time_s / CYCLE_S)
    for k in (cycle, cycle + 1, cycle - 1):
        if k in by_cycle:
            return by_cycle[k]
    return None


def _truth_key(name: str, time_s: float) -> Any:
    return (name, round(time_s / CYCLE_S))


FOUL_TYPES = {"0": "crowding", "1": "touching", "2": "illegal defence", "3": "illegal attack", "4": "incapable",
              "5": "kick-off", "6": "charging", "7": "self-collision"}


def _fouls(path: Path, until_s: float) -> collections.Counter[str]:
    """Referee fouls of the monitor stream by type (REFERENCE §4.5; each reported once by its index) up to
    game time ``until_s``."""
    seen: dict[str, str] = {}
    pattern = re.compile(rb"\(foul (\d+) (\d+) (\d+) (\d+)\)")
    time_pattern = re.compile(rb"\(time ([0-9.]+)\)")
    with open(path, "rb") as handle:
        for line in handle:
            found = time_pattern.search(line[:4000])
            if found and float(found.group(1)) > until_s + CYCLE_S / 2:
                break
            for index, kind, _team, _unum in pattern.findall(line[:4000]):
                seen[index.decode()] = FOUL_TYPES.get(kind.decode(), kind.decode())
    return collections.Counter(seen.values())


# ---- report --------------------------------------------------------------------------------------------
def _cell(value: Any) -> str:
    if isinstance(value, float):
        return "-" if math.isnan(value) else f"{value:.3f}".rstrip("0").rstrip(".")
    return str(value)


def table(real: dict[str, Any], ours: dict[str, Any]) -> str:
    long_keys = ("play modes", "motion starts", "kick details")
    keys = [k for k in dict.fromkeys([*real, *ours]) if k not in long_keys]
    rows = [f"{'figure':34s} {'real 0.7.3':>18s} {'ours':>18s}"]
    rows += [f"{k:34s} {_cell(real.get(k, '')):>18s} {_cell(ours.get(k, '')):>18s}" for k in keys]
    for key in long_keys:
        rows += [f"{key}:", f"  real: {real.get(key, '')}", f"  ours: {ours.get(key, '')}"]
    return "\n".join(rows)


def problems(played: Played) -> list[str]:
    """Exceptions (first tracebacks) and warnings, for the report."""
    lines = []
    for watched in played.agents:
        for text in watched.tracebacks:
            lines.append(f"{played.where} {watched.name}: exception\n{text}")
    lines += [f"{played.where}: {w}" for w in played.notes.get("first warnings", [])]
    return lines


# ---- entry ---------------------------------------------------------------------------------------------
def use_code(revision: str) -> tuple[str, Path]:
    """Put the code of a git revision first on ``sys.path`` (exported into a temporary folder); returns the
    short revision (``worktree``: this tree) and the folder."""
    if revision == "worktree":
        sys.path.insert(0, str(REPO))
        return "worktree", REPO
    # This script's folder is first on sys.path; git_export imports nothing of the project.
    from git_export import export_revision, short_revision

    short = short_revision(revision)
    folder = export_revision(short, Path(tempfile.mkdtemp(prefix=f"real_match_{short}_")))
    sys.path.insert(0, str(folder))
    if not (folder / "tools" / "real_server.py").exists():  # a revision before tools/real_server.py
        sys.path.insert(1, str(REPO))
    return short, folder


def main() -> None:
    global TYPES, CONNECT_GAP_CYCLES
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--players", type=int, default=3, help="players per team (default 3)")
    parser.add_argument("--duration", type=float, default=120.0, help="game time to play [s] (default 120)")
    parser.add_argument("--seed", type=int, default=0, help="our simulator's seed (default 0)")
    parser.add_argument("--code", default="HEAD", help="git revision whose agent, simulator and motions play "
                        "(default HEAD); 'worktree' = the files as they are now")
    parser.add_argument("--kick-off", choices=("Left", "Right", "same"), default="same",
                        help="side kicking off on the real server (default: the side our match's coin toss chose)")
    parser.add_argument("--types", help="robot types by unum, cycled, e.g. 0 or 0,2,4 (default: --type auto's, "
                        "agent.team.composition)")
    parser.add_argument("--cli", action="store_true",
                        help="real match with python -m agent processes (the command people use) instead of "
                        "agents in this process; only the monitor's figures then")
    parser.add_argument("--connect-gap", type=int, default=CONNECT_GAP_CYCLES,
                        help=f"cycles each agent plays before the next connects, in-process real match "
                        f"(default {CONNECT_GAP_CYCLES})")
    parser.add_argument("--only", choices=("real", "ours"), help="play one of the two matches only")
    parser.add_argument("--out", type=Path, default=Path("out/real_match_check"), help="logs")
    parser.add_argument("--json", type=Path, help="also write the figures as JSON")
    args = parser.parse_args()
    if args.only != "ours" and os.environ.get("SS_IN_NETNS") != "1":
        netns = "/work/shared/real-server/netns.sh"
        os.execvp(netns, [netns, sys.executable, *sys.argv])
    if not 1 <= args.players <= 11:
        parser.error("--players must be 1-11")
    revision, code_dir = use_code(args.code)
    CONNECT_GAP_CYCLES = args.connect_gap
    if args.types:
        TYPES = tuple(int(t) for t in args.types.split(","))
    import agent  # noqa: PLC0415 - after use_code

    args.out.mkdir(parents=True, exist_ok=True)
    logging.basicConfig(level=logging.INFO, filename=str(args.out / "agents.log"), filemode="w",
                        format="%(asctime)s %(threadName)s %(levelname)s %(name)s: %(message)s")
    print(f"code: {revision} ({Path(agent.__file__).parent.parent}); {args.players} v {args.players}, "
          f"{args.duration:g} s", flush=True)
    results: dict[str, Any] = {"code": revision, "players": args.players, "duration_s": args.duration,
                               "seed": args.seed, "types": [t for _, _, t in lineup(args.players)]}
    kick_off = "Left" if args.kick_off == "same" else args.kick_off
    played: list[Played] = []
    if args.only != "real":
        ours = run_ours(args.players, args.duration, args.seed, args.out)
        played.append(ours)
        if args.kick_off == "same":
            kick_off = ours.kick_off
        print(f"ours: played in {ours.wall_s:.0f} s", flush=True)
    if args.only != "ours":
        real = (run_real_cli(args.players, args.duration, kick_off, args.out, code_dir) if args.cli else
                run_real(args.players, args.duration, kick_off, args.out))
        played.insert(0, real)
        print(f"real: played in {real.wall_s:.0f} s", flush=True)
    figs = {p.where.split()[0]: figures(p) for p in played}
    for p in played:
        results[p.where.split()[0]] = {"what": p.where, "figures": figs[p.where.split()[0]], "notes": p.notes,
                                       "problems": problems(p)}
    print(table(figs.get("real", {}), figs.get("ours", {})), flush=True)
    for p in played:
        print(f"{p.where} notes: {json.dumps(p.notes, default=str)}")
        for line in problems(p):
            print(line)
    if args.json:
        args.json.parent.mkdir(parents=True, exist_ok=True)
        args.json.write_text(json.dumps(results, indent=1, default=str))


if __name__ == "__main__":
    main()
