"""Sim-to-real check of the shipped motions: the same agent and skill on the real rcssserver3d 0.7.3 and on our
simulator, measured by ground truth, side by side.

A tool for people, never run in CI (it needs the real server built by ../shared/real-server/build.sh). For each
case it starts a fresh real server (tools/real_server.py: sync mode, not real time) in a private network
namespace, runs our ``agent.Agent`` with ``SkillBehavior`` over TCP, and at cycle CONNECT_CYCLES sends the
trainer commands of :func:`trainer_commands` on the monitor port: move the robot (``(agent (unum 1)(team
Left)(move x y 0.4 angle))``, no beam noise), put the ball, PlayOn (the game time runs, so each monitor frame
lines up with an agent cycle by its time, and the ball is no longer held at the centre). A full state is
requested every cycle (diffs round poses to 5 mm) and gives the torso pose and the ball. The same session then
runs on our simulator (:func:`run_sim`: in-process agent, the full referee, the same trainer commands at the
same cycle). Timeline of both: CONNECT_CYCLES, trainer commands, SETTLE_CYCLES standing still, then the skill
for the case's cycles. Motions come from a git revision (``--motions``, default HEAD), so other people's
unfinished files do not leak in.

    .venv/bin/python tools/real_skill_check.py --list
    .venv/bin/python tools/real_skill_check.py turn_left walk_forward --json out/real_skill_check/figures.json
    .venv/bin/python tools/real_skill_check.py --fixture tests/sim/fixtures   # every case, traces written

(It re-runs itself inside ``netns.sh`` when started outside a namespace.) With ``--fixture DIR`` each real run
is also written as ``DIR/real_0.7.3_skill_<case>.jsonl.gz`` (tests/sim/test_real_skill_traces.py replays them):
the send/recv lines of tools/record_real_trace.py (vision left out), a ``meta`` line (case, motions revision,
spot, trainer commands and their cycle, skill start) and a ``truth`` line per cycle with a known pose (torso
position, up-axis z, heading, ball). Server logs, monitor logs and any sense message our agent rejected go to
``--out`` (default out/real_skill_check).
"""

from __future__ import annotations

import argparse
import gzip
import json
import math
import os
import re
import sys
import tempfile
import time
from collections.abc import Callable
from dataclasses import dataclass, field, replace
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from agent.agent import Agent, AgentConfig  # noqa: E402
from tools.git_export import export_revision, short_revision  # noqa: E402
from agent.protocol.effectors import Action, JointVelocity  # noqa: E402
from agent.protocol.errors import ProtocolError  # noqa: E402
from agent.protocol.framing import read_frame, write_frame  # noqa: E402
from agent.skills.base import PlayMotion, Skill  # noqa: E402
from agent.skills.behavior import SkillBehavior  # noqa: E402
from agent.skills.standup import StandUp  # noqa: E402
from agent.skills.turn import TurnBy  # noqa: E402
from agent.world_model import WorldModel  # noqa: E402
from motion_studio.scenarios import FALL_TORSO_Z_M, FALL_UP_Z, Truth  # noqa: E402
from tools.real_server import REAL_SERVER_DIR, MonitorLink, RealServer, connect  # noqa: E402

CYCLE_S = 0.02
#: Cycles before the move (scene, init, the agent's own beam), as motion_studio.scenarios.CONNECT_CYCLES.
CONNECT_CYCLES = 6
#: Cycles standing still after the move before the skill starts (the drop from z = 0.4 settles).
SETTLE_CYCLES = 40
TEAM, UNUM = "Check", 1
#: SelfCollisionsTolerance of naosoccersim.rb [m].
SELF_COLLISION_TOLERANCE_M = 0.04


# ---- cases ---------------------------------------------------------------------------------------------
class SkillSequence(Skill):
    """Skills one after the other; each for a number of cycles (None: until done)."""

    def __init__(self, *parts: tuple[Skill | None, int | None]) -> None:
        super().__init__()
        self.parts = parts
        self.name = " then ".join(p.name if p else "idle" for p, _ in parts)
        self.reset()

    def reset(self) -> None:
        super().reset()
        self._index, self._cycles = 0, 0
        for skill, _ in self.parts:
            if skill is not None:
                skill.reset()

    def step(self, world, motion):  # noqa: ANN001, ANN201 - Skill interface
        from agent.motion import MotionRequest

        while self._index < len(self.parts):
            skill, cycles = self.parts[self._index]
            finished = (cycles is not None and self._cycles >= cycles) or (
                cycles is None and skill is not None and skill.done)
            if not finished:
                self._cycles += 1
                return skill.step(world, motion) if skill is not None else MotionRequest(None)
            self._index, self._cycles = self._index + 1, 0
        self.done = True
        return MotionRequest(None)


