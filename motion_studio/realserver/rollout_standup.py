"""Stand-up rollouts from seeded lying starts, on the real rcssserver3d 0.7.3 or on our simulator alike.

A rollout (``StandUpBench.rollout``) on one running server, reset between rollouts by trainer commands
rather than by a restart (REFERENCE §5.2):

1. **reset**: the agent takes the walk stance (``stand``) wherever it lies, then the trainer moves it upright
   to ``SPOT_M`` at the start's yaw (``(agent (unum 1)(team Left)(move x y 0.4 angle))``: the real server
   turns the torso upright about the vertical and zeroes every body's velocity, ours does the same), and it
   stands still (in the stance: the benchmark's offset poses often tip over backwards on the real server
   before the fall begins);
2. **fall**: raw joint velocities (seeded ankle and hip bursts, left and right apart so it may land
   twisted) tip it onto the start's side; they persist until it lies at rest (gyro and accelerometer);
3. **lying**: it takes the start's pose while lying (the stand-up benchmark's ``prepose``: the walk stance
   with seeded offsets) and comes to rest (as ``Scenario.lay_down`` leaves a robot on our simulator);
4. **stand-up**: the motion to judge (``PlayMotion``), or the agent's ``StandUp`` skill (fall detection,
   side choice and retries included); the game clock is read from the sense messages, the torso's truth
   from the monitor (real) or the world (ours).

"Stood" (issue 12): the torso centre above ``STAND_Z_M`` for ``HOLD_S`` without a break; the time to stand
runs from the stand-up's first cycle to the start of that second. The real server is started in the
current network namespace (``../shared/real-server/netns.sh``); a stalled server (no sense message for
10 s, a closed socket) is restarted and the rollout repeated once.
"""

from __future__ import annotations

import logging
import math
import random
import time
from collections.abc import Callable
from dataclasses import asdict, dataclass, field, replace
from pathlib import Path

from agent.agent import Agent, AgentConfig
from agent.motion import MotionController, MotionLibrary, load_dynamic_params
from agent.protocol.effectors import Action, JointVelocity
from agent.skills.base import PlayMotion
from agent.skills.behavior import SkillBehavior
from agent.skills.standup import StandUp, at_rest, feet_force_n, upright_on_feet
from agent.world_model import WorldModel
from motion_studio.realserver.cases import FALL_SCRIPT_CYCLES
from motion_studio.realserver.session import RealSession
from motions.model import JointTarget, Motion
from agent.protocol.constants import CYCLE_S

logger = logging.getLogger(__name__)

TEAM, UNUM = "Bench", 1
#: The robot's weight, 4.6071 kg for every type (REFERENCE §2.5) [N].
WEIGHT_N = 4.6071 * 9.81
#: Standing (issue 12): torso centre above STAND_Z_M [m] for HOLD_S [s] without a break.
STAND_Z_M = 0.30
HOLD_S = 1.0
#: Where the rollouts happen (own half, nothing near) and the height of the trainer move [m].
SPOT_M = (-6.0, 0.0)
MOVE_Z_M = 0.40
#: Reset: cycles taking the pose before the move, standing after it.
POSE_CYCLES = 25
SETTLE_CYCLES = 30
#: Cycles of the wake-up twitch after the move, and its head-yaw speed [rad/s].
WAKE_CYCLES = 4
WAKE_RAD_S = 0.002
#: Longest wait for the fall to come to rest, and for rest after the lying pose [cycles]; cycles in a row
#: at rest that count (gyro and accelerometer, ``agent.skills.standup.at_rest``).
FALL_MAX_CYCLES = 120
REST_MAX_CYCLES = 40
QUIET_CYCLES = 3
#: Gravity along the torso's own up axis below this = lying [m/s²].
LYING_ACC_Z_M_S2 = 5.0
#: Duration of the lying pose keyframe [ms].
LYING_POSE_MS = 300
#: Length of the stand-up phase: the motion plus AFTER_S, at least MIN_S, at most MAX_S [s].
AFTER_S = 1.6
MIN_S = 4.2
MAX_S = 7.0
#: A rollout ends once the agent has felt itself standing this many cycles beyond HOLD_S.
EARLY_STOP_MARGIN_CYCLES = 10
#: A torso centre above this [m] was lifted by the referee: the Incapable foul (REFERENCE §4.5: on the ground
#: 15 s) lifts the robot to z = 1 for 0.5 s and puts it down standing, which would read as standing up at once.
#: Seen when many failing rollouts ran on one server (the foul's ground time carried over the trainer resets):
#: the rollout is void and runs again on a fresh server.
REFEREE_LIFT_Z_M = 0.7
#: The camera sits this far above the torso centre (REFERENCE §2.3) [m].
CAMERA_ABOVE_TORSO_M = 0.155
#: Bodies whose positions a trace keeps.
TRACE_BODIES = ("lfoot", "rfoot", "llowerarm", "rlowerarm")


