"""Kick rollouts on the real rcssserver3d 0.7.3: one server in this process's private loopback namespace, the
robot and the ball put back by trainer commands between kicks, the server restarted only when it stalls.

A rollout (:meth:`RealKickBench.run`), cycle by cycle on the real server in sync mode:

1. reset: a fresh motion controller with the candidate's library plays ``stand`` for ``RESET_POSE_CYCLES``
   wherever the robot is (lying or standing, so it is moved in its stance), the ball is parked behind the
   spot, then ``(playMode PlayOn)``, ``(time 0)`` (the half never ends) and the trainer move upright to
   ``spot_m`` facing the aim turned by the placement's heading error (no beam noise; velocities zeroed);
2. ``settle_cycles`` of ``stand``; a full state gives the torso's pose, and the ball goes where the kick wants
   it (its constants ``ball_forward_m`` / ``ball_left_m``, plus the placement error, along the aim) with
   ``(ball (pos x y 0.042)(vel 0 0 0))``;
3. ``stand_cycles`` more of ``stand`` (the ball at rest), then the kick motion until it ends;
4. the ball rolls: until ``ROLL_AFTER_CONTACT_S`` after the strike (the real ball rests 5.2-6.5 s after a
   2-8 m/s launch, REFERENCE §2.4) with the robot holding still (only ``(syn)``: joint velocities persist
   on the server, and after the motion every command is 0).

The outcome is a ``motion_studio.kick_rollout.KickRun`` measured as on our simulator (ball rest distance,
direction error against the aim, the strike's time, foot and ball speeds, falls), from the monitor frames
(one per cycle; a diff carries an element only when it moved by more than 5 mm, so fast bodies are exact
and resting ones within 5 mm). With ``record`` each cycle's measured joint angles and commands are kept
(:class:`CycleRecord`) for comparing the strike with our simulator's.

The real server never runs in tests: it needs ../shared/real-server (build.sh) and a private network
namespace (:func:`ensure_private_network`).
"""

from __future__ import annotations

import logging
import math
import re
import sys
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path

from agent.motion import MotionController, MotionLibrary, load_dynamic_params
from agent.motion.dynamic import DynamicParams
from agent.protocol.effectors import Action, JointVelocity
from agent.skills.base import PlayMotion
from agent.skills.behavior import SkillBehavior
from agent.world_model import WorldModel
from motion_studio.kick_rollout import (STRIKE_SPEED_M_S, TRAP_FOOT_UP_M_S, TRAP_TORSO_UP_M_S, KickRun,
                                        Placement, ball_spot)
from motion_studio.realserver.paths import checked_scripts_dir
from motion_studio.realserver.process import reexec_in_netns
from motion_studio.realserver.session import STALL_S, RealSession
from motion_studio.scenarios import Truth
from agent.protocol.constants import BALL_RADIUS_M, CYCLE_S
from sim.engine import BEAM_HEIGHT_M

logger = logging.getLogger(__name__)

TEAM, UNUM = "KickBench", 1
BALL_Z_M = BALL_RADIUS_M
#: Cycles of the stance played where the robot lies or stands before it is moved (its joints reach the stance).
RESET_POSE_CYCLES = 25
#: The ball rests this long after the strike at the latest (REFERENCE §2.4: 5.2-6.5 s for 2-8 m/s) [s].
ROLL_AFTER_CONTACT_S = 6.6
#: Without a strike the run ends this long after the motion [s].
ROLL_WITHOUT_CONTACT_S = 1.0
#: Head yaw velocities [rad/s] sent in the cycles after the trainer move (net zero turn). ODE auto-disables
#: bodies at rest (spark.rb), the move does not wake them, and a stance whose targets the joints already
#: hold is commanded exactly 0, which does not either: without this the robot hung at the move's height until
#: the kick's first command (measured: 60 cycles at z = 0.4, then a fall).
WAKE_HEAD_RAD_S = (0.05, -0.05)
#: A stalled server: no sense message for this long [s].
_TIME = re.compile(rb"\(time ([0-9.eE+-]+)\)")
_GAME_TIME = re.compile(rb"\(t ([0-9.]+)\)")