@dataclass(frozen=True)
class Case:
    """One measured run: a skill from a standstill at a spot, for a number of cycles."""

    name: str
    make_skill: Callable[[], Skill | None]
    cycles: int
    position_m: tuple[float, float] = (-8.0, 0.0)
    heading_deg: float = 0.0
    ball_m: tuple[float, float] | None = (0.0, 8.0)
    """Where the ball lies (out of the way unless the case kicks it)."""
    fall: str | None = None
    """"back"/"front": the skill starts with a scripted fall (raw joint velocities, FALL_SCRIPT)."""
    recover_falls: bool = False
    walk_cycles: int | None = None
    """For a walk: the cycles it is requested (the rest is its stop)."""
    motion: str | None = None
    """The motion the case needs (cases whose motion the library lacks are skipped)."""
    kick: bool = False
    """The ball goes where the motion's constants ``ball_forward_m``/``ball_left_m`` want it (robot frame, walk
    stance; the stand before the kick moves the torso STAND_SHIFT_M forward)."""


def _walk(name: str, seconds: float = 10.0, stop_s: float = 2.0) -> Case:
    walk = int(seconds / CYCLE_S)
    return Case(name, lambda: SkillSequence((PlayMotion(name, repeat=True), walk), (None, None)),
                walk + int(stop_s / CYCLE_S), walk_cycles=walk)


CASES: dict[str, Case] = {
    "stand": Case("stand", lambda: PlayMotion("stand"), 200),
    "turn_left": Case("turn_left", lambda: PlayMotion("turn_left", repeat=True), 400),
    "turn_right": Case("turn_right", lambda: PlayMotion("turn_right", repeat=True), 400),
    "turn_by_90": Case("turn_by_90", lambda: TurnBy(90.0), 400),
    "walk_forward": _walk("walk_forward"),
    "walk_backward": replace(_walk("walk_backward"), position_m=(-3.0, 0.0)),
    "walk_left": replace(_walk("walk_left"), position_m=(-5.0, -4.0)),
    "walk_right": replace(_walk("walk_right"), position_m=(-5.0, 4.0)),
    "standup_back": Case("standup_back", StandUp, 500, fall="back"),
    "standup_front": Case("standup_front", StandUp, 500, fall="front"),
}
#: Torso moved forward by the stand motion from the zero pose [m] (measured: real 0.032, ours 0.033).
STAND_SHIFT_M = 0.032
STAND_CYCLES = 60


def _kick(name: str) -> Case:
    return Case(name, lambda: SkillSequence((PlayMotion("stand"), STAND_CYCLES), (PlayMotion(name), None),
                                            (None, None)), STAND_CYCLES + 300, motion=name, kick=True)


for _name in ("kick", "kick_left", "kick_strong", "kick_strong_left"):
    CASES[_name] = _kick(_name)
for _case in list(CASES.values()):
    if _case.motion is None and _case.name in ("stand", "turn_left", "turn_right", "walk_forward", "walk_backward",
                                               "walk_left", "walk_right"):
        CASES[_case.name] = replace(_case, motion=_case.name)
CASES["standup_back"] = replace(CASES["standup_back"], motion="standup_back")
CASES["standup_front"] = replace(CASES["standup_front"], motion="standup_front")

#: Raw joint velocities [rad/s] by cycle of the skill phase that knock the robot over: both hips at 3 rad/s tip it
#: onto its back (as tests/sim/fixtures/real_0.7.3_fall); hips at -1.5 and ankles at -3 rad/s onto its front.
FALL_SCRIPT = {
    "back": {0: {"lle3": 3.0, "rle3": 3.0}, 40: {"lle3": 0.0, "rle3": 0.0}},
    "front": {0: {"lle3": -1.5, "rle3": -1.5, "lle5": -3.0, "rle5": -3.0},
              30: {"lle3": 0.0, "rle3": 0.0, "lle5": 0.0, "rle5": 0.0}},
}
FALL_SCRIPT_CYCLES = 100


