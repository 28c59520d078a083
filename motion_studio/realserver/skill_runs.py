"""One skill case run and measured by ground truth: on our simulator (in-process agent, the full referee) or on
the real rcssserver3d 0.7.3 (our agent over TCP, the monitor's full states as truth).

Both runs index their truth the same way: ``Run.truths[j]`` is the state reported by sense message
``case.skill_cycle + 1 + j`` (the simulator delivers a message, then steps; the real monitor frame with a sense
message's game time is the state that message reports).
"""

from __future__ import annotations

import math
import re
import time
from dataclasses import dataclass, field
from pathlib import Path

from agent.agent import Agent, AgentConfig
from agent.protocol.errors import ProtocolError
from agent.protocol.framing import read_frame, write_frame
from agent.skills.behavior import SkillBehavior
from motion_studio.realserver.cases import (CONNECT_CYCLES, CYCLE_S, FALL_SCRIPT_CYCLES, TEAM, UNUM, Case,
                                            DribbleSkill, MotionSource, SkillSequence, behavior,
                                            changed_dribble_settings, fall_steps, trainer_commands)
from motion_studio.realserver.errors import RealServerError
from motion_studio.realserver.process import AGENT_PORT, MonitorLink, RealServer, connect
from motion_studio.scenarios import Truth
from sim.physics_params import PhysicsParams

#: SelfCollisionsTolerance of naosoccersim.rb [m].
SELF_COLLISION_TOLERANCE_M = 0.04


@dataclass
class Run:
    """Truth per cycle of the skill phase (index 0 = the first cycle with the skill), motion completions."""

    where: str
    truths: list[Truth | None]
    completions: list[tuple[int, str]] = field(default_factory=list)
    """(skill-phase cycle, motion name) of each motion that ended; empty for an open-loop replay."""
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
    modes: list[str | None] = field(default_factory=list)
    """The playing skill's ``mode`` per skill-phase cycle (a dribble's push, turn, ...; None for a skill without
    one): where a skill's time goes, on both servers. Empty for an open-loop replay."""
    monitor: list[str] = field(default_factory=list)
    """Our simulator's run with ``record=True``: our monitor's full state after every cycle (the real harness's
    monitor log, one line per cycle)."""
    senses: list[bytes] = field(default_factory=list)
    """... and every sense message the agent got, in order."""


def record_mode(run: Run, inner: SkillBehavior) -> None:
    """Append the mode of the skill ``inner`` plays now (inside a case's ``SkillSequence``) to ``run.modes``."""
    skill = inner.skill
    if isinstance(skill, SkillSequence):
        skill = skill.current
    mode = getattr(skill, "mode", None)
    run.modes.append(mode if isinstance(mode, str) else None)


def record_completions(run: Run, inner: SkillBehavior, done: dict[str, int], index: int) -> None:
    """Append to ``run.completions`` the motions ``inner`` completed since ``done`` (updated), at ``index``."""
    for name, count in inner.motion.completed.items():
        if count > done.get(name, 0):
            run.completions.append((index, name))
            done[name] = count


def run_sim(case: Case, motions: MotionSource, record: bool = False, physics: PhysicsParams | None = None) -> Run:
    """The session on our simulator: in-process agent, the full referee (PlayOn rules, self-collision
    fouls) and the same trainer commands at the same cycle as on the real server. ``record`` keeps our
    monitor's full state after every cycle and the sense messages (``Run.monitor``, ``Run.senses``): the inputs
    of the measures that read the real server's logs (``motion-studio real joint-slack --ours``). ``physics``:
    our world's parameters (default: `sim.physics_params.default_physics_params`)."""
    from sim.engine import SimEngine
    from sim.inprocess import InProcessHost
    from sim.monitor import MonitorStream, MujocoWorldScene, snapshot_of
    from sim.rules.self_collision import colliding_pairs
    from sim.rules.trainer import apply_trainer_message

    engine = SimEngine(seed=0, physics=physics)
    host = InProcessHost(engine, record=record)
    if record:
        stream, scene = MonitorStream(engine.referee.config), MujocoWorldScene(engine.world)
    inner, fall_behavior = behavior(case, motions)
    agent = Agent(AgentConfig(TEAM, UNUM, case.robot_type, say=False), fall_behavior)
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
    skill_cycle = case.skill_cycle
    done: dict[str, int] = {}
    blow_ups = world.divergences
    commands = trainer_commands(case, motions)
    while agent.world.game.cycles < skill_cycle + case.cycles:
        seen = agent.world.game.cycles
        host.run(1)
        if record:
            run.monitor.append(stream.message(snapshot_of(scene, engine.referee), full=True))
        if agent.world.game.cycles == seen:
            continue
        index = seen  # the message just answered; the world now holds the state message index + 1 reports
        if index == CONNECT_CYCLES:
            for command in commands:
                apply_trainer_message(command, engine.referee, world)
        if index == skill_cycle - 1:
            inner.set_skill(case.make_skill())
            fall_behavior.start_cycle = fall_behavior.cycle + 1
        if index >= skill_cycle:
            record_completions(run, inner, done, index - skill_cycle)
            record_mode(run, inner)
            rotation = world.torso_rotation(key)
            poses = next(bodies for _, unum, _, bodies in world.robot_body_poses() if unum == UNUM)
            run.self_collisions += len(colliding_pairs(case.robot_type, poses, SELF_COLLISION_TOLERANCE_M))
            run.truths.append(Truth(world.time_s,
                                    tuple(world.torso_position(key).tolist()), float(rotation[2, 2]),
                                    world.heading_deg(key), world.ball_position(), False))
        else:
            done = dict(inner.motion.completed)
    run.blow_ups = world.divergences - blow_ups
    run.fouls = len(getattr(engine.referee, "fouls", []))
    if record:
        run.senses = [payload for _, _, payload in host.stats.transcript]
    return run


