"""Walk robustness trials: the transitions a walk meets in a match, scripted and randomised, on our simulator.

Why: the walk benchmark starts every walk from a calm stance and walks straight, but in matches robots fell
when a walk started right after a turn, when the lean changed soon after the start, when a walk stopped
after a few steps, or started again during its own stop. A trial here is a *script* of requests (walk with
a lean schedule, stop, turn, stand, pause) that the real agent plays through its motion controller
(``motion_studio.scenarios.Scenario``), optionally with small pushes; ground truth says whether and where it
fell. ``random_script`` draws scripts like the ones the skills produce; ``robustness`` runs a batch and
counts falls. The gait tuner (``motion_studio.tune_gait --robust``) adds such trials to its loss.
"""

from __future__ import annotations

import math
import random
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

from agent.motion import MotionController, MotionLibrary, MotionRequest
from agent.motion.dynamic import DynamicParams
from agent.skills.base import Skill
from agent.skills.walk import FORWARD, FORWARD_WALKS
from agent.world_model import WorldModel
from motions.model import Motion
from motion_studio.scenarios import Scenario, Truth
from motion_studio.walk_rollout import BALL_AWAY_M, CYCLE_S, Push, apply_due_pushes, make_controller

#: The walks that steer with the walk lean (their scripts change the lean as steering does).
LEANING = FORWARD_WALKS
TURNS = ("turn_left", "turn_right")
SIDE_WALKS = ("walk_backward", "walk_left", "walk_right")


@dataclass(frozen=True)
class Segment:
    """One request of a script.

    motion: the motion requested (None: none, the current motion leaves through its stop).
    duration_s: how long it is requested; a turn is requested until it has played once instead.
    lean: lean target [-1, 1] during the segment (reached at ``lean_rate_per_s`` from the previous value).
    turn_deg: the turn a turn motion should make (gain from the turn-gain curve).
    """

    motion: str | None
    duration_s: float = 0.0
    lean: float = 0.0
    turn_deg: float | None = None


@dataclass(frozen=True)
class Script:
    """A trial: segments played in order, pushes (times from the script's start), a lean slew rate."""

    segments: tuple[Segment, ...]
    pushes: tuple[Push, ...] = ()
    lean_rate_per_s: float = 2.5
    label: str = ""

    @property
    def duration_s(self) -> float:
        return sum(s.duration_s for s in self.segments)


class ScriptedRequests(Skill):
    """Plays a :class:`Script`'s segments as motion requests (the lean slewed as the walk skills do)."""

    name = "scripted requests"

    def __init__(self, script: Script) -> None:
        super().__init__()
        self.script = script
        self.reset()

    def reset(self) -> None:
        super().reset()
        self.index = 0
        self.cycles = 0
        self.lean = 0.0
        self._turns_before: int | None = None

    @property
    def segment(self) -> Segment | None:
        return self.script.segments[self.index] if self.index < len(self.script.segments) else None

    def step(self, world: WorldModel, motion: MotionController) -> MotionRequest:
        segment = self.segment
        if segment is None:
            self.done = True
            return MotionRequest(None)
        if segment.motion in TURNS:
            if self._turns_before is None:
                self._turns_before = motion.completed[segment.motion]
            if motion.completed[segment.motion] > self._turns_before:
                self._advance()
                return self.step(world, motion)
            return MotionRequest(segment.motion, turn_deg=segment.turn_deg)
        if self.cycles * CYCLE_S >= segment.duration_s:
            self._advance()
            return self.step(world, motion)
        self.cycles += 1
        if segment.motion in LEANING and (motion.phase_name or "").startswith("cycle"):
            rate = self.script.lean_rate_per_s * CYCLE_S
            self.lean += max(-rate, min(rate, segment.lean - self.lean))
        elif motion.motion_name != segment.motion or motion.stopping:
            self.lean = 0.0
        return MotionRequest(segment.motion, lean=self.lean if segment.motion in LEANING else 0.0)

    def _advance(self) -> None:
        self.index += 1
        self.cycles = 0
        self._turns_before = None


@dataclass
class TrialResult:
    """Outcome of one scripted trial."""

    label: str
    fell: bool
    fall_time_s: float | None
    fall_segment: int | None
    """Index of the segment during which the robot fell (the fall = torso up-axis z < 0.6 or low torso)."""
    fall_motion: str | None
    fall_phase: str | None
    """The motion and phase playing when the torso first tilted past ``TILT_UP_Z`` before the fall."""
    distance_m: float
    min_up_z: float
    truths: list[Truth] = field(repr=False, default_factory=list)