class FallThenSkill:
    """A ``Behavior``: from ``start_cycle`` on, FALL_SCRIPT_CYCLES cycles of the scripted fall, then ``inner``."""

    def __init__(self, inner: SkillBehavior, side: str | None) -> None:
        self.inner = inner
        self.side = side
        self.cycle = -1
        self.start_cycle: int | None = None

    def __call__(self, world: WorldModel) -> list[Action]:
        self.cycle += 1
        if self.side is None or self.start_cycle is None or self.cycle - self.start_cycle >= FALL_SCRIPT_CYCLES:
            return self.inner(world)
        step = FALL_SCRIPT[self.side].get(self.cycle - self.start_cycle, {})
        return [JointVelocity(name, value) for name, value in step.items()]


# ---- one run, measured ----------------------------------------------------------------------------------
@dataclass
class Run:
    """Truth per cycle of the skill phase (index 0 = the first cycle with the skill), motion completions."""

    where: str
    truths: list[Truth | None]
    completions: list[tuple[int, str]] = field(default_factory=list)
    self_collisions: int = 0
    """Self-colliding box pairs summed over the cycles (the real server prints each as ANALYSECOLLISIONS;
    ours: sim.rules.self_collision.colliding_pairs on the same poses)."""
    replies: dict[int, bytes] = field(default_factory=dict)
    """Our simulator's run: the agent's answer to each sense message (-1: the connect message)."""
    bad_messages: int = 0
    """Sense messages our agent rejected (ProtocolError; answered with (syn) as agent.runner does)."""
    fouls: int = 0
    """Self-collision fouls our referee enforced (joints frozen; the real server's count is not reported)."""
    blow_ups: int = 0
    """Our simulator's blow-up guard firing (sim.world: a hinge far past its stop or spinning; the robot is
    put back to the cycle's start at rest)."""


#: Where the motions come from: None = the working tree; else a folder with ``files/`` and
#: ``params/dynamic_elements.toml`` (see :func:`export_motions`).
MOTIONS_DIR: Path | None = None
MOTIONS_REVISION = "worktree"


def export_motions(revision: str, into: Path) -> Path:
    """The motion files and dynamic elements of a git revision, exported into ``into`` (the working tree
    may hold other helpers' unfinished motions). Returns the folder holding ``files/`` and ``params/``."""
    return export_revision(revision, into, "motions/files", "motions/params") / "motions"


def _controller():  # noqa: ANN202 - agent.motion.MotionController
    from agent.motion import MotionController, default_library, load_dynamic_params

    if MOTIONS_DIR is None:
        return None
    return MotionController(default_library(0, MOTIONS_DIR / "files"),
                            load_dynamic_params(MOTIONS_DIR / "params" / "dynamic_elements.toml"), 0)


def _behavior(case: Case) -> tuple[SkillBehavior, FallThenSkill]:
    inner = SkillBehavior(_controller(), None, 0, case.recover_falls)
    return inner, FallThenSkill(inner, case.fall)


def library():  # noqa: ANN201 - agent.motion.MotionLibrary
    from agent.motion import default_library

    return default_library(0, MOTIONS_DIR / "files" if MOTIONS_DIR is not None else None)


def kick_ball_m(case: Case) -> tuple[float, float]:
    """Field position of the ball for a kick case, from the motion's constants (robot frame)."""
    constants = library().get(case.motion).constants
    forward = float(constants["ball_forward_m"]) + STAND_SHIFT_M
    left = float(constants["ball_left_m"])
    c, s = math.cos(math.radians(case.heading_deg)), math.sin(math.radians(case.heading_deg))
    return case.position_m[0] + c * forward - s * left, case.position_m[1] + s * forward + c * left


def trainer_commands(case: Case) -> list[str]:
    """What the monitor sends at the move cycle (both servers): the move (trainer ``move`` angle = heading -
    90 deg for the left team, as beam adds -90), the ball, PlayOn."""
    x, y = case.position_m
    commands = [f"(agent (unum {UNUM})(team Left)(move {x} {y} 0.4 {case.heading_deg - 90.0}))"]
    ball = kick_ball_m(case) if case.kick else case.ball_m
    if ball is not None:
        commands.append(f"(ball (pos {ball[0]:.4f} {ball[1]:.4f} 0.042)(vel 0 0 0))")
    commands.append("(playMode PlayOn)")
    return commands


