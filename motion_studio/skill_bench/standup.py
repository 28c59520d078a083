"""Stand-up benchmark on our simulator: success rate and time to stand from the back, from the front, and
after real falls, with the real agent recovering by itself (``SkillBehavior``'s fall watch and
``agent.skills.standup.StandUp``) through the protocol bytes (``motion_studio.scenarios.Scenario``).

Trials (each on a fresh simulator; the robot first stands in the walk stance, motion ``stand``):

* **lying** (back, front and side): the robot first takes a seeded pose near the walk stance (``prepose``: legs
  and arms offset as in a step, a kick or a swing of the arms, left and right apart), is laid on that side
  (``Scenario.lay_down``) at a seeded yaw in [-180, 180) deg and twist about its long axis (a side: on its back
  turned 90 deg to the left or the right, plus that twist), then nudged by a seeded push (torso velocity up to
  ``PUSH_M_S``, angular velocity up to ``SPIN_RAD_S``). The lying body comes to rest whatever the push, so the
  pose is what makes trials differ. A robot on its side rolls onto its back first (``roll_to_back``).
* **pushed**: the robot standing in the walk stance, or walking (``walk_forward``), is knocked over by a
  seeded push in a random direction; the clock starts when it has fallen (REFERENCE §8.1 criterion).

Time to stand = from the lay-down (or the fall) to the first cycle from which the robot stands for
``HOLD_S`` (torso centre above ``STAND_TORSO_Z_M``, up axis z above ``STAND_UP_Z``, a foot on the ground but for
flight cycles of at most ``FEET_OFF_GAP_CYCLES``: a robot knocked over while walking walks on once it is up);
detection by the agent counts, since a robot in a match must notice its fall too. A success is a stand
within ``TARGET_S``; trials run until ``LIMIT_S`` so that slow recoveries (retries) are still measured.

No league challenge scores standing up (REFERENCE §8), so ``score`` is the fraction of lying trials that
stand within 3 s. Targets: issue 6 (success >= 95 % within 3 s).
"""

from __future__ import annotations

import math
import pathlib
import random
from collections.abc import Callable
from dataclasses import asdict, dataclass, field, replace

from agent.motion import MotionController, MotionLibrary, default_library, load_dynamic_params
from agent.skills.base import PlayMotion
from motion_studio.scenarios import Scenario, Truth
from motions.model import JointTarget, Motion
from agent.protocol.constants import CYCLE_S

SIDES = ("back", "front", "side")
#: Lying sides whose stand-up is named after them (a side lie plays roll_to_back, then the back stand-up).
NAMED_SIDES = ("back", "front")
#: A side lie: lying on the back turned this far about the long axis, to the left or the right [deg].
SIDE_TWIST_DEG = 90.0
#: Trials per side (and pushed trials) in a full / quick run.
TRIALS, TRIALS_QUICK = 20, 1
PUSHED_TRIALS, PUSHED_TRIALS_QUICK = 20, 1
#: Largest nudge after the lay-down: torso speed [m/s] and spin [rad/s]; largest twist about the long axis [deg].
PUSH_M_S = 0.3
SPIN_RAD_S = 1.0
TWIST_DEG = 20.0
#: Pose offsets before a fall, per joint group, left and right drawn apart [deg]: (low, high).
PREPOSE_OFFSETS_DEG = {
    "hip_pitch": (-15.0, 15.0), "knee": (-20.0, 15.0), "ankle_pitch": (-10.0, 10.0), "hip_roll": (-5.0, 5.0),
    "shoulder_pitch": (-30.0, 90.0), "shoulder_roll": (-5.0, 30.0),
}
_PREPOSE_JOINTS = {"hip_pitch": ("llj3", "rlj3", 1), "knee": ("llj4", "rlj4", 1), "ankle_pitch": ("llj5", "rlj5", 1),
                   "hip_roll": ("llj2", "rlj2", -1), "shoulder_pitch": ("laj1", "raj1", 1),
                   "shoulder_roll": ("laj2", "raj2", -1)}