#: A torso up-axis z below this marks the start of a fall (for naming the phase that caused it).
TILT_UP_Z = 0.9


def run_script(library: MotionLibrary, script: Script, *, dynamic: DynamicParams | None = None, seed: int = 0,
               position_m: tuple[float, float] = (-5.0, 0.0), heading_deg: float = 0.0, settle_s: float = 1.5,
               robot_type: int = 0) -> TrialResult:
    """Play ``script`` (then request nothing for ``settle_s``) and report whether and where the robot fell."""
    controller = make_controller(library, dynamic)
    skill = ScriptedRequests(script)
    scenario = Scenario(skill, position_m=position_m, heading_deg=heading_deg, controller=controller,
                        recover_falls=False, seed=seed, robot_type=robot_type, ball_m=BALL_AWAY_M)
    pending = sorted(script.pushes, key=lambda p: p.time_s)
    truths: list[Truth] = []
    phases: list[tuple[int, str | None, str | None]] = []
    limit = int(round((script.duration_s + settle_s + 8.0) / CYCLE_S))  # turns have no duration of their own
    settle_cycles = int(round(settle_s / CYCLE_S))
    done_at: int | None = None
    for index in range(limit):
        apply_due_pushes(scenario, pending, index * CYCLE_S)
        truths.append(scenario.run(1)[0])
        phases.append((skill.index, controller.motion_name, controller.phase_name))
        if truths[-1].fallen:
            break
        if skill.done and done_at is None:
            done_at = index
        if done_at is not None and index - done_at >= settle_cycles:
            break
    return trial_result(script.label, truths, phases)


def trial_result(label: str, truths: Sequence[Truth | None], phases: Sequence[tuple[int, str | None, str | None]]
                 ) -> TrialResult:
    """A transition trial's outcome from its truth per cycle and, per cycle, (the script's segment index, the
    motion and the phase playing), as :func:`run_script` reports ours (and ``realserver.rollout_walk`` the real
    server's): the trial ends at the first fallen cycle; a fall is blamed on the segment, motion and phase
    playing when the torso last tilted past ``TILT_UP_Z`` before it.

    Raises:
        ValueError: no truth at all.
    """
    known = [(i, truth) for i, truth in enumerate(truths) if truth is not None]
    if not known:
        raise ValueError("no truth in the trial")
    fall = next((k for k, (_, truth) in enumerate(known) if truth.fallen), None)
    kept = known if fall is None else known[:fall + 1]
    tilt = None
    for index, truth in kept:
        if truth.up_z >= TILT_UP_Z:
            tilt = None
        elif tilt is None:
            tilt = index
    fell = fall is not None
    blamed = phases[min(tilt, len(phases) - 1)] if fell and tilt is not None and phases else (None, None, None)
    first, last = kept[0][1], kept[-1][1]
    return TrialResult(label, fell, last.time_s if fell else None, *blamed,
                       math.dist(first.torso_m[:2], last.torso_m[:2]), min(t.up_z for _, t in kept),
                       [t for _, t in kept])


def _walk_segment(rng: random.Random, low_s: float, high_s: float, lean_change: bool,
                  motion: str = FORWARD) -> list[Segment]:
    """A forward walk of random length, its lean changing at random times (as steering does)."""
    total = rng.uniform(low_s, high_s)
    out = []
    while total > 0.0:
        part = min(total, rng.uniform(0.6, 2.5)) if lean_change else total
        lean = rng.choice((-1.0, -0.5, 0.0, 0.5, 1.0)) if lean_change else 0.0
        out.append(Segment(motion, part, lean))
        total -= part
    return out