def run_sim(case: Case) -> Run:
    """The same session on our simulator: in-process agent, the full referee (PlayOn rules, self-collision
    fouls) and the same trainer commands at the same cycle."""
    from sim.engine import SimEngine
    from sim.inprocess import InProcessHost
    from sim.rules.self_collision import colliding_pairs
    from sim.rules.trainer import apply_trainer_message

    engine = SimEngine(seed=0)
    host = InProcessHost(engine)
    inner, behavior = _behavior(case)
    agent = Agent(AgentConfig(TEAM, UNUM, 0, say=False), behavior)
    run = Run("sim", [])
    replies = run.replies

    class Recorded:  # the agent, its answers kept by message index
        def connect_message(self) -> bytes:
            replies[-1] = agent.connect_message()
            return replies[-1]

        def step(self, sense: bytes) -> bytes:
            index = len(replies) - 1
            replies[index] = agent.step(sense)
            return replies[index]

    key = host.add(Recorded())
    world = engine.world
    skill_cycle = CONNECT_CYCLES + SETTLE_CYCLES
    done: dict[str, int] = {}
    blow_ups = world.divergences
    while agent.world.game.cycles < skill_cycle + case.cycles:
        seen = agent.world.game.cycles
        host.run(1)
        if agent.world.game.cycles == seen:
            continue
        index = seen  # the message just answered; the world now holds the state message index + 1 reports
        if index == CONNECT_CYCLES:
            for command in trainer_commands(case):
                apply_trainer_message(command, engine.referee, world)
        if index == skill_cycle - 1:
            inner.set_skill(case.make_skill())
            behavior.start_cycle = behavior.cycle + 1
        if index >= skill_cycle:
            _completions(run, inner, done, index - skill_cycle)
            rotation = world.torso_rotation(key)
            poses = next(bodies for _, unum, _, bodies in world.robot_body_poses() if unum == UNUM)
            run.self_collisions += len(colliding_pairs(0, poses, SELF_COLLISION_TOLERANCE_M))
            run.truths.append(Truth(world.time_s,
                                    tuple(world.torso_position(key).tolist()), float(rotation[2, 2]),
                                    world.heading_deg(key), world.ball_position(), False))
        else:
            done = dict(inner.motion.completed)
    run.blow_ups = world.divergences - blow_ups
    run.fouls = len(getattr(engine.referee, "fouls", []))
    return run


def _completions(run: Run, inner: SkillBehavior, done: dict[str, int], index: int) -> None:
    for name, count in inner.motion.completed.items():
        if count > done.get(name, 0):
            run.completions.append((index, name))
            done[name] = count


class ScriptedAgent:
    """Sends recorded answers (message index -> bytes, -1 = the connect message) instead of thinking."""

    def __init__(self, replies: dict[int, bytes]) -> None:
        self.replies = replies
        self.received = 0

    def connect_message(self) -> bytes:
        return self.replies[-1]

    def step(self, sense: bytes) -> bytes:
        self.received += 1
        return self.replies.get(self.received - 1, b"(syn)")


def _game_time_s(sense: bytes) -> float:
    """Game time of a sense message while in PlayOn, else 0 (which monitor frame it matches is then unknown)."""
    start = sense.find(b"(GS ")
    end = sense.find(b"))", start)
    gs = sense[start:end + 2] if start >= 0 and end >= 0 else b""
    found = re.search(rb"\(t ([0-9.]+)\)", gs)
    return float(found.group(1)) if found and b"(pm PlayOn)" in gs else 0.0