# ---- lying starts ------------------------------------------------------------------------------------
@dataclass(frozen=True)
class RealStart:
    """A seeded lying start (see the module docstring); ``noise_seed``: seed of the parameter noise a tuner
    puts on the candidate for this start (None = none)."""

    side: str
    seed: int
    noise_seed: int | None = None
    transfer_seed: int | None = None
    """Not None: the lying start ``seed`` of ``motion-studio transfer --seed transfer_seed`` instead (its case
    that lies on ``side``, ``transfer.vary_fall``): the robot stands in the zero pose, falls by the case's
    script and lies as the script left it (no lying pose)."""

    def transfer_case(self):
        """The transfer case (``cases.Case``) this start copies (``transfer_seed`` set)."""
        from motion_studio.realserver.cases import CASES
        from motion_studio.realserver.transfer import LIES_ON, vary_fall

        name = next(name for name, side in LIES_ON.items() if side == self.side)
        return vary_fall(CASES[name], self.seed, self.transfer_seed)

    def plan(self, attempt: int = 0) -> dict:
        """yaw [deg], the fall script (cycle -> effector -> rad/s), the pose seed, the spot [m] the robot is moved
        to and the cycles it settles there before the fall; ``attempt`` > 0: the
        script of a retry (a fall that ended on the other side), pushed harder towards the side."""
        if self.transfer_seed is not None:
            from motion_studio.realserver.cases import fall_steps

            case = self.transfer_case()
            return {"yaw_deg": case.heading_deg, "script": fall_steps(case), "pose_seed": None,
                    "settle_cycles": case.settle_cycles, "spot_m": case.position_m}
        rng = random.Random(f"real-standup/{self.side}/{self.seed}")
        yaw_deg = round(rng.uniform(-180.0, 180.0), 1)
        # measured: ankles toes-up tip the robot onto its front, toes-down onto its back; hips flexed
        # (torso forward) help the front, extended the back
        sign = 1.0 if self.side == "front" else -1.0
        ankle = sign * rng.uniform(3.0, 4.0)
        hip = sign * (rng.uniform(0.0, 1.5) + 0.75 * attempt)
        skew = rng.uniform(-0.3, 0.3)
        cycles = rng.randint(14, 20)
        script = {0: {"lle5": ankle * (1 + skew), "rle5": ankle * (1 - skew), "lle3": hip, "rle3": hip},
                  cycles: {"lle5": 0.0, "rle5": 0.0, "lle3": 0.0, "rle3": 0.0}}
        return {"yaw_deg": yaw_deg, "script": script, "pose_seed": self.seed, "settle_cycles": SETTLE_CYCLES,
                "spot_m": SPOT_M}


def real_starts(side: str, count: int, seed: int = 0, noise: bool = False) -> tuple[RealStart, ...]:
    """``count`` starts on ``side``; with ``noise`` every start but the first gets a noise seed."""
    return tuple(RealStart(side, seed * 1000 + i, seed * 1000 + 500 + i if noise and i > 0 else None)
                 for i in range(count))


def transfer_starts(side: str, count: int, seed: int = 0) -> tuple[RealStart, ...]:
    """The first ``count`` lying starts on ``side`` of ``motion-studio transfer --seed seed``."""
    return tuple(RealStart(side, i, None, seed) for i in range(count))


# ---- the worlds: the real server, ours ---------------------------------------------------------------
@dataclass
class TruthSample:
    """Ground truth of one cycle: game time [s], torso centre [m], torso up-axis z and forward-axis z, and
    the positions of TRACE_BODIES [m]."""

    time_s: float
    torso_m: tuple[float, float, float]
    up_z: float
    forward_z: float
    bodies: dict[str, tuple[float, float, float]] = field(default_factory=dict)
    rotation: tuple[float, ...] = ()
    """Torso orientation, row-major 3x3 (columns: torso x right, y forward, z up in the field frame)."""


