"""Tune a stand-up's parameters on our simulator with CMA-ES, checkpointing every generation.

Each candidate: StandUpParams -> keyframes (``motions.authoring.standup``) -> the real agent plays the motion
on our simulator (``motion_studio.scenarios.Scenario``) from a few lying starts (the robot laid down from
the walk stance at a seeded yaw, nudged by a seeded push and spin, left to settle). The loss of a start is
the time from the motion's start until the robot stands for good (torso above 0.30 m, up axis z above 0.9,
feet carrying the robot), or, if it never does, 6 s plus how far it stayed from standing (at the end and at
its best moment) and how much of its weight its feet ever carried. Penalties: a torso turned upside down (a flip is fragile), the server's self-collision
rule firing (it would freeze joints in a match, REFERENCE §4.5), the simulator's blow-up guard firing (a
hinge driven far past its stop, e.g. an arm crushed under the body). The candidate's loss is the mean over the starts; with ``--noise`` every start but the first plays
the candidate with seeded noise on its durations and angles, so that knife-edge candidates lose. With
``--target-s T --time-weight W`` a start that stands later than T s adds W per second late (the benchmark
counts a stand within 3 s of the fall, detection included, so the motion must beat 3 s by that much on
every start, not on average). ``--timing-only`` tunes the durations and the crouch / rise keyframes and keeps
the ground phases' angles.

``--backend real`` judges the candidates on the real rcssserver3d 0.7.3 instead (one server per worker, each
in its own loopback namespace; seeded scripted falls as lying starts, the robot reset between rollouts by
trainer commands: ``motion_studio.realserver.standup_backend``); ``--backend both`` judges them on the real
server and on ours (its own lay-down starts, ``--sim-starts``; loss: real + ``--sim-weight`` x ours). With
``--transfer-starts`` the real starts are those of ``motion-studio transfer --seed <--starts-seed>`` (the robot
falls from the zero pose by the transfer case's script and the StandUp skill plays the candidate, as there; with
``both`` ours plays them too). The real server's contacts
stick (no Coulomb limit, REFERENCE §2.4): a stand-up that drags the feet or the lying torso across the ground,
as ours allows, fails there.

``--type N`` tunes robot type N's own stand-up (REFERENCE §2.5; types 1 and 3 have longer legs): the candidates'
crouch and rise are solved with that type's kinematics (as ``motions.authoring.standup_types`` writes them; the
crouch may be as much higher as the legs are longer), a robot of that type plays them on every backend, the
parameters come from and ``--write`` goes to ``motions/params/standup_type<N>.toml`` (made from
``standup.toml`` if missing; the shared file is never written) and the files to ``motions/files/type<N>/``.

Run::

    python -m motion_studio.tune_standup standup_front --generations 60 --write
    motion-studio tune standup standup_back --backend both --starts 8 --noise --workers 2
    motion-studio tune standup standup_front --type 1 --backend both --transfer-starts --starts 4 --sim-starts 0

The run folder (``out/tuning/standup_<section>``: checkpoint, trace of every evaluation, plots;
``motion_studio.tuning``) is checkpointed after each generation; running the same command again resumes from
it. ``--write`` puts the best parameters into ``motions/params/standup.toml``
(with a provenance line) and regenerates the motion files.
"""

from __future__ import annotations

import argparse
import json
import math
import random
from dataclasses import dataclass, replace
from functools import lru_cache, partial
from pathlib import Path

import numpy as np

from agent.motion import MotionController, MotionLibrary, default_library, load_dynamic_params
from agent.protocol.constants import CYCLE_S
from agent.skills.base import PlayMotion
from motion_studio.scenarios import Scenario
from motion_studio.tuning import BatchBackend, Parameter, Problem, make_backend
from motion_studio.tuning.session import one_line_errors, run_cmaes
from motion_studio.tuning.params_file import Provenance, write_file
from motion_studio.tuning.run_folder import best_evaluation, default_run_dir
from motions.authoring.standup import (PARAMS_PATH, STANDUPS, GroundPose, SagittalSolver, StandUpParams,
                                       build_standup, dumps_section, load_standup_params, read_meta, stance_params,
                                       write_all)