def run_real(case: Case, workdir: Path, script: dict[int, bytes] | None = None) -> tuple[Run, list[dict]]:
    """The case on the real server; returns the run and the trace lines (send/recv/meta/truth). With
    ``script`` (e.g. ``run_sim(case).replies``) the recorded answers are sent instead of our agent's."""
    from sim.replay import read_log

    server = RealServer(workdir / f"server_{case.name}.log")
    try:
        time.sleep(1.0)
        monitor = MonitorLink()
        sock = connect(3100)
        inner, behavior = _behavior(case)
        agent = Agent(AgentConfig(TEAM, UNUM, 0, say=False), behavior) if script is None else ScriptedAgent(script)
        lines: list[dict] = []
        move_cycle, skill_cycle = CONNECT_CYCLES, CONNECT_CYCLES + SETTLE_CYCLES
        total = skill_cycle + case.cycles
        game_times: list[float] = []
        run = Run("real", [])
        done: dict[str, int] = {}

        def send(i: int, payload: bytes) -> None:
            lines.append({"k": "send", "a": "A", "i": i, "msg": payload.decode()})
            write_frame(sock, payload)

        send(-1, agent.connect_message())
        for i in range(total):
            payload = read_frame(sock)
            if payload is None:
                raise RuntimeError(f"the real server closed the connection at cycle {i}")
            lines.append({"k": "recv", "a": "A", "i": i, "msg": payload.decode()})
            if i == move_cycle:
                for command in trainer_commands(case):
                    monitor.send(command)
            if i >= move_cycle:
                # a full state every cycle: diffs carry a transform only when an element moved by > 0.005,
                # so their poses lag by up to 5 mm; full states are exact (6 significant digits)
                monitor.send("(reqfullstate)")
            if i == skill_cycle and script is None:
                inner.set_skill(case.make_skill())
                behavior.start_cycle = behavior.cycle + 1
            try:
                reply = agent.step(payload)
            except ProtocolError as error:  # as agent.runner does: skip the message, answer (syn)
                run.bad_messages += 1
                (workdir / f"bad_sense_{case.name}_{i}.txt").write_text(f"{error}\n{payload.decode()}\n")
                reply = b"(syn)"
            game_times.append(_game_time_s(payload))
            if i >= skill_cycle:
                _completions(run, inner, done, i - skill_cycle)
            else:
                done = dict(inner.motion.completed)
            send(i, reply)
        sock.close()
        time.sleep(0.3)
        monitor.close()
    finally:
        server.stop()
    log_path = workdir / f"monitor_{case.name}.log"
    log_path.write_bytes(b"\n".join(monitor.frames) + b"\n")
    by_time: dict[int, Truth] = {}
    # self-collisions (the real server freezes the joints involved): printed as ANALYSECOLLISIONS lines
    collisions = (workdir / f"server_{case.name}.log").read_text(errors="replace").count("ANALYSECOLLISIONS")
    for frame in read_log(log_path):
        robot = frame.robots.get(f"left_{UNUM}")
        if robot is None or frame.play_mode != 3:  # PlayOn: the game time runs
            continue
        torso = robot.bodies["torso"]
        forward = torso[:3, 1]
        ball = frame.ball[:3, 3] if frame.ball is not None else (math.nan,) * 3
        by_time[round(frame.time_s / CYCLE_S)] = Truth(frame.time_s, tuple(float(v) for v in torso[:3, 3]),
                                                       float(torso[2, 2]),
                                                       math.degrees(math.atan2(forward[1], forward[0])),
                                                       tuple(float(v) for v in ball), False)
    truths_all = [by_time.get(round(t / CYCLE_S)) if t > 0 else None for t in game_times]
    for i, truth in enumerate(truths_all):
        if truth is not None:
            torso = truth.torso_m
            lines.append({"k": "truth", "i": i, "t": round(truth.time_s, 2), "torso": [round(v, 5) for v in torso],
                          "up_z": round(truth.up_z, 5), "heading_deg": round(truth.heading_deg, 3),
                          "ball": [round(v, 5) for v in truth.ball_m]})
    lines.insert(0, {"k": "meta", "case": case.name, "motions": MOTIONS_REVISION, "position_m": list(case.position_m),
                     "heading_deg": case.heading_deg, "ball_m": list(case.ball_m) if case.ball_m else None,
                     "move_cycle": move_cycle, "trainer": trainer_commands(case), "skill_cycle": skill_cycle,
                     "fall": case.fall, "commands": "our agent" if script is None else "our agent on our simulator",
                     "server": "rcssserver3d 0.7.3 (sync, not real time)", "tool": "tools/real_skill_check.py"})
    # truths_all[i] is the state message i reports; the simulator's truth after the cycle that delivered
    # message i is one step later (sim.engine delivers, then steps), so line the real run up with it
    run.truths = truths_all[skill_cycle + 1:] + [None]
    run.self_collisions = collisions
    return run, lines


# ---- figures -------------------------------------------------------------------------------------------
def _fallen(truth: Truth) -> bool:
    return truth.up_z < FALL_UP_Z or truth.torso_m[2] < FALL_TORSO_Z_M