class RealWorld(RealSession):
    """A real server in this network namespace, its monitor connection and our agent's connection."""

    def __init__(self, workdir: Path, behavior: Callable[[WorldModel], list[Action]],
                 scripts: Path | None = None, robot_type: int = 0) -> None:
        from motion_studio.realserver.paths import checked_scripts_dir

        super().__init__(checked_scripts_dir(scripts), workdir, behavior, TEAM, UNUM, robot_type)
        self._log_from = 0

    def mark(self) -> None:
        """Start keeping truth: the frames so far are dropped (memory), a full state is requested (diffs only
        update it)."""
        if not self.monitor.thread.is_alive():
            raise RuntimeError("the monitor connection closed")
        self.monitor.frames.clear()
        self._log_from = self.log_size()
        self.monitor.send("(reqfullstate)")

    def truths(self) -> tuple[dict[int, TruthSample], int]:
        """Truth by game-time cycle since :meth:`mark`, and the self-collisions the server reported.

        Raises:
            RuntimeError: no full state arrived (the monitor connection is gone): the server is restarted.
        """
        from sim.replay import read_log

        first = None
        for _ in range(20):  # the monitor thread catches up
            time.sleep(0.02)
            frames = list(self.monitor.frames)
            first = next((i for i, f in enumerate(frames) if b"(RSG" in f[:4000]), None)
            if first is not None:
                break
        if first is None:
            raise RuntimeError("no full state from the monitor")
        out: dict[int, TruthSample] = {}
        path = self.workdir / "frames.log"
        path.write_bytes(b"\n".join(frames[first:]) + b"\n")
        for frame in read_log(path):
            robot = frame.robots.get(f"left_{UNUM}")
            if robot is not None:
                out[round(frame.time_s / CYCLE_S)] = _sample(frame.time_s, robot.bodies)
        if not out:
            raise RuntimeError("the monitor showed no robot")
        return out, self.collisions_since(self._log_from)


def _sample(time_s: float, bodies: dict) -> TruthSample:
    torso = bodies["torso"]
    return TruthSample(time_s, tuple(float(v) for v in torso[:3, 3]), float(torso[2, 2]), float(torso[2, 1]),
                       {name: tuple(float(v) for v in bodies[name][:3, 3]) for name in TRACE_BODIES if name in bodies},
                       tuple(float(v) for v in torso[:3, :3].reshape(-1)))


class SimWorld:
    """Our simulator with the full referee and the same trainer commands (``sim.rules.trainer``)."""

    def __init__(self, behavior: Callable[[WorldModel], list[Action]], seed: int = 0, robot_type: int = 0) -> None:
        from sim.engine import SimEngine
        from sim.inprocess import InProcessHost

        self.engine = SimEngine(seed=seed)
        self.host = InProcessHost(self.engine)
        self.robot_type = robot_type
        self.agent = Agent(AgentConfig(TEAM, UNUM, robot_type, say=False), behavior)
        self.key = self.host.add(self.agent)
        self._truths: dict[int, TruthSample] | None = None
        self._collisions = 0

    def step(self) -> None:
        import numpy as np

        from sim.rules.self_collision import colliding_pairs

        seen = self.agent.world.game.cycles
        while self.agent.world.game.cycles == seen:
            self.host.run(1)
        if self._truths is None:
            return
        world = self.engine.world
        poses = next((bodies for _, unum, _, bodies in world.robot_body_poses() if unum == UNUM), None)
        if poses is None:
            return
        matrices = {}
        for name, (position, rotation) in poses.items():
            matrix = np.eye(4)
            matrix[:3, :3] = np.array(rotation).reshape(3, 3)
            matrix[:3, 3] = position
            matrices[name] = matrix
        # the world now holds the state the next sense message reports
        cycle = round(self.agent.world.game.game_time_s / CYCLE_S) + 1
        self._truths[cycle] = _sample(cycle * CYCLE_S, matrices)
        self._collisions += bool(colliding_pairs(self.robot_type, poses, 0.04))

    def send(self, command: str) -> None:
        from sim.rules.trainer import apply_trainer_message

        apply_trainer_message(command, self.engine.referee, self.engine.world)

    def mark(self) -> None:
        self._truths, self._collisions = {}, 0

    def truths(self) -> tuple[dict[int, TruthSample], int]:
        return dict(self._truths or {}), self._collisions

    def close(self) -> None:
        pass