from motions.model import Motion

#: Standing for the loss: torso centre height [m], up axis z, summed foot force [N], for HOLD_S.
STAND_Z_M = 0.30
STAND_UP_Z = 0.9
STAND_FEET_N = 30.0
HOLD_S = 0.5
#: A rollout lasts the motion plus this, at most MAX_S [s].
AFTER_S = 1.2
MAX_S = 5.0
#: Cycles in the walk stance before the lay-down; cycles lying before the motion starts.
STANCE_CYCLES = 30
SETTLE_CYCLES = 15
#: The robot's weight, 4.6071 kg for every type (REFERENCE §2.5) [N].
WEIGHT_N = 4.6071 * 9.81
#: Loss terms.
FAIL_LOSS = 6.0
INVERTED_UP_Z = -0.45
INVERTED_LOSS = 3.0
SELF_COLLISION_LOSS = 0.5
SELF_COLLISION_CAP = 6
BLOWUP_LOSS = 2.0
#: Default late-stand term (off): seconds past TARGET_S cost TIME_WEIGHT each.
TARGET_S = 6.0
TIME_WEIGHT = 0.0


#: Bounds of the ground-phase joints (left side, SimSpark degrees; inside the joint limits) and durations.
GROUND_BOUNDS: dict[str, tuple[float, float, bool]] = {
    "duration_ms": (60, 600, True), "hip_yaw_pitch_deg": (-89.0, 0.0, False), "hip_roll_deg": (-20.0, 40.0, False),
    "hip_pitch_deg": (-24.0, 99.0, False), "knee_deg": (-129.0, 0.0, False), "ankle_pitch_deg": (-44.0, 74.0, False),
    "ankle_roll_deg": (-40.0, 20.0, False),
    "shoulder_pitch_deg": (-119.0, 119.0, False), "shoulder_roll_deg": (-0.5, 94.0, False),
    "elbow_yaw_deg": (-119.0, 119.0, False), "elbow_roll_deg": (0.0, 89.0, False),
}
#: Bounds of the crouch / rise parameters.
POSE_BOUNDS: dict[str, tuple[float, float, bool]] = {
    "ready_ms": (100, 400, True),
    "crouch_pitch_deg": (0.0, 45.0, False), "crouch_height_m": (0.26, 0.32, False),
    "crouch_com_forward_m": (-0.02, 0.05, False), "crouch_shoulder_pitch_deg": (-119.0, 90.0, False),
    "crouch_ms": (100, 600, True), "rise_com_forward_m": (-0.02, 0.04, False), "rise_ms": (100, 600, True),
    "stance_ms": (200, 600, True),
}


def _dimension(path: str, low: float, high: float, integer: bool) -> Parameter:
    """A tuned parameter named by its dotted path (``crouch_ms``, ``ground.1.knee_deg``)."""
    return Parameter(path, low, high, step=1 if integer else 0.0, decimals=3)


def leg_extra_m(robot_type: int) -> float:
    """How much longer the legs of ``robot_type`` are than type 0's, hip to sole [m] (REFERENCE §2.5: 0.0366
    for type 1, 0.0557 for type 3, 0 for the others)."""
    from kinematics.fk import NaoKinematics

    def sole_below_torso(kind: int) -> float:  # zero pose
        return -float(NaoKinematics(kind).frame_pose("lsole").position_m[2])

    return round(sole_below_torso(robot_type) - sole_below_torso(0), 4)


def pose_bounds(robot_type: int = 0) -> dict[str, tuple[float, float, bool]]:
    """POSE_BOUNDS for ``robot_type``: the crouch height's upper bound raised by how much longer its legs are,
    the lower one by half that (type 3's crouch is out of reach below ~0.27 m at the usual leans, so a quarter
    of the candidates of a first type-3 run were void)."""
    low, high, integer = POSE_BOUNDS["crouch_height_m"]
    extra = leg_extra_m(robot_type)
    return {**POSE_BOUNDS, "crouch_height_m": (round(low + extra / 2, 4), round(high + extra, 4), integer)}