def _wrap(angle_deg: float) -> float:
    return (angle_deg + 180.0) % 360.0 - 180.0


def figures(run: Run, case: Case) -> dict[str, float | str]:
    """The measured figures of a run (NaN where the truth is missing)."""
    truths = [t for t in run.truths if t is not None]
    if not truths:
        return {"truth cycles": 0}
    first = truths[0]
    out: dict[str, float | str] = {"truth cycles": len(truths), "self-collision pairs": run.self_collisions}
    if run.where == "real":
        out["sense msgs rejected (real)"] = run.bad_messages
    if run.where == "sim":
        out["self-collision fouls"] = run.fouls
        out["blow-ups (ours)"] = run.blow_ups
    fall = next((i for i, t in enumerate(run.truths) if t is not None and _fallen(t)), None)
    out["first fall [s]"] = math.nan if fall is None else fall * CYCLE_S
    heading, turned = first.heading_deg, 0.0
    for t in truths[1:]:
        turned += _wrap(t.heading_deg - heading)
        heading = t.heading_deg
    out["turn total [deg]"] = turned
    end_index = (case.walk_cycles or case.cycles) - 1
    end = next((run.truths[i] for i in range(min(end_index, len(run.truths) - 1), -1, -1)
                if run.truths[i] is not None), truths[-1])
    c, s = math.cos(math.radians(first.heading_deg)), math.sin(math.radians(first.heading_deg))
    dx, dy = end.torso_m[0] - first.torso_m[0], end.torso_m[1] - first.torso_m[1]
    out["forward [m]"], out["left [m]"] = c * dx + s * dy, -s * dx + c * dy
    out["heading change [deg]"] = _wrap(end.heading_deg - first.heading_deg)
    upright = [t for t in truths if not _fallen(t)]
    out["torso z mean [m]"] = sum(t.torso_m[2] for t in upright) / max(1, len(upright))
    out["up_z min"] = min(t.up_z for t in truths)
    if case.walk_cycles:
        seconds = case.walk_cycles * CYCLE_S
        out["speed [m/s]"] = math.hypot(dx, dy) / seconds
        start = run.truths[min(150, len(run.truths) - 1)]
        if start is not None and fall is None:
            out["speed after 3 s [m/s]"] = math.dist(start.torso_m[:2], end.torso_m[:2]) / (seconds - 3.0)
    turns = [i for i, name in run.completions if name.startswith("turn_")]
    if turns:
        headings = []
        for i in [0, *turns]:
            t = next((run.truths[j] for j in range(i, -1, -1) if run.truths[j] is not None), None)
            headings.append(t.heading_deg if t is not None else math.nan)
        per = [_wrap(b - a) for a, b in zip(headings, headings[1:])]
        out["turn motions"] = len(turns)
        out["turn per motion [deg]"] = sum(per) / len(per)
        out["turn per motion min/max"] = f"{min(per):.1f}/{max(per):.1f}"
        out["turn motion [s]"] = turns[0] * CYCLE_S if len(turns) == 1 else (turns[-1] - turns[0]) * CYCLE_S / (
            len(turns) - 1)
        out["turn rate [deg/s]"] = sum(per) / (turns[-1] * CYCLE_S)
        out["drift [m]"] = math.dist(first.torso_m[:2], end.torso_m[:2])
    if (case.ball_m is not None or case.kick) and not math.isnan(first.ball_m[0]):
        out["ball moved [m]"] = math.dist(first.ball_m[:2], truths[-1].ball_m[:2])
        if case.kick:
            dx, dy = truths[-1].ball_m[0] - first.ball_m[0], truths[-1].ball_m[1] - first.ball_m[1]
            out["ball direction [deg]"] = _wrap(math.degrees(math.atan2(dy, dx)) - first.heading_deg)
    if case.fall:
        stood = next((i for i, t in enumerate(run.truths) if t is not None and fall is not None and i > fall
                      and all(u is not None and u.up_z > 0.9 for u in run.truths[i:i + 25])), None)
        out["stood up after [s]"] = math.nan if stood is None else (stood - (fall or 0)) * CYCLE_S
        out["upright at end"] = "yes" if truths[-1].up_z > 0.9 and truths[-1].torso_m[2] > 0.3 else "no"
    return out