# ---- rollouts ----------------------------------------------------------------------------------------
@dataclass
class CycleRecord:
    """What the agent saw in one cycle of the stand-up phase."""

    game_time_s: float
    feet_n: float
    phase: str
    joints_deg: dict[str, float] = field(default_factory=dict)


@dataclass
class StandUpOutcome:
    """What one lying start gave (the fields of ``motion_studio.tune_standup.Rollout`` and more)."""

    time_s: float | None
    """From the stand-up's first cycle until the robot stands for good [s]; None = it did not."""
    final_score: float
    best_score: float
    """Standing-ness in [0, 1] (torso height and up axis) at the end / at its best 0.2 s."""
    min_up_z: float
    self_collisions: int
    best_feet_load: float
    """Largest 0.2 s mean of the vertical foot force over the robot's weight."""
    lying_up_z: float
    lying_forward_z: float
    """The torso's up-axis and forward-axis z when the stand-up started (lying on the back: 0 and +1)."""
    attempts: int = 1
    trace: list[dict] = field(default_factory=list)

    def to_json(self) -> dict:
        return asdict(self)


def lying_pose(stand: Motion, seed: int, name: str = "bench_pose") -> Motion:
    """The start's pose: the stand-up benchmark's ``prepose`` (the walk stance with seeded offsets), reached
    in LYING_POSE_MS."""
    from motion_studio.skill_bench.standup import prepose

    motion = prepose(stand, random.Random(seed), name=name)
    return replace(motion, keyframes=[replace(motion.keyframes[0], duration_s=LYING_POSE_MS / 1000.0)])


#: The all-zero pose a transfer start stands in before its fall (the robot as it connects).
ZERO_POSE = "bench_zero_pose"


def zero_pose(stand: Motion) -> Motion:
    """Every joint of ``stand``'s last keyframe at 0 deg, reached in LYING_POSE_MS."""
    last = stand.keyframes[-1]
    targets = {name: JointTarget.from_deg(0.0) for name in last.targets}
    keyframe = replace(last, name="zero", duration_s=LYING_POSE_MS / 1000.0, targets=targets, set_flag_true=None,
                       source=None)
    return Motion(ZERO_POSE, [keyframe], source_format=stand.source_format, first_phase="zero")