#: Height of the trainer move per robot type [m]: the beam's AgentRadius (REFERENCE §3.7), 0.40, but for type 3
#: 0.39. Measured on the real server (2026-11-27, kick from its spot and 1 and 2 cm beyond): moved to 0.40, type 3
#: toppled during the settle in every run (torso 0.25 m, up-axis z 0.30 when the ball was placed: the kick then
#: "fell" and moved the ball 0.2 m backward); moved to 0.39 or 0.38 it stood (torso 0.377 m, up-axis z 0.975) and
#: kicked 4.7-5.1 m. Type 0 stays at 0.40: at 0.39 it settled otherwise (up-axis z 0.982 instead of 0.974) and
#: its kick went 3.3-4.1 m instead of 3.8-4.3, so its tuned figures keep their harness.
MOVE_HEIGHT_M = {3: 0.39}


def move_height_m(robot_type: int) -> float:
    """The trainer move's torso height for ``robot_type`` [m] (``MOVE_HEIGHT_M``)."""
    return MOVE_HEIGHT_M.get(robot_type, BEAM_HEIGHT_M)


@dataclass(frozen=True)
class RealKickConfig:
    """Where and how long (the defaults follow the kick cases of motion_studio.realserver.cases)."""

    spot_m: tuple[float, float] = (-8.0, 0.0)
    """Where the robot is moved (own half: a kick along +x stays far from goals and lines) [m]."""
    aim_deg: float = 0.0
    """Kick direction in the field frame [deg]."""
    move_z_m: float | None = None
    """Height of the trainer move [m]; None = `move_height_m` of the robot type."""
    settle_cycles: int = 70
    """Stance cycles after the move before the ball is placed. The move puts the torso upright while the
    standing robot leans 12.7 deg forward, so it lands on its heels and rocks (pitch 0 -> 21 -> 11 deg);
    measured at rest 60 cycles after the move (with 40 the kick started while it rocked: 1.31 m against
    1.57 m settled, same placement)."""
    stand_cycles: int = 20
    """Stance cycles with the ball at its spot before the kick."""
    park_ball_m: tuple[float, float] = (-1.5, 1.5)
    """Where the ball waits during the reset, from ``spot_m`` [m]."""


@dataclass
class CycleRecord:
    """One agent cycle of a recorded rollout: the sense message's game time, the motion's phase, the measured
    joint angles (wire name -> rad) and the commands sent (effector name -> rad/s)."""

    time_s: float
    phase: str | None
    joints_rad: dict[str, float]
    commands: dict[str, float]


@dataclass
class RealKickRun:
    """A kick on the real server: the measured run plus what only the real bench knows."""

    run: KickRun
    kick_start_s: float
    """Game time of the sense message answered with the kick's first command [s]."""
    frames: dict[int, dict] = field(repr=False, default_factory=dict)
    """Monitor truth by cycle (game time / 20 ms) from the kick on: ``torso``/``rfoot``/``lfoot``/``ball``
    positions [m], ``up_z``, ``heading_deg``, ``pitch_deg``, ``roll_deg`` (:func:`parse_truth`)."""
    cycles: list[CycleRecord] = field(repr=False, default_factory=list)
    self_collisions: int = 0
    """ANALYSECOLLISIONS lines the server printed during the rollout (it freezes those joints for 1 s)."""
    restarts: int = 0


# ---- the namespace ----------------------------------------------------------------------------------
def ensure_private_network(module: str, argv: Sequence[str], scripts: Path | None = None) -> None:
    """Re-run ``python -m module argv`` inside the real-server scripts' netns.sh unless already inside one (the
    real server binds 0.0.0.0; in the namespace only this process reaches it, on 127.0.0.1).

    Raises:
        RealServerError: the scripts are missing.
    """
    reexec_in_netns(checked_scripts_dir(scripts), [sys.executable, "-m", module, *argv])