def random_script(rng: random.Random, library: MotionLibrary, *, lean_change: bool = True, pushes: bool = True,
                  max_push_m_s: float = 0.12, lean_rate_per_s: float = 2.5) -> Script:
    """A match-like script: a start (from the stance, after a turn, after a stop), forward walks with lean
    changes, stops of random length, restarts during a stop, side walks, more turns; small pushes."""
    segments: list[Segment] = []
    kinds = []
    start = rng.choice(("stand", "turn", "turn_stand", "upright"))
    kinds.append(start)
    if start in ("stand", "turn_stand") and "stand" in library:
        segments.append(Segment("stand", 0.5))
    if start.startswith("turn") and all(t in library for t in TURNS):
        turn = rng.choice(TURNS)
        segments.insert(0, Segment(turn, 0.0, turn_deg=rng.uniform(3.0, 40.0)))
    for _ in range(rng.randint(2, 3)):
        segments += _walk_segment(rng, 0.4, 4.0, lean_change)
        after = rng.choice(("pause", "restart", "turn", "side"))
        kinds.append(after)
        if after == "pause":
            segments.append(Segment(None, rng.uniform(0.8, 2.0)))
        elif after == "restart":
            segments.append(Segment(None, rng.uniform(0.04, 0.8)))  # a new request during the walk's stop
        elif after == "turn" and all(t in library for t in TURNS):
            segments.append(Segment(rng.choice(TURNS), 0.0, turn_deg=rng.uniform(3.0, 40.0)))
        else:
            side = rng.choice([w for w in SIDE_WALKS if w in library] or [FORWARD])
            segments.append(Segment(side, rng.uniform(0.3, 1.5)))
    walk_s = sum(s.duration_s for s in segments)
    shoves: tuple[Push, ...] = ()
    if pushes:
        count = rng.randint(0, 2)
        shoves = tuple(sorted((Push(rng.uniform(0.5, max(0.6, walk_s)),
                                    *_polar(rng.uniform(0.03, max_push_m_s), rng.uniform(-math.pi, math.pi)))
                               for _ in range(count)), key=lambda p: p.time_s))
    return Script(tuple(segments), shoves, lean_rate_per_s, "+".join(kinds))


#: Start conditions of :func:`transition_script`: from ``stand``'s stance, right after a walk's stop (a
#: restart during the stop or after it), after a turn (with or without ``stand`` after it), from the upright
#: beam pose (the walk plays its own stance phase).
STARTS = ("stand", "restart", "turn", "turn_stand", "upright")


def transition_script(rng: random.Random, library: MotionLibrary, motion: str = FORWARD, *,
                      starts: Sequence[str] = STARTS, max_push_m_s: float = 0.04) -> Script:
    """A script for one walk ``motion``: a start condition from ``starts``, a random pause, the walk for
    1-3 s (the forward walk with lean changes), its stop, and half the time a restart during the stop and
    another short walk; a tiny push while standing (the state a real start meets is never exactly calm)."""
    start = rng.choice(list(starts))
    turns_ok = all(t in library for t in TURNS)
    if start.startswith("turn") and not turns_ok:
        start = "stand"
    segments: list[Segment] = []
    if start != "upright" and "stand" in library:
        segments.append(Segment("stand", 0.5))
    if start == "restart":
        segments += [Segment(motion, rng.uniform(0.5, 2.0)), Segment(None, rng.uniform(0.04, 1.0))]
    elif start.startswith("turn"):
        segments.append(Segment(rng.choice(TURNS), 0.0, turn_deg=rng.uniform(3.0, 40.0)))
        if start == "turn_stand" and "stand" in library:
            segments.append(Segment("stand", 0.5))
    pause = rng.uniform(0.0, 1.0)
    segments.append(Segment(None, pause))
    push_time_s = sum(s.duration_s for s in segments) - pause / 2.0
    lean_change = motion in LEANING
    segments += (_walk_segment(rng, 1.0, 3.0, lean_change, motion) if lean_change
                 else [Segment(motion, rng.uniform(1.0, 3.0))])
    if rng.random() < 0.5:
        segments.append(Segment(None, rng.uniform(0.04, 0.6)))
        segments.append(Segment(motion, rng.uniform(0.6, 1.5)))
    push = Push(max(0.0, push_time_s), *_polar(rng.uniform(0.0, max_push_m_s), rng.uniform(-math.pi, math.pi)))
    return Script(tuple(segments), (push,), label=f"{motion}:{start}")


def perturbed(motion: Motion, rng: random.Random, sigma_deg: float,
              prefixes: tuple[str, ...] = ("start_", "cycle_", "stop_")) -> Motion:
    """A copy of an XML walk whose leg targets in the phases named with ``prefixes`` carry Gaussian noise of
    ``sigma_deg`` (robustness to small changes of the authored angles, which felled earlier gaits)."""
    from dataclasses import replace as dc_replace

    from motions.model import JointTarget

    phases = []
    for phase in motion.keyframes:
        if phase.name.startswith(prefixes):
            targets = {wire: (JointTarget(t.angle_rad + math.radians(rng.gauss(0.0, sigma_deg)), t.computed)
                              if t.angle_rad is not None and wire[1:3] == "lj" else t)
                       for wire, t in phase.targets.items()}
            phase = dc_replace(phase, targets=targets)
        phases.append(phase)
    return dc_replace(motion, keyframes=phases)


def _polar(radius: float, angle: float) -> tuple[float, float]:
    return radius * math.cos(angle), radius * math.sin(angle)