def dimensions(params: StandUpParams, frozen: frozenset[str] = frozenset(), timing_only: bool = False,
               robot_type: int = 0) -> list[Parameter]:
    """Every tuned parameter of a stand-up with its bounds; ``frozen`` names
    ground phases (or ``ready``) kept as they are; ``timing_only`` keeps the ground phases' angles (their
    durations and the crouch / rise parameters are tuned); ``robot_type``: the crouch may be higher on longer
    legs (:func:`pose_bounds`)."""
    dims = [_dimension(name, *bounds) for name, bounds in pose_bounds(robot_type).items()
            if not (name == "ready_ms" and ("ready" in frozen or params.ready_ms == 0))]
    for index, pose in enumerate(params.ground):
        if pose.name not in frozen:
            dims += [_dimension(f"ground.{index}.{name}", *bounds) for name, bounds in GROUND_BOUNDS.items()
                     if not timing_only or name == "duration_ms"]
    return dims


def get_value(params: StandUpParams, path: str) -> float:
    parts = path.split(".")
    if parts[0] == "ground":
        return float(getattr(params.ground[int(parts[1])], parts[2]))
    return float(getattr(params, path))


def with_values(params: StandUpParams, values: dict[str, float]) -> StandUpParams:
    """A copy of ``params`` with the dotted-path values replaced."""
    top = {k: v for k, v in values.items() if not k.startswith("ground.")}
    ground = list(params.ground)
    for path, value in values.items():
        if path.startswith("ground."):
            _, index, name = path.split(".")
            ground[int(index)] = replace(ground[int(index)], **{name: value})
    return replace(params, ground=tuple(ground), **top)


@dataclass(frozen=True)
class Start:
    """A lying start: the pose before the lay-down (None = the walk stance, else the seed of a
    ``skill_bench.standup.prepose``), yaw [deg], torso push [m/s] and spin [rad/s] right after the lay-down,
    and the seed of the noise put on the candidate's parameters for this start (None = none)."""

    pose_seed: int | None
    yaw_deg: float
    push_m_s: tuple[float, float, float]
    spin_rad_s: tuple[float, float, float]
    noise_seed: int | None = None
    twist_deg: float = 0.0
    """Turn about the long axis at the lay-down (``Scenario.lay_down``)."""


#: Parameter noise of a noisy start: durations scaled by 1 +- DURATION_NOISE, ground-phase angles moved by up
#: to ANGLE_NOISE_DEG, crouch lean by up to ANGLE_NOISE_DEG and height by up to HEIGHT_NOISE_M (uniform). A
#: candidate that only works exactly as written is a knife edge; one that works under this noise is not.
DURATION_NOISE = 0.08
ANGLE_NOISE_DEG = 3.0
HEIGHT_NOISE_M = 0.005


def noisy(params: StandUpParams, seed: int) -> StandUpParams:
    """``params`` with seeded noise on durations, ground-phase angles and the crouch (see the constants)."""
    rng = random.Random(seed)

    def ms(value: int) -> int:
        return max(20, int(round(value * (1.0 + rng.uniform(-DURATION_NOISE, DURATION_NOISE)))))

    ground = []
    for pose in params.ground:
        changes: dict[str, float] = {"duration_ms": ms(pose.duration_ms)}
        for name, (low, high, _) in GROUND_BOUNDS.items():
            if name != "duration_ms":
                value = getattr(pose, name) + rng.uniform(-ANGLE_NOISE_DEG, ANGLE_NOISE_DEG)
                changes[name] = min(high, max(low, value))
        ground.append(replace(pose, **changes))
    return replace(params, ground=tuple(ground), ready_ms=ms(params.ready_ms) if params.ready_ms else 0,
                   crouch_ms=ms(params.crouch_ms),
                   rise_ms=ms(params.rise_ms), stance_ms=ms(params.stance_ms),
                   crouch_pitch_deg=params.crouch_pitch_deg + rng.uniform(-ANGLE_NOISE_DEG, ANGLE_NOISE_DEG),
                   crouch_height_m=params.crouch_height_m + rng.uniform(-HEIGHT_NOISE_M, HEIGHT_NOISE_M))