#: Push that knocks a standing / walking robot over: horizontal torso speed range [m/s].
KNOCK_M_S = (0.9, 1.5)
#: Standing: torso centre above this [m], up axis z above this, a foot touching, for HOLD_S.
STAND_TORSO_Z_M = 0.28
STAND_UP_Z = 0.85
HOLD_S = 1.0
#: Both feet off the ground for at most this many cycles in a row do not end the hold [cycles]. Why: a robot that
#: walks on once it is up (a push while walking) has flight cycles, as the real walk has one every stride; counted
#: as "not standing", they restarted the hold 0.3-1.3 s after a robot had stood up and walked (measured 2026-11-30,
#: type 0, pushed while walking: up at 2.14 s, clocked at 3.44 s after the walk's flight cycles at 3.10 and 3.42 s).
FEET_OFF_GAP_CYCLES = 3
#: Success = standing within this time [s] (issue 6); a trial is cut at LIMIT_S.
TARGET_S = 3.0
LIMIT_S = 8.0
#: Cycles in the walk stance before a trial starts; cycles of walking before a push.
STANCE_CYCLES = 25
WALK_CYCLES = 60
#: Torso height samples kept per trial for the plot (every TRACE_EVERY cycles).
TRACE_EVERY = 2
TARGETS = {"success_rate": 0.95, "time_s": TARGET_S}
#: The server's self-collision tolerance (REFERENCE §4.5) [m].
SELF_COLLISION_M = 0.04


@dataclass
class Trial:
    """One stand-up trial: its conditions and what the simulator's truth measured."""

    kind: str
    """"back", "front" (laid down) or "pushed_stand" / "pushed_walk" (knocked over)."""
    yaw_deg: float
    push_m_s: tuple[float, float, float]
    spin_rad_s: tuple[float, float, float]
    time_s: float | None = None
    """Time to stand [s], None if it did not stand within LIMIT_S."""
    attempts: int = 0
    """Stand-up motions the agent started."""
    sides: list[str] = field(default_factory=list)
    """Side the agent chose for each attempt."""
    fell: bool = True
    """A pushed robot actually fell (laid-down robots always count as fallen)."""
    torso_z_m: list[float] = field(default_factory=list)
    """Torso height every TRACE_EVERY cycles from the start of the clock [m]."""
    self_collisions: int = 0
    """Cycles (checked every other one) in which the server's self-collision rule would have fired (REFERENCE
    §4.5: it freezes the joints of both boxes for 1 s in a match; our scenarios run without that rule)."""

    @property
    def success(self) -> bool:
        return self.time_s is not None and self.time_s <= TARGET_S


def upright(truth: Truth) -> bool:
    """Torso high and upright (stricter than the §8.1 'not fallen'); `_clock` adds the feet on the ground."""
    return truth.torso_m[2] > STAND_TORSO_Z_M and truth.up_z > STAND_UP_Z


def _clock(scenario: Scenario, trial: Trial) -> Trial:
    """Run up to LIMIT_S from now; set the trial's time to stand and its trace."""
    hold = round(HOLD_S / CYCLE_S)
    limit = round(LIMIT_S / CYCLE_S)
    run_start: int | None = None
    feet_off_run = 0   # cycles in a row with both feet off the ground
    from sim.rules.self_collision import colliding_pairs

    for cycle in range(limit + hold):
        truth = scenario.run(1)[0]
        if cycle % 2 == 0 and colliding_pairs(scenario.robot_type, scenario.engine.robot_body_poses()[0][3],
                                              SELF_COLLISION_M):
            trial.self_collisions += 1
        if cycle % TRACE_EVERY == 0 and cycle <= limit:
            trial.torso_z_m.append(round(truth.torso_m[2], 3))
        feet_off_run = feet_off_run + 1 if truth.feet_off_ground else 0
        if upright(truth) and feet_off_run <= FEET_OFF_GAP_CYCLES:
            run_start = cycle if run_start is None else run_start
            if cycle - run_start + 1 >= hold:
                trial.time_s = round(run_start * CYCLE_S, 2)
                break
        else:
            run_start = None
            if cycle >= limit:
                break
    trial.attempts = scenario.behavior.standup.attempts
    trial.sides = list(scenario.behavior.standup.sides)
    return trial


def prepose(stand: Motion, rng: random.Random, name: str = "prepose") -> Motion:
    """The walk stance (``stand``'s last keyframe) with seeded offsets (PREPOSE_OFFSETS_DEG), as a motion."""
    last = stand.keyframes[-1]
    targets = dict(last.targets)
    for group, (low, high) in PREPOSE_OFFSETS_DEG.items():
        left, right, sign = _PREPOSE_JOINTS[group]
        for wire, mirror in ((left, 1), (right, sign)):
            base = targets[wire].angle_deg or 0.0
            targets[wire] = JointTarget.from_deg(base + mirror * rng.uniform(low, high))
    keyframe = replace(last, name="prepose", targets=targets, set_flag_true=None, source=None)
    return Motion(name, [keyframe], source_format=stand.source_format, first_phase="prepose")