def table(case: Case, real: dict, sim: dict) -> str:
    rows = [f"{case.name}", f"  {'figure':28s} {'real 0.7.3':>14s} {'ours':>14s} {'ours - real':>12s}"]
    for key in dict.fromkeys([*real, *sim]):
        a, b = real.get(key, ""), sim.get(key, "")
        diff = b - a if isinstance(a, (int, float)) and isinstance(b, (int, float)) else ""
        rows.append(f"  {key:28s} {_cell(a):>14s} {_cell(b):>14s} {_cell(diff):>12s}")
    return "\n".join(rows)


def _cell(value: object) -> str:
    if isinstance(value, float):
        return "-" if math.isnan(value) else f"{value:.3f}"
    return str(value)


def without_vision(message: str) -> str:
    """A sense message without its ``(See ...)`` (half of a fixture's bytes; the replays need joints, FRP,
    gyro and accelerometer)."""
    start = message.find("(See ")
    if start < 0:
        return message
    depth = 0
    for index in range(start, len(message)):
        depth += {"(": 1, ")": -1}.get(message[index], 0)
        if depth == 0:
            return message[:start] + message[index + 1:]
    return message


def write_fixture(lines: list[dict], path: Path) -> None:
    """The trace as gzip JSONL, vision left out of the sense messages (meta ``vision``: "omitted")."""
    with gzip.open(path, "wt") as handle:
        for line in lines:
            if line["k"] == "meta":
                line = {**line, "vision": "omitted"}
            elif line["k"] == "recv":
                line = {**line, "msg": without_vision(line["msg"])}
            handle.write(json.dumps(line, separators=(",", ":")) + "\n")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("cases", nargs="*", help=f"cases (default all): {', '.join(CASES)}")
    parser.add_argument("--list", action="store_true", help="list the cases and exit")
    parser.add_argument("--fixture", type=Path, help="write each real trace into this folder")
    parser.add_argument("--out", type=Path, default=Path("out/real_skill_check"), help="server and monitor logs")
    parser.add_argument("--json", type=Path, help="also write the figures as JSON")
    parser.add_argument("--replay-sim", action="store_true",
                        help="send the answers our agent gave on our simulator to the real server (the same "
                             "joint commands on both: physics alone compared)")
    parser.add_argument("--motions", default="HEAD",
                        help="git revision of motions/files and motions/params to play (default HEAD: the "
                             "committed motions); 'worktree' = the files as they are now")
    args = parser.parse_args()
    if args.list:
        print("\n".join(f"{name}: {case.cycles} cycles" for name, case in CASES.items()))
        return
    if os.environ.get("SS_IN_NETNS") != "1":
        os.execvp(str(REAL_SERVER_DIR / "netns.sh"), [str(REAL_SERVER_DIR / "netns.sh"), sys.executable, *sys.argv])
    unknown = [name for name in args.cases if name not in CASES]
    if unknown:
        parser.error(f"unknown case(s) {unknown}; known: {', '.join(CASES)}")
    args.out.mkdir(parents=True, exist_ok=True)
    global MOTIONS_DIR, MOTIONS_REVISION
    revision = "worktree"
    if args.motions != "worktree":
        revision = short_revision(args.motions)
        MOTIONS_DIR = export_motions(revision, Path(tempfile.mkdtemp(prefix="motions_")))
    MOTIONS_REVISION = revision
    print(f"motions: {revision}", flush=True)
    results = {"motions": revision}
    available = library()
    for name in args.cases or list(CASES):
        case = CASES[name]
        if case.motion is not None and case.motion not in available:
            print(f"{name}: skipped (no motion {case.motion!r} at {revision})", flush=True)
            continue
        if args.replay_sim:  # physics alone: our agent's answers on our simulator, sent to both
            sim_run = run_sim(case)
            real_run, lines = run_real(case, args.out, script=sim_run.replies)
        else:
            real_run, lines = run_real(case, args.out)
            sim_run = run_sim(case)
        if args.fixture:
            suffix = "_simcmds" if args.replay_sim else ""
            write_fixture(lines, args.fixture / f"real_0.7.3_skill_{name}{suffix}.jsonl.gz")
        real, sim = figures(real_run, case), figures(sim_run, case)
        results[name] = {"real": real, "sim": sim}
        print(table(case, real, sim), flush=True)
    if args.json:
        args.json.write_text(json.dumps(results, indent=1))


if __name__ == "__main__":
    main()