class StandUpBench:
    """Stand-up rollouts one after the other on one server (real or ours), reset by trainer commands.

    Args:
        make_world: behaviour -> a world (``RealWorld`` or ``SimWorld``) with a robot of ``robot_type``;
            called again after a stall.
        base_library: the motions besides the judged ones (``stand``, the other stand-ups, ``roll_to_back``)
            for ``robot_type``.
        robot_type: 0-4.
    """

    def __init__(self, make_world: Callable[[Callable[[WorldModel], list[Action]]], object],
                 base_library: MotionLibrary, robot_type: int = 0) -> None:
        self.make_world = make_world
        self.base_library = base_library
        self.robot_type = robot_type
        self.world = None
        self.inner: SkillBehavior | None = None
        self._raw: dict[str, float] | None = None
        self._scripted = False
        self._wake = 0

    def _behave(self, world: WorldModel) -> list[Action]:
        if self._scripted:  # the fall: only the script's commands (velocities persist on the server)
            raw, self._raw = self._raw or {}, None
            return [JointVelocity(name, value) for name, value in raw.items()]
        actions = self.inner(world)
        if self._wake > 0:
            # The real server lets a robot at rest fall asleep (ODE auto-disable); a trainer move keeps it
            # asleep, hanging where it was put, until a joint gets a non-zero command (hingeeffector.cpp
            # enables the body then). A tiny head-yaw twitch, sent last so it wins, wakes it.
            self._wake -= 1
            actions.append(JointVelocity("he1", WAKE_RAD_S if self._wake % 2 else -WAKE_RAD_S))
        return actions

    def _open(self) -> None:
        self.inner = SkillBehavior(MotionController(self.base_library, load_dynamic_params(), self.robot_type), None,
                                   self.robot_type, False)
        self.world = self.make_world(self._behave)
        while self.world.agent.world.game.unum is None:  # connected: scene, init
            self.world.step()

    def close(self) -> None:
        if self.world is not None:
            self.world.close()
            self.world = None

    def rollout(self, motions: dict[str, Motion], play: str, start: RealStart, use_skill: bool = False,
                trace: bool = False) -> StandUpOutcome:
        """One rollout from ``start``: ``motions`` replace the library's motions of the same names, ``play`` is
        the stand-up played (or, with ``use_skill``, the skill chooses). Raises RuntimeError when the server
        stalls twice in a row."""
        for _ in range(2):
            if self.world is None:
                self._open()
            try:
                return self._rollout(motions, play, start, use_skill, trace)
            except (OSError, RuntimeError) as error:
                logger.warning("server stalled or rollout void (%s); restarting it", error)
                self.close()
        raise RuntimeError("the server stalled twice in a row")

    def _run(self, cycles: int, until: Callable[[], bool] | None = None) -> None:
        for _ in range(cycles):
            self.world.step()
            if until is not None and until():
                return

    def _resting(self) -> Callable[[], bool]:
        body_world = self.world.agent.world
        quiet = [0]

        def rested() -> bool:
            lying = abs(body_world.body.acc_m_s2[2]) < LYING_ACC_Z_M_S2
            quiet[0] = quiet[0] + 1 if lying and at_rest(body_world) else 0
            return quiet[0] >= QUIET_CYCLES
        return rested

    def _rollout(self, motions: dict[str, Motion], play: str, start: RealStart, use_skill: bool,
                 trace: bool) -> StandUpOutcome:
        world, inner = self.world, self.inner
        body_world = world.agent.world
        plan = start.plan()
        library = MotionLibrary({name: self.base_library.get(name) for name in self.base_library.names})
        library.webots_timing.update(self.base_library.webots_timing)
        library.gain_bases.update(self.base_library.gain_bases)
        for motion in motions.values():
            library.add(motion)
        copy = start.transfer_seed is not None  # a transfer start: zero pose, its fall, lying as it fell
        pose = None if copy else library.get(library.add(lying_pose(library.get("stand"), plan["pose_seed"])))
        if copy:
            library.add(zero_pose(library.get("stand")))
        inner.motion = MotionController(library, load_dynamic_params(), self.robot_type)
        # 1. reset (the game clock back to 0 each time keeps it far from half time)
        world.send("(playMode PlayOn)")
        world.send("(time 0)")
        if trace:
            world.mark()
        inner.set_skill(PlayMotion(ZERO_POSE if copy else "stand"))
        self._run(POSE_CYCLES)
        if copy:
            inner.set_skill(None)  # the transfer's robot holds the zero pose with no skill
        spot = plan["spot_m"]
        world.send(f"(agent (unum {UNUM})(team Left)(move {spot[0]} {spot[1]} {MOVE_Z_M} "
                   f"{plan['yaw_deg'] - 90.0}))")
        self._wake = WAKE_CYCLES
        self._run(plan["settle_cycles"])
        # 2. the fall
        inner.set_skill(None)
        script = plan["script"]
        self._scripted = True
        try:
            for cycle in range(FALL_SCRIPT_CYCLES if copy else max(script) + 1):
                self._raw = script.get(cycle)
                world.step()
        finally:
            self._scripted = False
        if not copy:
            self._run(FALL_MAX_CYCLES, self._resting())
            # 3. lying in the pose, at rest
            inner.set_skill(PlayMotion(pose.name))
            self._run(round(LYING_POSE_MS / 1000 / CYCLE_S) + 2)
            inner.set_skill(None)
            self._run(REST_MAX_CYCLES, self._resting())
        # 4. the stand-up
        if not trace:
            world.mark()
        skill = StandUp() if use_skill else PlayMotion(play)
        inner.set_skill(skill)
        start_time_s = body_world.game.game_time_s
        limit_s = MAX_S if use_skill else min(MAX_S, max(MIN_S, library.get(play).duration_s + AFTER_S))
        records = []
        upright = 0
        for _ in range(round(limit_s / CYCLE_S)):
            world.step()
            # the agent's own sense of standing ends a rollout early (the truth decides the figures): upright
            # on loaded feet with the torso centre, from the camera height above the soles, over STAND_Z_M
            torso_z = body_world.body.camera_height_m - CAMERA_ABOVE_TORSO_M * body_world.body.up_z
            upright = upright + 1 if upright_on_feet(body_world) and torso_z > STAND_Z_M + 0.01 else 0
            if upright > round(HOLD_S / CYCLE_S) + EARLY_STOP_MARGIN_CYCLES:
                break
            records.append(CycleRecord(body_world.game.game_time_s, feet_force_n(body_world),
                                       f"{inner.motion.motion_name or ''}:{inner.motion.phase_name or ''}",
                                       {k: round(math.degrees(v), 1) for k, v in body_world.body.joints_rad.items()}
                                       if trace else {}))
        samples, collisions = world.truths()
        reason = void_reason(samples, start_time_s)
        if reason:
            raise RuntimeError(f"rollout void: {reason}")
        outcome = outcome_of(samples, records, start_time_s, collisions)
        outcome.attempts = skill.attempts if use_skill else 1
        if trace:
            outcome.trace = [{"t": round(s.time_s, 2), "z": round(s.torso_m[2], 3), "x": round(s.torso_m[0], 3),
                              "y": round(s.torso_m[1], 3), "up_z": round(s.up_z, 3), "fwd_z": round(s.forward_z, 3),
                              "rotation": [round(v, 4) for v in s.rotation],
                              **{k: [round(v, 3) for v in p] for k, p in s.bodies.items()}}
                             for _, s in sorted(samples.items())]
            by_cycle = {round(r.game_time_s / CYCLE_S): r for r in records}
            for row in outcome.trace:
                record = by_cycle.get(round(row["t"] / CYCLE_S))
                if record is not None:
                    row.update(phase=record.phase, feet_n=round(record.feet_n, 1), joints=record.joints_deg)
        return outcome