def default_starts(count: int = 4, seed: int = 1, noise: bool = False) -> tuple[Start, ...]:
    """The first start from the walk stance, then starts drawn like the benchmark's lying trials
    (``motion_studio.skill_bench.standup``: seeded poses near the stance, yaw, twist, push, spin); the lying
    body comes to rest on its flat torso, so the pose matters most."""
    from motion_studio.skill_bench.standup import PUSH_M_S, SPIN_RAD_S, TWIST_DEG, random_vector

    rng = random.Random(f"tune_standup/{seed}")
    starts = [Start(None, 0.0, (0.0, 0.0, 0.0), (0.0, 0.0, 0.0))]
    for index in range(count - 1):
        yaw = round(rng.uniform(-180.0, 180.0), 1)
        twist = round(rng.uniform(-TWIST_DEG, TWIST_DEG), 1)
        push = random_vector(rng, PUSH_M_S, horizontal=True)
        spin = random_vector(rng, SPIN_RAD_S)
        starts.append(Start(seed * 100 + index, yaw, push, spin, seed * 100 + 50 + index if noise else None, twist))
    return tuple(starts)


@dataclass
class Rollout:
    """What one start gave."""

    time_s: float | None
    """From the motion's start until the robot stands for good [s]; None = it did not."""
    final_score: float
    best_score: float
    """Standing-ness in [0, 1] (torso height and up axis) at the end / at its best 0.2 s."""
    min_up_z: float
    self_collisions: int
    blowups: int
    """Cycles the simulator restarted because the robot's physics blew up (a hinge far past its stop)."""
    best_feet_load: float = 0.0
    """Largest 0.2 s mean of the vertical foot force over the robot's weight (the weight on the feet is
    what a stand-up must reach; it shapes the loss of the failures)."""
    target_s: float = TARGET_S
    time_weight: float = TIME_WEIGHT
    """Late-stand term: each second past ``target_s`` [s] costs ``time_weight``."""

    @property
    def loss(self) -> float:
        loss = self.time_s + self.time_weight * max(0.0, self.time_s - self.target_s) if self.time_s is not None else \
            FAIL_LOSS + 3.0 * (1.0 - self.final_score) + 3.0 * (1.0 - self.best_score) + \
            2.0 * (1.0 - self.best_feet_load)
        loss += BLOWUP_LOSS * min(self.blowups, 3)
        if self.min_up_z < INVERTED_UP_Z:
            loss += INVERTED_LOSS
        return loss + SELF_COLLISION_LOSS * min(self.self_collisions, SELF_COLLISION_CAP)


@lru_cache(maxsize=1)
def _stand_motion() -> Motion:
    """The shipped walk stance (read once per process)."""
    return default_library(0).get("stand")


@lru_cache(maxsize=5)
def solver_for(robot_type: int) -> SagittalSolver:
    """The crouch / rise solver with ``robot_type``'s kinematics (one per process and type)."""
    return SagittalSolver(robot_type)