# ---- one server -------------------------------------------------------------------------------------
class _Session(RealSession):
    """The kick bench's session: trainer commands queued to land in a fixed cycle, the game time read from
    each sense message."""

    def __init__(self, scripts: Path, workdir: Path, behavior: Callable[[WorldModel], list[Action]],
                 robot_type: int = 0) -> None:
        super().__init__(scripts, workdir, behavior, TEAM, UNUM, robot_type)
        self.game_time_s = 0.0
        self._commands: list[str] = []

    def command(self, text: str) -> None:
        """A trainer command, sent in the next cycle before the agent's answer: the server (sync mode) is then
        still waiting for that answer and applies the command at the start of the following cycle, always
        the same one (sent at any moment, it landed one cycle early or late and the kicks differed)."""
        self._commands.append(text)

    def step(self, think: bool = True) -> None:
        """One cycle: read the sense message, send the queued trainer commands, answer the message
        (``think`` False: only ``(syn)``)."""
        payload = self.read()
        start = payload.find(b"(GS ")
        found = _GAME_TIME.search(payload, start) if start >= 0 else None
        if found:
            self.game_time_s = float(found.group(1))
        reply = self.agent.step(payload) if think else b"(syn)"
        for text in self._commands:
            self.send(text)
        self._commands = []
        self.answer(reply)

    def collisions(self) -> int:
        return self.collisions_since(0)


def frame_time_s(frame: bytes) -> float | None:
    """Game time of a monitor frame (None if it carries none)."""
    found = _TIME.search(frame[:4000])
    return float(found.group(1)) if found else None


def parse_truth(frames: Sequence[bytes], workdir: Path) -> dict[int, dict]:
    """Truth by cycle (game time / 20 ms) from monitor frames, starting at the first full state (earlier
    frames are skipped): torso, feet and ball positions [m], the torso's up-axis z, heading, pitch (+ = leaning
    forward) and roll (+ = leaning left) [deg]."""
    from sim.replay import read_log

    start = next((i for i, frame in enumerate(frames) if b"(RSG" in frame[:4000]), None)
    if start is None:
        return {}
    path = workdir / "frames.log"
    path.write_bytes(b"\n".join(frames[start:]) + b"\n")
    out: dict[int, dict] = {}
    for frame in read_log(path):
        robot = frame.robots.get(f"left_{UNUM}")
        if robot is None or frame.ball is None:
            continue
        torso = robot.bodies["torso"]
        forward = torso[:3, 1]
        out[round(frame.time_s / CYCLE_S)] = {
            "time_s": frame.time_s, "torso": tuple(float(v) for v in torso[:3, 3]), "up_z": float(torso[2, 2]),
            "heading_deg": math.degrees(math.atan2(forward[1], forward[0])),
            "pitch_deg": math.degrees(math.asin(max(-1.0, min(1.0, float(-forward[2]))))),
            "roll_deg": math.degrees(math.asin(max(-1.0, min(1.0, float(torso[2, 0]))))),
            "rfoot": tuple(float(v) for v in robot.bodies["rfoot"][:3, 3]),
            "lfoot": tuple(float(v) for v in robot.bodies["lfoot"][:3, 3]),
            "ball": tuple(float(v) for v in frame.ball[:3, 3])}
    return out


def sample_truth(sample: dict) -> Truth:
    """The ``Truth`` of one sample of :func:`parse_truth` (the feet-off-ground flag unknown: False)."""
    return Truth(sample["time_s"], sample["torso"], sample["up_z"], sample["heading_deg"], sample["ball"], False)