def _stood_scenario(seed: int, rng: random.Random | None = None, library: MotionLibrary | None = None,
                    robot_type: int = 0) -> Scenario:
    """A fresh robot of ``robot_type`` in the walk stance, or in a seeded pose near it when ``rng`` is given,
    playing ``library`` (default: that type's shipped motions, its own stand-ups where it has them)."""
    library = library or default_library(robot_type)
    skill = PlayMotion("stand")
    if rng is not None:
        library.add(prepose(library.get("stand"), rng))
        skill = PlayMotion("prepose")
    scenario = Scenario(skill, robot_type=robot_type, seed=seed,
                        controller=MotionController(library, load_dynamic_params(), robot_type))
    scenario.run(STANCE_CYCLES)
    scenario.set_skill(None)  # after its recovery the robot holds its stance (not the pre-fall pose again)
    return scenario


def lying_trial(side: str, rng: random.Random, seed: int, robot_type: int = 0) -> Trial:
    """Lay the standing robot on ``side`` at a random yaw, nudge it, and clock its recovery."""
    yaw = rng.uniform(-180.0, 180.0)
    twist = rng.uniform(-TWIST_DEG, TWIST_DEG)
    push = random_vector(rng, PUSH_M_S, horizontal=True)
    spin = random_vector(rng, SPIN_RAD_S)
    trial = Trial(side, round(yaw, 1), push, spin)
    scenario = _stood_scenario(seed, rng, robot_type=robot_type)
    if side == "side":
        scenario.lay_down("back", yaw, math.copysign(SIDE_TWIST_DEG, rng.uniform(-1.0, 1.0)) + twist)
    else:
        scenario.lay_down(side, yaw, twist)
    scenario.push(push, spin)
    return _clock(scenario, trial)


def pushed_trial(walking: bool, rng: random.Random, seed: int, robot_type: int = 0) -> Trial:
    """Knock a standing (or walking) robot over with a random push; clock from the fall."""
    scenario = _stood_scenario(seed, robot_type=robot_type)
    if walking:
        scenario.set_skill(PlayMotion("walk_forward", repeat=True))
        scenario.run(WALK_CYCLES)
    direction = rng.uniform(-math.pi, math.pi)
    speed = rng.uniform(*KNOCK_M_S)
    heading = math.radians(scenario.truth().heading_deg)
    push = (round(speed * math.cos(heading + direction), 3), round(speed * math.sin(heading + direction), 3), 0.0)
    trial = Trial("pushed_walk" if walking else "pushed_stand", round(math.degrees(direction), 1), push, (0.0, 0.0, 0.0))
    scenario.push(push)
    fell = scenario.run(round(2.0 / CYCLE_S), stop=lambda truth: truth.fallen)
    trial.fell = bool(fell) and fell[-1].fallen
    if not trial.fell:
        trial.time_s = 0.0
        return trial
    return _clock(scenario, trial)


def random_vector(rng: random.Random, size: float, horizontal: bool = False) -> tuple[float, float, float]:
    """A seeded vector of random direction (horizontal or in 3-D) and length up to ``size``."""
    angle = rng.uniform(-math.pi, math.pi)
    z = 0.0 if horizontal else rng.uniform(-1.0, 1.0)
    r = math.sqrt(max(0.0, 1.0 - z * z))
    scale = size * rng.uniform(0.0, 1.0)
    return (round(scale * r * math.cos(angle), 3), round(scale * r * math.sin(angle), 3), round(scale * z, 3))


def _percentile(values: list[float], q: float) -> float | None:
    if not values:
        return None
    ordered = sorted(values)
    position = q * (len(ordered) - 1)
    low = math.floor(position)
    high = min(low + 1, len(ordered) - 1)
    return round(ordered[low] + (ordered[high] - ordered[low]) * (position - low), 2)


def summarise(trials: list[Trial]) -> dict:
    """Success rate within TARGET_S, time to stand (median, p90, max over the robots that stood), attempts."""
    counted = [t for t in trials if t.fell]
    times = [t.time_s for t in counted if t.time_s is not None]
    return {
        "trials": len(counted),
        "success_rate": round(sum(t.success for t in counted) / len(counted), 3) if counted else None,
        "stood_rate": round(len(times) / len(counted), 3) if counted else None,
        "time_median_s": _percentile(times, 0.5),
        "time_p90_s": _percentile(times, 0.9),
        "time_max_s": max(times) if times else None,
        "attempts_mean": round(sum(t.attempts for t in counted) / len(counted), 2) if counted else None,
        "wrong_side": sum(1 for t in counted if t.kind in NAMED_SIDES and t.sides and t.sides[0] != t.kind),
        "first_attempt_success_rate": round(sum(t.success and t.attempts <= 1 for t in counted) / len(counted), 3)
        if counted else None,
        "trials_with_self_collision": sum(1 for t in counted if t.self_collisions),
    }