def rollout(motion: Motion, side: str, start: Start, seed: int = 0, robot_type: int = 0) -> Rollout:
    """Play ``motion`` on a robot of ``robot_type`` laid on ``side`` from ``start`` (the real agent, no fall
    recovery)."""
    import mujoco

    from sim.rules.self_collision import colliding_pairs

    from motion_studio.skill_bench.standup import prepose

    library = MotionLibrary({"stand": _stand_motion(), motion.name: motion})
    first = "stand"
    if start.pose_seed is not None:
        first = library.add(prepose(_stand_motion(), random.Random(start.pose_seed)))
    scenario = Scenario(PlayMotion(first), seed=seed, recover_falls=False, robot_type=robot_type,
                        controller=MotionController(library, load_dynamic_params(), robot_type))
    scenario.run(STANCE_CYCLES)
    scenario.lay_down(side, start.yaw_deg, start.twist_deg)
    scenario.push(start.push_m_s, start.spin_rad_s)
    scenario.run(SETTLE_CYCLES)
    scenario.set_skill(PlayMotion(motion.name))
    data = scenario.world.data
    warnings = data.warning[mujoco.mjtWarning.mjWARN_BADQACC].number
    divergences = getattr(scenario.world, "divergences", 0)
    cycles = round(min(MAX_S, motion.duration_s + AFTER_S) / CYCLE_S)
    scores, standing, min_up, collisions, loads, blowups = [], [], 1.0, 0, [], 0
    for cycle in range(cycles):
        truth = scenario.run(1)[0]
        if (data.warning[mujoco.mjtWarning.mjWARN_BADQACC].number != warnings
                or getattr(scenario.world, "divergences", 0) != divergences):
            # the simulator put the robot back to the cycle's start at rest (a joint far past its stop)
            blowups += 1
            warnings = data.warning[mujoco.mjtWarning.mjWARN_BADQACC].number
            divergences = getattr(scenario.world, "divergences", 0)
        if cycle % 2 == 0 and colliding_pairs(robot_type, scenario.engine.robot_body_poses()[0][3], 0.04):
            collisions += 1
        forces = scenario.world.foot_forces(scenario.key).values()
        feet = sum(float(np.linalg.norm(force)) for _, force in forces)
        loads.append(min(1.0, sum(max(0.0, float(force[2])) for _, force in forces) / WEIGHT_N))
        min_up = min(min_up, truth.up_z)
        scores.append((min(1.0, max(0.0, truth.torso_m[2] / 0.34)) + min(1.0, max(0.0, truth.up_z))) / 2.0)
        standing.append(truth.torso_m[2] > STAND_Z_M and truth.up_z > STAND_UP_Z and feet > STAND_FEET_N)
    first = len(standing)
    while first > 0 and standing[first - 1]:
        first -= 1
    held = len(standing) - first >= round(HOLD_S / CYCLE_S)
    window = np.convolve(scores, np.ones(10) / 10, mode="valid")
    load = np.convolve(loads, np.ones(10) / 10, mode="valid")
    return Rollout(round(first * CYCLE_S, 2) if held else None, float(np.mean(scores[-25:])),
                   float(window.max()) if window.size else 0.0, min_up, collisions, blowups,
                   float(load.max()) if load.size else 0.0)


def evaluate(section: str, params: StandUpParams, starts: tuple[Start, ...], target_s: float = TARGET_S,
             time_weight: float = TIME_WEIGHT, robot_type: int = 0) -> dict[str, object]:
    """Loss and per-start figures of one candidate (a pose out of reach is a failed candidate); see
    :class:`Rollout` for ``target_s`` and ``time_weight``; ``robot_type``: the crouch and rise are solved with
    its kinematics and a robot of that type plays the motion."""
    side = STANDUPS[section]
    stance = stance_params()
    runs = []
    for i, start in enumerate(starts):
        try:
            candidate = params if start.noise_seed is None else noisy(params, start.noise_seed)
            motion = build_standup(section, candidate, side, stance, solver=solver_for(robot_type))
        except ValueError as error:
            return {"loss": 2 * FAIL_LOSS + 6.0, "error": str(error)}
        runs.append(replace(rollout(motion, side, start, seed=i, robot_type=robot_type), target_s=target_s,
                            time_weight=time_weight))
    losses = [run.loss for run in runs]
    return {"loss": float(np.mean(losses)), "losses": [round(v, 3) for v in losses],
            "times_s": [run.time_s for run in runs], "self_collisions": [run.self_collisions for run in runs]}


def _evaluate_values(section: str, base: StandUpParams, starts: tuple[Start, ...], target_s: float, time_weight: float,
                     robot_type: int, values: dict[str, float]) -> dict[str, object]:
    """:func:`evaluate` of the base with the dotted-path ``values`` put in (runs in worker processes)."""
    return evaluate(section, with_values(base, values), starts, target_s, time_weight, robot_type)