def measure(samples: dict[int, dict], motion: str, placement: Placement, ball_start_m: tuple[float, float],
            aim_deg: float, kick_start_s: float, motion_s: float | None) -> KickRun:
    """The KickRun of a real kick from its truth by cycle, measured as ``motion_studio.kick_rollout.run_kick``
    measures ours: the strike is the first cycle the ball moves faster than STRIKE_SPEED_M_S, the foot
    speed is the fastest foot's over the cycle before it, the ball's speed is taken 3 cycles after it.

    Raises:
        ValueError: no truth after the kick's start.
    """
    first = round(kick_start_s / CYCLE_S) + 1
    keys = sorted(k for k in samples if k >= first)
    if not keys:
        raise ValueError(f"no monitor truth after the kick's start at {kick_start_s:.2f} s")
    contact = foot_speed = ball_speed = None
    trapped = fell = False
    height = 0.0
    for key in keys:
        now, before = samples[key], samples.get(key - 1)
        fell = fell or sample_truth(now).fallen
        height = max(height, now["ball"][2] - BALL_Z_M)
        if before is None:
            continue
        ball_v = math.dist(now["ball"], before["ball"]) / CYCLE_S
        if contact is None and ball_v > STRIKE_SPEED_M_S:
            contact = key
            earlier = samples.get(key - 2)
            speeds = [_foot_speed(a, b) for a, b in ((before, now), (earlier, before)) if a is not None]
            foot_speed = max(speeds)
        if contact is not None and key - contact <= 3:
            foot_up = max(now[f][2] - before[f][2] for f in ("rfoot", "lfoot")) / CYCLE_S
            trapped = trapped or foot_up > TRAP_FOOT_UP_M_S or \
                (now["torso"][2] - before["torso"][2]) / CYCLE_S > TRAP_TORSO_UP_M_S
        if contact is not None and key - contact == 3:
            ball_speed = ball_v
    end = samples[keys[-1]]
    contact_s = None if contact is None else round(contact * CYCLE_S - kick_start_s, 3)
    truths = [sample_truth(samples[k]) for k in keys]
    return KickRun(motion, placement, ball_start_m, (end["ball"][0], end["ball"][1]), aim_deg, contact_s,
                   motion_s if motion_s is not None else keys[-1] * CYCLE_S - kick_start_s, fell, trapped, height,
                   foot_speed, ball_speed, truths)


def _foot_speed(before: dict, now: dict) -> float:
    return max(math.dist(now[f][:2], before[f][:2]) for f in ("rfoot", "lfoot")) / CYCLE_S


def launch(samples: dict[int, dict], contact_s: float | None, kick_start_s: float) -> dict[str, float]:
    """Ball velocity over the first two cycles after the strike: speed [m/s], elevation [deg]."""
    if contact_s is None:
        return {}
    key = round((kick_start_s + contact_s) / CYCLE_S)
    a, b = samples.get(key), samples.get(key + 2)
    if a is None or b is None:
        return {}
    v = [(q - p) / (2 * CYCLE_S) for p, q in zip(a["ball"], b["ball"])]
    horizontal = math.hypot(v[0], v[1])
    return {"launch_m_s": round(math.hypot(horizontal, v[2]), 3),
            "elevation_deg": round(math.degrees(math.atan2(v[2], horizontal)), 2)}