def void_reason(samples: dict[int, TruthSample], start_time_s: float) -> str | None:
    """Why the stand-up phase from ``start_time_s`` says nothing about the stand-up (None: it is valid): the
    robot was not lying when it began, or the referee lifted it (``REFEREE_LIFT_Z_M``)."""
    phase = [samples[k] for k in sorted(samples) if samples[k].time_s >= start_time_s - 1e-6]
    if any(sample.torso_m[2] > REFEREE_LIFT_Z_M for sample in phase):
        return "the referee lifted the robot (Incapable foul)"
    if phase and phase[0].torso_m[2] > STAND_Z_M:
        return "the robot was up when the stand-up began"
    return None


def outcome_of(samples: dict[int, TruthSample], records: list[CycleRecord], start_time_s: float,
               collisions: int) -> StandUpOutcome:
    """The figures of a stand-up phase from the truth by game-time cycle and the agent's records."""
    series, last = [], None
    for record in records:
        last = samples.get(round(record.game_time_s / CYCLE_S)) or last  # a missing frame: the previous one
        series.append(last)
    first = next((s for s in series if s is not None), None)
    if first is None:
        return StandUpOutcome(None, 0.0, 0.0, 1.0, collisions, 0.0, math.nan, math.nan)
    series = [s or first for s in series]
    hold = round(HOLD_S / CYCLE_S)
    run, stood = 0, None
    for index, sample in enumerate(series):
        run = run + 1 if sample.torso_m[2] > STAND_Z_M else 0
        if run >= hold:
            stood = index + 1 - hold
            break
    scores = [(min(1.0, max(0.0, s.torso_m[2] / 0.34)) + min(1.0, max(0.0, s.up_z))) / 2.0 for s in series]
    loads = [min(1.0, r.feet_n / WEIGHT_N) for r in records]
    lead_s = records[0].game_time_s - start_time_s  # the first record is the stand-up's first cycle
    return StandUpOutcome(None if stood is None else round(stood * CYCLE_S + lead_s, 2),
                          sum(scores[-25:]) / len(scores[-25:]), _best_mean(scores, 10),
                          min(s.up_z for s in series), collisions, _best_mean(loads, 10), first.up_z, first.forward_z)


def _best_mean(values: list[float], width: int) -> float:
    if len(values) < width:
        return sum(values) / max(1, len(values))
    return max(sum(values[i:i + width]) / width for i in range(len(values) - width + 1))