def tune(section: str, base: StandUpParams, generations: int, starts: tuple[Start, ...], sigma: float = 0.1,
         popsize: int | None = None, workers: int = 1, checkpoint: Path | None = None, seed: int = 0,
         frozen: frozenset[str] = frozenset(), log=print, timing_only: bool = False, target_s: float = TARGET_S,
         time_weight: float = TIME_WEIGHT, evaluator=None, bar: bool = False, robot_type: int = 0,
         command: str | None = None) -> dict:
    """CMA-ES over :func:`dimensions` around ``base`` in the run folder ``checkpoint`` (default
    ``out/tuning/standup_<section>``); returns the best {"loss", "values", "result"}.

    ``evaluator``: judges a generation at once (``evaluator.evaluate(list of StandUpParams)``, e.g. the real
    server's ``motion_studio.realserver.standup_backend.RealEvaluator``); None = :func:`evaluate` on our
    simulator from ``starts`` in ``workers`` processes; ``robot_type``: see :func:`evaluate`; ``command``: the
    command line, kept in the run folder's trace (``--write-only`` writes it into the provenance later)."""
    dims = dimensions(base, frozen, timing_only, robot_type)
    problem = Problem(f"standup:{section}" + (f":type{robot_type}" if robot_type else ""), tuple(dims),
                      partial(_evaluate_values, section, base, starts, target_s, time_weight, robot_type),
                      start={d.name: get_value(base, d.name) for d in dims}, fail_loss=2 * FAIL_LOSS + 6.0,
                      rollouts_per_candidate=len(starts))
    if evaluator is not None:
        backend = BatchBackend("real", lambda batch: evaluator.evaluate([with_values(base, v) for v in batch]))
    else:
        backend = make_backend("inprocess", workers)
    try:
        result = run_cmaes(problem, checkpoint or default_run_dir(f"standup_{section}"), generations, sigma, popsize,
                           seed, backend, log, bar, meta={"command": command} if command else None)
    finally:
        if evaluator is None:
            backend.close()
    return {"loss": result.best["loss"], "values": result.best["values"], "result": result.best["result"],
            "run_dir": str(result.run_dir)}


TYPE_FILE_HEADER = """# Stand-up parameters of robot type {robot_type} (REFERENCE §2.5), read by
# motions/authoring/standup_types.py
# (python -m motions.authoring.standup_types writes motions/files/type{robot_type}/standup_*.xml). Same layout and
# units as motions/params/standup.toml; the crouch and rise are solved with type {robot_type}'s kinematics.
# Tuned with python -m motion_studio.tune_standup <section> --type {robot_type} (rewrites a section).
"""


def type_params_file(robot_type: int) -> Path:
    """Where ``--type N`` reads and writes its parameters: ``motions/params/standup_type<N>.toml`` (type 0: the
    shared ``standup.toml``). Types 2 and 4 without a file of their own play the shared parameters."""
    return PARAMS_PATH if robot_type == 0 else PARAMS_PATH.with_name(f"standup_type{robot_type}.toml")


def seed_type_file(path: Path, robot_type: int, seed_from: Path = PARAMS_PATH) -> None:
    """Make a type's parameter file from the stand-up sections of ``seed_from`` (provenance: copied)."""
    sections = load_standup_params(seed_from)
    parts = [TYPE_FILE_HEADER.format(robot_type=robot_type)]
    for name in STANDUPS:
        meta = {"provenance": f"copied from [{name}] of {seed_from.name} (type 0's parameters), not tuned for "
                              f"type {robot_type}"}
        parts.append(dumps_section(name, sections[name], meta))
    write_file(path, "\n".join(parts), load_standup_params)


def write_best(section: str, params: StandUpParams, provenance: str, measured: str = "",
               path: Path = PARAMS_PATH, seed_from: Path = PARAMS_PATH, robot_type: int = 0) -> None:
    """Rewrite ``section`` of the parameter file (other sections and the header comments kept). A file that
    does not exist yet is first made from ``seed_from`` (:func:`seed_type_file`)."""
    if not path.exists():
        seed_type_file(path, robot_type, seed_from)
    text = path.read_text(encoding="utf-8")
    header_lines = []
    for line in text.splitlines():
        if not line.startswith("#") and line.strip():
            break
        header_lines.append(line)
    sections = load_standup_params(path)
    sections[section] = params
    parts = ["\n".join(header_lines).rstrip() + "\n"]
    for name, value in sections.items():
        meta = read_meta(path, name)
        if name == section:
            meta = {"provenance": provenance, **({"measured": measured} if measured else {})}
        parts.append(dumps_section(name, value, meta))
    write_file(path, "\n".join(parts), load_standup_params)