# ---- the bench --------------------------------------------------------------------------------------
class RealKickBench:
    """Kick rollouts one after the other on one real server (this namespace); see the module docstring.

    Args:
        workdir: server log, monitor frames.
        config: where the robot stands, how long it stands.
        scripts: the real-server scripts (default: motion_studio.realserver.paths.scripts_dir()).
        dynamic: the controller's dynamic elements (default: the shipped ones).
        robot_type: the robot (0-4) that kicks; ``library`` must hold that type's motions.

    Raises:
        RealServerError: the scripts are missing.
    """

    def __init__(self, workdir: Path, config: RealKickConfig | None = None, scripts: Path | None = None,
                 dynamic: DynamicParams | None = None, robot_type: int = 0) -> None:
        self.dynamic = dynamic
        self.robot_type = robot_type
        self.scripts = checked_scripts_dir(scripts)
        self.workdir = Path(workdir)
        self.config = config or RealKickConfig()
        self.session: _Session | None = None
        self.behavior: SkillBehavior | None = None
        self.restarts = 0
        self._record: list[CycleRecord] | None = None
        self._wake: list[float] = []

    def _behave(self, world: WorldModel) -> list[Action]:
        actions = self.behavior(world)
        if self._wake:
            actions = [a for a in actions if not (isinstance(a, JointVelocity) and a.effector == "he1")]
            actions.append(JointVelocity("he1", self._wake.pop(0)))
        if self._record is not None:
            self._record.append(CycleRecord(
                world.game.game_time_s, self.behavior.motion.phase_name, dict(world.body.joints_rad),
                {a.effector: a.velocity_rad_s for a in actions if isinstance(a, JointVelocity)}))
        return actions

    def _open(self, library: MotionLibrary) -> None:
        self.behavior = SkillBehavior(None, None, self.robot_type, recover_falls=False)
        self.session = _Session(self.scripts, self.workdir, self._behave, self.robot_type)
        for _ in range(6):  # scene, init
            self.session.step()
        # two resets first: every kick then starts from a reset of a robot standing in its stance (measured:
        # after one reset from the zero pose of the connection the robot settled 2.5 mm farther back and
        # 0.15 mm higher, and the shipped kick moved the ball 1.94 m instead of 1.14 m)
        for _ in range(2):
            self._reset(library, self.config.aim_deg)

    def close(self) -> None:
        if self.session is not None:
            self.session.close()
            self.session = None

    def __enter__(self) -> RealKickBench:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def run(self, library: MotionLibrary, motion: str, placement: Placement = Placement(),
            record: bool = False, distance_m: float | None = None) -> RealKickRun:
        """One kick of ``motion`` (``library`` must also hold ``stand``) with the ball at its spot moved by
        ``placement``; a stalled server is restarted and the rollout tried again once.

        Raises:
            KeyError / ValueError: an unknown motion or one without the ball constants.
            RuntimeError: the server stalled twice.
        """
        constants = library.get(motion).constants
        if "ball_forward_m" not in constants or "ball_left_m" not in constants:
            raise ValueError(f"motion {motion!r} has no ball_forward_m / ball_left_m constants")
        for _ in range(2):
            if self.session is None:
                self._open(library)
            try:
                result = self._run(library, motion, placement, record, distance_m)
                result.restarts = self.restarts
                return result
            except (OSError, RuntimeError, ValueError) as error:
                logger.warning("real server stalled (%s); restarting it", error)
                self.close()
                self.restarts += 1
        raise RuntimeError("the real server stalled twice in one rollout")

    def rollout(self, library: MotionLibrary, motion: str, placement: Placement, seed: int = 0) -> KickRun:
        """The tuner's rollout signature (``motion_studio.tune_kick.Rollout``): :meth:`run`'s KickRun. ``seed``
        is unused: in sync mode the real server's physics has no noise, and the kick needs no vision."""
        return self.run(library, motion, placement).run

    def _steps(self, cycles: int, think: bool = True) -> None:
        for _ in range(cycles):
            self.session.step(think)

    def _wait_frame(self, since: int, at_least_s: float) -> None:
        """Until the monitor thread holds, after index ``since``, a full state and a frame with game time >=
        ``at_least_s``."""
        deadline = time.monotonic() + STALL_S
        while True:
            frames = self.session.monitor.frames[since:]
            full = next((i for i, f in enumerate(frames) if b"(RSG" in f[:4000]), None)
            if full is not None and any((frame_time_s(f) or -1.0) >= at_least_s - 1e-6 for f in frames[full:]):
                return
            if time.monotonic() > deadline:
                raise RuntimeError(f"no monitor frame at {at_least_s:.2f} s")
            time.sleep(0.002)

    def _reset(self, library: MotionLibrary, heading_deg: float) -> None:
        """A fresh controller plays ``stand`` where the robot is, the ball is parked, the robot is moved upright
        to the spot facing ``heading_deg`` and stands there ``settle_cycles``."""
        config, session = self.config, self.session
        self.behavior.motion = MotionController(library, self.dynamic or load_dynamic_params(), self.robot_type)
        sx, sy = config.spot_m
        session.command(f"(ball (pos {sx + config.park_ball_m[0]} {sy + config.park_ball_m[1]} {BALL_Z_M})"
                        f"(vel 0 0 0))")
        self.behavior.set_skill(PlayMotion("stand"))
        self._steps(RESET_POSE_CYCLES)
        # the trainer's move angle is the heading - 90 deg (as the beam's, REFERENCE §3.7)
        z = config.move_z_m if config.move_z_m is not None else move_height_m(self.robot_type)
        move = f"(agent (unum {UNUM})(team Left)(move {sx} {sy} {z} {heading_deg - 90.0}))"
        for command in ("(playMode PlayOn)", "(time 0)", move):
            session.command(command)
        self._wake = list(WAKE_HEAD_RAD_S)
        self._steps(config.settle_cycles)

    def _run(self, library: MotionLibrary, motion: str, placement: Placement, record: bool,
             distance_m: float | None = None) -> RealKickRun:
        config, session = self.config, self.session
        behavior = self.behavior
        self._record = None
        collisions = session.collisions()
        self._reset(library, config.aim_deg + placement.heading_deg)
        # the ball at its spot, from the torso's pose now
        since = len(session.monitor.frames)
        session.command("(reqfullstate)")
        self._steps(1)
        now_s = session.game_time_s
        self._wait_frame(since, now_s)
        samples = parse_truth(session.monitor.frames[since:], self.workdir)
        if not samples:
            raise RuntimeError("no full state after the settle")
        start = sample_truth(samples[max(samples)])
        constants = library.get(motion).constants
        aim = start.heading_deg - placement.heading_deg
        spot = ball_spot(start, float(constants["ball_forward_m"]) + placement.forward_m,
                         float(constants["ball_left_m"]) + placement.left_m, aim)
        session.command(f"(ball (pos {spot[0]:.5f} {spot[1]:.5f} {BALL_Z_M})(vel 0 0 0))")
        self._steps(config.stand_cycles)
        # the kick (frames from a full state on, so that the diffs can be followed)
        since = len(session.monitor.frames)
        session.command("(reqfullstate)")
        behavior.set_skill(PlayMotion(motion, distance_m=distance_m))
        if record:
            self._record = []
        kick_start_s = None
        motion_s = None
        skill = behavior.skill
        limit = round(12.0 / CYCLE_S)
        for _ in range(limit):
            session.step()
            if kick_start_s is None:
                kick_start_s = session.game_time_s
            if skill.done:
                motion_s = session.game_time_s - kick_start_s
                break
        cycles, self._record = self._record or [], None
        # the roll: the robot holds still (its last commands were 0), only (syn)
        self._wait_frame(since, session.game_time_s)
        samples = parse_truth(session.monitor.frames[since:], self.workdir)
        contact = measure(samples, motion, placement, spot, aim, kick_start_s, motion_s).contact_s
        end_s = kick_start_s + (contact + ROLL_AFTER_CONTACT_S if contact is not None
                                else (motion_s or 0.0) + ROLL_WITHOUT_CONTACT_S)
        self._steps(max(0, round((end_s - session.game_time_s) / CYCLE_S)), think=False)
        self._wait_frame(since, session.game_time_s)
        samples = parse_truth(session.monitor.frames[since:], self.workdir)
        del session.monitor.frames[:]
        run = measure(samples, motion, placement, spot, aim, kick_start_s, motion_s)
        return RealKickRun(run, kick_start_s, samples, cycles, session.collisions() - collisions)


__all__ = ["CycleRecord", "RealKickBench", "RealKickConfig", "RealKickRun", "ensure_private_network",
           "frame_time_s", "launch", "measure", "parse_truth", "sample_truth"]