def run(quick: bool = False, seed: int = 0, progress: Callable[[int, int], None] | None = None,
        robot_type: int = 0) -> dict:
    """Run the stand-up trials of a robot of ``robot_type`` (0-4) with its shipped motions; returns JSON-ready
    figures with ``robot_type`` (see the module docstring)."""
    n_side = TRIALS_QUICK if quick else TRIALS
    n_pushed = PUSHED_TRIALS_QUICK if quick else PUSHED_TRIALS
    plan: list[tuple[str, int]] = [(side, i) for side in SIDES for i in range(n_side)]
    plan += [("pushed", i) for i in range(n_pushed)]
    trials: list[Trial] = []
    for done, (kind, i) in enumerate(plan):
        rng = random.Random(f"standup/{seed}/{kind}/{i}")
        trial_seed = seed * 1000 + len(trials)
        if kind == "pushed":
            trials.append(pushed_trial(i % 2 == 1, rng, trial_seed, robot_type))
        else:
            trials.append(lying_trial(kind, rng, trial_seed, robot_type))
        if progress is not None:
            progress(done + 1, len(plan))
    per_side = {side: summarise([t for t in trials if t.kind == side]) for side in SIDES}
    lying = [t for t in trials if t.kind in SIDES]
    pushed = [t for t in trials if t.kind.startswith("pushed")]
    overall = summarise(lying)
    result = {
        "robot_type": robot_type,
        "score": overall["success_rate"],
        "lying": overall,
        **per_side,
        "pushed": {**summarise(pushed), "knocked_over": sum(t.fell for t in pushed), "pushes": len(pushed)},
        "targets": TARGETS,
        "passed": {
            **{f"{side}_success_rate": (per_side[side]["success_rate"] or 0.0) >= TARGETS["success_rate"]
               for side in SIDES},
            "pushed_success_rate": (summarise(pushed)["success_rate"] or 0.0) >= TARGETS["success_rate"],
        },
        "settings": {"trials_per_side": n_side, "pushed_trials": n_pushed, "seed": seed, "quick": quick,
                     "limit_s": LIMIT_S, "hold_s": HOLD_S, "push_m_s": PUSH_M_S, "spin_rad_s": SPIN_RAD_S},
        "trials": [_trial_record(t) for t in trials],
    }
    return result


def _trial_record(trial: Trial) -> dict:
    record = asdict(trial)
    record["success"] = trial.success
    return record


def plot(result: dict, out_dir: pathlib.Path) -> list[pathlib.Path]:
    """``standup_type<N>.png`` (N = the result's robot type): time-to-stand histogram per side, and torso height
    over time of a few trials per side."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    out_dir.mkdir(parents=True, exist_ok=True)
    trials = result["trials"]
    kinds = list(SIDES) + ["pushed"]
    fig, (hist, trace) = plt.subplots(1, 2, figsize=(11, 4))
    bins = [i * 0.25 for i in range(int(LIMIT_S / 0.25) + 1)]
    for kind in kinds:
        times = [t["time_s"] for t in trials if t["kind"].startswith(kind) and t["fell"] and t["time_s"] is not None]
        if times:
            hist.hist(times, bins=bins, alpha=0.6, label=f"{kind} ({len(times)})")
    hist.axvline(TARGET_S, color="k", linestyle="--", linewidth=1, label=f"target {TARGET_S:g} s")
    hist.set_xlim(0.0, LIMIT_S)
    hist.set_xlabel("time to stand [s]")
    hist.set_ylabel("trials")
    rates = ", ".join(f"{kind} {result[kind]['success_rate']:.0%}" for kind in kinds
                      if result.get(kind, {}).get("success_rate") is not None)
    hist.set_title(f"Type {result.get('robot_type', 0)}: time to stand (within {TARGET_S:g} s: {rates})")
    hist.legend()
    colours = {"back": "tab:blue", "front": "tab:orange", "side": "tab:purple", "pushed": "tab:green"}
    for kind in kinds:
        shown = [t for t in trials if t["kind"].startswith(kind) and t["torso_z_m"]][:4]
        for index, t in enumerate(shown):
            times = [i * TRACE_EVERY * CYCLE_S for i in range(len(t["torso_z_m"]))]
            trace.plot(times, t["torso_z_m"], color=colours[kind], alpha=0.8,
                       label=kind if index == 0 else None)
    trace.axhline(STAND_TORSO_Z_M, color="k", linestyle=":", linewidth=1)
    trace.set_xlabel("time since lay-down / fall [s]")
    trace.set_ylabel("torso height [m]")
    trace.set_title("Torso height (a few trials)")
    trace.legend()
    fig.tight_layout()
    path = out_dir / f"standup_type{result.get('robot_type', 0)}.png"
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return [path]