def run_folder_best(run_dir: Path) -> dict:
    """The lowest-loss candidate of a run folder's trace (``run_folder.best_evaluation``): {"loss", "values",
    "result", "generation" (1-based; 0 = the start point), "generations" (run so far), "command" (the run's
    command line, None if its trace has none)}.

    Raises:
        TuningError: no evaluated candidate in the folder.
    """
    best = best_evaluation(run_dir)
    return {"loss": best["loss"], "values": dict(best["values"]), "result": best.get("result", {}),
            "generation": int(best.get("iteration", -1)) + 1, "generations": best["generations"],
            "command": best.get("command")}


def _regenerate(params_path: Path, robot_type: int) -> list[Path]:
    """Rewrite the motion files made from ``params_path`` if it is the type's shipped parameter file."""
    if params_path.resolve() != type_params_file(robot_type).resolve():
        return []
    if robot_type == 0:
        return write_all()
    from motions.authoring.standup_types import write_all as write_type

    return write_type(types=(robot_type,))


@one_line_errors("motion-studio tune standup")
def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="motion-studio tune standup", description=__doc__.splitlines()[0],
                                     formatter_class=argparse.ArgumentDefaultsHelpFormatter)
    parser.add_argument("section", choices=sorted(STANDUPS), help="stand-up to tune")
    parser.add_argument("--generations", type=int, default=40, help="CMA-ES generations")
    parser.add_argument("--sigma", type=float, default=0.1, help="initial CMA-ES step (unit box)")
    parser.add_argument("--popsize", type=int, default=None, help="candidates per generation (default 4 + 3 ln n)")
    parser.add_argument("--starts", type=int, default=4, help="lying starts per candidate")
    parser.add_argument("--noise", action="store_true", help="put seeded parameter noise on every start but the first")
    parser.add_argument("--workers", type=int, default=1, help="local processes (or real servers) for the rollouts")
    parser.add_argument("--seed", type=int, default=0, help="seed of the CMA-ES sampler")
    parser.add_argument("--checkpoint", type=Path, default=None,
                        help="run folder (checkpoint, trace, plots); default out/tuning/standup_<section>[_real|_both]")
    parser.add_argument("--freeze", default="", help="comma-separated ground phases (or 'ready') kept as they are")
    parser.add_argument("--timing-only", action="store_true",
                        help="tune durations and the crouch / rise keyframes only (ground-phase angles kept)")
    parser.add_argument("--starts-seed", type=int, default=1, help="seed of the lying starts")
    parser.add_argument("--target-s", type=float, default=TARGET_S,
                        help="a start standing later than this from the motion's start costs --time-weight per s")
    parser.add_argument("--time-weight", type=float, default=TIME_WEIGHT, help="loss per second past --target-s")
    parser.add_argument("--backend", choices=("mujoco", "real", "both"), default="mujoco",
                        help="where candidates are judged: our simulator in-process (default), the real "
                             "rcssserver3d (one server per worker, each in its own loopback namespace, scripted "
                             "falls as starts), or both (loss: real + --sim-weight x ours from --sim-starts)")
    parser.add_argument("--transfer-starts", action="store_true",
                        help="real backend: the lying starts of motion-studio transfer --seed <--starts-seed> (the "
                             "robot falls from the zero pose by the transfer case's script) instead of the scripted "
                             "falls")
    parser.add_argument("--sim-weight", type=float, default=1.0, help="weight of our simulator's loss (--backend both)")
    parser.add_argument("--sim-starts", type=int, default=4,
                        help="lying starts on our simulator (--backend both: the MuJoCo tuner's own, --starts-seed, "
                             "--noise)")
    parser.add_argument("--params", type=Path, default=None,
                        help="parameter file to start from and to --write into (default the shipped one of the type: "
                             "motions/params/standup.toml, standup_type<N>.toml with --type N, made from standup.toml "
                             "if missing; the motion files are regenerated only for the shipped one)")
    parser.add_argument("--type", type=int, default=0, choices=range(5), metavar="N", dest="robot_type",
                        help="robot type 0-4: the candidates' crouch and rise solved with its kinematics, a robot of "
                             "that type plays them (on every backend); --write goes to its own parameter file and "
                             "motions/files/type<N>/")
    parser.add_argument("--write", action="store_true", help="write the best parameters and regenerate the files")
    parser.add_argument("--write-only", action="store_true",
                        help="run nothing: write the lowest-loss candidate the run folder's trace holds (a run stopped "
                             "early; resuming runs --generations more) and regenerate the files")
    args = parser.parse_args(argv)
    shipped = type_params_file(args.robot_type)
    params_path = args.params or shipped
    base = load_standup_params(params_path if params_path.exists() else PARAMS_PATH)[args.section]
    suffix = ((f"_type{args.robot_type}" if args.robot_type else "")
              + ("" if args.backend == "mujoco" else f"_{args.backend}"))
    checkpoint = args.checkpoint or default_run_dir(f"standup_{args.section}{suffix}")
    starts = default_starts(args.starts, seed=args.starts_seed, noise=args.noise)
    frozen = frozenset(name for name in args.freeze.split(",") if name)
    evaluator = None
    both = f" --sim-weight {args.sim_weight:g} --sim-starts {args.sim_starts}"
    options = (f" --type {args.robot_type}" * (args.robot_type != 0)
               + f" --backend {args.backend}" * (args.backend != "mujoco") + both * (args.backend == "both")
               + f" --starts-seed {args.starts_seed}" * (args.starts_seed != 1) + " --noise" * args.noise
               + " --transfer-starts" * args.transfer_starts
               + " --timing-only" * args.timing_only
               + (f" --target-s {args.target_s:g} --time-weight {args.time_weight:g}" if args.time_weight else ""))
    command = (f"motion-studio tune standup {args.section} --starts {args.starts}{options} --freeze '{args.freeze}' "
               f"--sigma {args.sigma:g} --seed {args.seed} --generations {args.generations}")
    if args.write_only:
        best = run_folder_best(checkpoint)
        args.write = True
    elif args.backend != "mujoco":
        from motion_studio.realserver.standup_backend import make_evaluator

        ours = default_starts(args.sim_starts, seed=args.starts_seed, noise=args.noise) if args.sim_starts else ()
        evaluator = make_evaluator(args.section, args.backend, args.starts, args.starts_seed, args.noise, args.workers,
                                   args.target_s, args.time_weight, args.sim_weight, ours,
                                   args.transfer_starts, args.robot_type)
    if not args.write_only:
        try:
            best = tune(args.section, base, args.generations, starts, args.sigma, args.popsize, args.workers,
                        checkpoint, args.seed, frozen, timing_only=args.timing_only, target_s=args.target_s,
                        time_weight=args.time_weight, evaluator=evaluator, bar=True, robot_type=args.robot_type,
                        command=command)
        finally:
            if evaluator is not None:
                evaluator.close()
    print(json.dumps(best, indent=1))
    if args.write:
        params = with_values(base, best["values"])
        if args.write_only:
            # The run's own options, from its trace: this invocation's are only what --write-only needed.
            run = best.get("command") or "a run whose trace does not record its command"
            provenance = Provenance.now(f"{run} (best of generation {best['generation']} of {best['generations']} "
                                        f"run, written with --write-only)").text("tuned by CMA-ES")
        else:
            provenance = Provenance.now(command).text("tuned by CMA-ES")
        times = best["result"].get("times_s")
        write_best(args.section, params, provenance, f"loss {best['loss']:.3f}, time to stand per start {times} s",
                   params_path, robot_type=args.robot_type)
        for target in _regenerate(params_path, args.robot_type):
            print(f"wrote {target}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