class ScriptedAgent:
    """Sends recorded answers (message index -> bytes, -1 = the connect message) instead of thinking."""

    def __init__(self, replies: dict[int, bytes]) -> None:
        self.replies = replies
        self.messages: list[bytes] = []
        """The sense messages it got, in order."""

    @property
    def received(self) -> int:
        return len(self.messages)

    def connect_message(self) -> bytes:
        return self.replies[-1]

    def step(self, sense: bytes) -> bytes:
        self.messages.append(sense)
        return self.replies.get(self.received - 1, b"(syn)")


def _game_time_s(sense: bytes) -> float:
    """Game time of a sense message while in PlayOn, else 0 (which monitor frame it matches is then unknown)."""
    start = sense.find(b"(GS ")
    end = sense.find(b"))", start)
    gs = sense[start:end + 2] if start >= 0 and end >= 0 else b""
    found = re.search(rb"\(t ([0-9.]+)\)", gs)
    return float(found.group(1)) if found and b"(pm PlayOn)" in gs else 0.0


def meta_line(case: Case, motions: MotionSource, commands: str, tool: str) -> dict:
    """The fixture's meta line: case, motions revision, spot, trainer commands and their cycle, skill start
    (and, for a varied lying start, the start and its fall script)."""
    meta = {"k": "meta", "case": case.name, "motions": motions.revision, "position_m": list(case.position_m),
            "heading_deg": case.heading_deg, "ball_m": list(case.ball_m) if case.ball_m else None,
            "move_cycle": CONNECT_CYCLES, "trainer": trainer_commands(case, motions), "skill_cycle": case.skill_cycle,
            "fall": case.fall, "commands": commands, "server": "rcssserver3d 0.7.3 (sync, not real time)",
            "tool": tool}
    if case.robot_type:
        meta["robot_type"] = case.robot_type
    changed = changed_dribble_settings(case.make_skill.config) if isinstance(case.make_skill, DribbleSkill) else {}
    if changed:   # the fields changed by --dribble, so the trace says which dribble it shows
        meta["dribble_config"] = changed
    if case.start:
        meta["start"] = case.start
        meta["fall_script"] = {str(cycle): step for cycle, step in fall_steps(case).items()}
        meta["fall_script_cycles"] = FALL_SCRIPT_CYCLES
    return meta


def run_real(case: Case, motions: MotionSource, scripts: Path, workdir: Path,
             script: dict[int, bytes] | None = None, tool: str = "motion-studio real skills") -> tuple[Run, list[dict]]:
    """The case on the real server (this process must be inside netns.sh's namespace); returns the run and the
    trace lines (meta, send, recv, truth). With ``script`` (e.g. ``run_sim(case).replies``) the recorded
    answers are sent instead of our agent's.

    Raises:
        RealServerError: the server closed the connection before the case ended, or the monitor connection (the
            ground truth) failed.
    """
    from sim.replay import read_log

    server = RealServer(scripts, workdir / f"server_{case.name}.log")
    try:
        time.sleep(1.0)
        monitor = MonitorLink()
        sock = connect(AGENT_PORT)
        inner, fall_behavior = behavior(case, motions)
        agent = (Agent(AgentConfig(TEAM, UNUM, case.robot_type, say=False), fall_behavior) if script is None
                 else ScriptedAgent(script))
        lines: list[dict] = []
        move_cycle, skill_cycle = CONNECT_CYCLES, case.skill_cycle
        total = skill_cycle + case.cycles
        game_times: list[float] = []
        run = Run("real", [])
        done: dict[str, int] = {}
        commands = trainer_commands(case, motions)

        def send(i: int, payload: bytes) -> None:
            lines.append({"k": "send", "a": "A", "i": i, "msg": payload.decode()})
            write_frame(sock, payload)

        send(-1, agent.connect_message())
        for i in range(total):
            payload = read_frame(sock)
            if payload is None:
                raise RealServerError(f"{case.name}: the real server closed the connection at cycle {i}")
            lines.append({"k": "recv", "a": "A", "i": i, "msg": payload.decode()})
            if i == move_cycle:
                for command in commands:
                    monitor.send(command)
            if i >= move_cycle:
                # a full state every cycle: diffs carry a transform only when an element moved by > 0.005,
                # so their poses lag by up to 5 mm; full states are exact (6 significant digits)
                monitor.send("(reqfullstate)")
            if i == skill_cycle and script is None:
                inner.set_skill(case.make_skill())
                fall_behavior.start_cycle = fall_behavior.cycle + 1
            try:
                reply = agent.step(payload)
            except ProtocolError as error:  # as agent.runner does: skip the message, answer (syn)
                run.bad_messages += 1
                (workdir / f"bad_sense_{case.name}_{i}.txt").write_text(f"{error}\n{payload.decode()}\n")
                reply = b"(syn)"
            game_times.append(_game_time_s(payload))
            if i >= skill_cycle:
                record_completions(run, inner, done, i - skill_cycle)
                record_mode(run, inner)
            else:
                done = dict(inner.motion.completed)
            send(i, reply)
        sock.close()
        time.sleep(0.3)
        monitor.close()
        if monitor.failure:  # the ground truth has a gap: no figure from it
            raise RealServerError(f"{case.name}: {monitor.failure}")
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
    lines.insert(0, meta_line(case, motions, "our agent" if script is None else "our agent on our simulator", tool))
    # truths_all[i] is the state message i reports; the simulator's truth after the cycle that delivered
    # message i is one step later (sim.engine delivers, then steps), so line the real run up with it
    run.truths = truths_all[skill_cycle + 1:] + [None]
    run.self_collisions = collisions
    return run, lines