@dataclass
class Robustness:
    """Falls over a batch of scripted trials."""

    trials: int
    falls: int
    results: list[TrialResult]

    @property
    def fall_rate(self) -> float:
        return self.falls / max(1, self.trials)

    def by_phase(self) -> dict[str, int]:
        """Falls by the motion and phase kind (``start``, ``cycle``, ``stop``...) that began them."""
        out: dict[str, int] = {}
        for r in self.results:
            if r.fell:
                phase = (r.fall_phase or "-").rstrip("0123456789_")
                key = f"{r.fall_motion}/{phase}"
                out[key] = out.get(key, 0) + 1
        return dict(sorted(out.items(), key=lambda kv: -kv[1]))


def robustness(library: MotionLibrary, trials: int, seed: int = 0, *, dynamic: DynamicParams | None = None,
               scripts: Sequence[Script] | None = None, robot_type: int = 0,
               progress: Callable[[int, int], None] | None = None, **script_options: object) -> Robustness:
    """Run ``trials`` random scripts (or the given ones); seeds derive from ``seed``."""
    rng = random.Random(seed)
    chosen = list(scripts) if scripts is not None else [random_script(rng, library, **script_options)  # type: ignore[arg-type]
                                                         for _ in range(trials)]
    results = []
    for index, script in enumerate(chosen):
        results.append(run_script(library, script, dynamic=dynamic, seed=seed * 1000 + index, robot_type=robot_type))
        if progress is not None:
            progress(index + 1, len(chosen))
    return Robustness(len(chosen), sum(r.fell for r in results), results)


def _real_robustness(library: MotionLibrary, trials: int, seed: int, scripts: list[Script] | None, pushes: bool,
                     lean_change: bool, workdir: str, argv: list[str] | None) -> Robustness:
    """The scripts :func:`robustness` would play (the same draws), played on the real server instead: the process
    re-runs itself inside the real-server scripts' private namespace, one server for every trial."""
    import sys
    from pathlib import Path

    from motion_studio.realserver.rollout_kick import ensure_private_network
    from motion_studio.realserver.rollout_walk import RealWalkBench

    ensure_private_network("motion_studio.walk_trials", list(argv) if argv is not None else sys.argv[1:])
    rng = random.Random(seed)
    chosen = scripts if scripts is not None else [random_script(rng, library, pushes=pushes, lean_change=lean_change)
                                                  for _ in range(trials)]
    with RealWalkBench(Path(workdir)) as bench:
        results = [bench.script(library, script) for script in chosen]
    return Robustness(len(chosen), sum(r.fell for r in results), results)


def main(argv: list[str] | None = None) -> int:
    """``python -m motion_studio.walk_trials [--trials N] [--seed S]``: falls of the shipped walks in random
    match-like scripts."""
    import argparse

    from agent.motion import default_library

    parser = argparse.ArgumentParser(prog="python -m motion_studio.walk_trials", description=main.__doc__)
    parser.add_argument("--trials", type=int, default=20)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--robot-type", type=int, default=0)
    parser.add_argument("--no-pushes", action="store_true")
    parser.add_argument("--no-lean", action="store_true")
    parser.add_argument("--motion", default=None, help="transition trials of this walk (default: match-like mixes)")
    parser.add_argument("--folder", default=None, help="motion folder (default: the shipped motions)")
    parser.add_argument("--verbose", action="store_true")
    parser.add_argument("--real", action="store_true",
                        help="play the same scripts on the real rcssserver3d 0.7.3 (type 0, pushes left out; "
                             "motion_studio.realserver.rollout_walk)")
    parser.add_argument("--real-workdir", default="out/walk_trials_real", help="the real server's logs (--real)")
    args = parser.parse_args(argv)
    library = default_library(args.robot_type, args.folder)
    scripts = None
    if args.motion:
        rng = random.Random(args.seed)
        scripts = [transition_script(rng, library, args.motion) for _ in range(args.trials)]
    if args.real:
        result = _real_robustness(library, args.trials, args.seed, scripts, not args.no_pushes, not args.no_lean,
                                  args.real_workdir, argv)
    else:
        result = robustness(library, args.trials, args.seed, robot_type=args.robot_type, scripts=scripts,
                            pushes=not args.no_pushes, lean_change=not args.no_lean)
    for r in result.results:
        if args.verbose or r.fell:
            print(f"{'FELL' if r.fell else 'ok  '} {r.label:<40} seg {r.fall_segment} {r.fall_motion}/{r.fall_phase} "
                  f"t={r.fall_time_s} min_up={r.min_up_z:.2f} d={r.distance_m:.2f}")
    print(f"falls {result.falls}/{result.trials} ({result.fall_rate:.0%}) by phase {result.by_phase()}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
