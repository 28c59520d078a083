"""Sim-to-real transfer of the shipped skills: every skill case on the real rcssserver3d 0.7.3 and on our
simulator side by side (same spot, same trainer commands), or, without the real server, the recorded real runs
(fixtures) with their commands replayed open loop on ours; the figures of both as rows with ours/real ratios.

Figures: walk speed over the 10 s of walking (forward, backward, sideways) [m/s]; turn per turn motion [deg]
and TurnBy(90)'s total turn [deg]; kick distance with the ball on the motion's spot [m]; stand-up outcome and
time to stand, from the back and the front, over N lying starts (start 0 is the case as shipped, the others vary
the fall script's speed and stop and the settle time, seeded); falls on a 20 m forward walk; the torso height
standing. Stood up = the torso centre above 0.30 m for 1 s (measures.stood_index); the time to stand runs from
the end of the fall script (the agent takes over) to the start of that second. Every case is played by one robot
type (``plan``'s ``robot_type``) with its own motions; a type's recorded runs are named ``<case>_type<N>``.
"""

from __future__ import annotations

import math
import random
import statistics
import subprocess
from collections.abc import Callable, Iterator
from dataclasses import dataclass, field, replace
from pathlib import Path

from agent.skills.base import PlayMotion
from motion_studio.realserver.cases import (CASES, CYCLE_S, FALL_SCRIPT_CYCLES, KICK_LINEUP_CM, SETTLE_CYCLES, Case,
                                            MotionSource, SkillSequence, motion_source, with_dribble_config)
from motion_studio.realserver.errors import FixtureError, RealServerError
from motion_studio.realserver.fixtures import Fixture, fixture_path, read_fixture, write_fixture
from motion_studio.realserver.measures import (ball_travel_m, count_falls, displacement_m, first_fall, known,
                                               stood_index, turned_deg, wrap_deg)
from motion_studio.realserver.skill_figures import dribble_figures, orbit_figures
from motion_studio.realserver.skill_runs import Run

TOOL = "motion-studio transfer"
#: The 20 m walk: walk_forward requested this long [s] (real 0.52 m/s over 10 s: 20 m in ~39 s), then stop.
WALK_20M_S, WALK_20M_STOP_S = 44.0, 2.0
WALK_20M_DISTANCE_M = 20.0


def _walk_20m(name: str, motion: str) -> Case:
    return Case(name, lambda: SkillSequence((PlayMotion(motion, repeat=True), round(WALK_20M_S / CYCLE_S)),
                                            (None, None)),
                round((WALK_20M_S + WALK_20M_STOP_S) / CYCLE_S), position_m=(-13.0, 0.0), ball_m=(-14.0, -9.0),
                recover_falls=True, walk_cycles=round(WALK_20M_S / CYCLE_S), motion=motion)


WALK_20M = _walk_20m("walk_20m", "walk_forward")
"""Starts 7 m from the far goal line so that a walk faster than the real one (26 m) ends before the goal."""
#: The same 20 m with the fast walk (it leaves the field at the far goal line after 28 m: the 20 m come first).
WALK_FAST_20M = _walk_20m("walk_fast_20m", "walk_fast")
WALK_20M_CASES = (WALK_20M, WALK_FAST_20M)
#: Walk cases and the direction they walk in (robot frame unit vector).
WALK_DIRECTIONS = {"walk_forward": (1.0, 0.0), "walk_fast": (1.0, 0.0), "walk_backward": (-1.0, 0.0),
                   "walk_left": (0.0, 1.0), "walk_right": (0.0, -1.0)}
STANDUP_CASES = ("standup_back", "standup_front", "standup_side")
#: Cases without a kick motion of their own whose figure is how far the ball moved: KickToward's line-up and kick
#: from behind the ball, and WalkToBall's line-up beside it (which must leave it where it lies).
BALL_CASES = (*(f"kick_lineup_{d}cm" for d in KICK_LINEUP_CM), "walk_to_ball_beside")
#: The side each stand-up case's robot really lies on, measured on both servers 2.7 s into the skill phase:
#: standup_back's fall script tips it forward (torso forward axis z -0.5, up axis z -0.85, centre at 0.19 m) and
#: the agent plays standup_front; standup_front's tips it onto its back (forward axis z 0.97) and standup_back
#: plays. The case names are kept: the recorded fixtures carry them. standup_side's tips it onto its right side.
LIES_ON = {"standup_back": "front", "standup_front": "back", "standup_side": "side"}
#: Lying start variations (uniform, seeded): factor on the fall script's joint velocities, cycles added to its
#: stop step, cycles added to the settle time before it.
FALL_SPEED_SCALE = (0.85, 1.15)
FALL_STOP_SHIFT_CYCLES = (-5, 5)
SETTLE_EXTRA_CYCLES = (0, 15)


# ---- what runs ----------------------------------------------------------------------------------------
def vary_fall(case: Case, start: int, seed: int) -> Case:
    """Lying start ``start`` of a stand-up case: start 0 is the case itself; the others scale the fall
    script's velocities, shift its stop and lengthen the settle time by seeded amounts."""
    if start == 0:
        return case
    rng = random.Random(f"transfer/{seed}/{case.name}/{start}")
    return replace(case, start=start, fall_speed_scale=round(rng.uniform(*FALL_SPEED_SCALE), 3),
                   fall_stop_shift_cycles=rng.randint(*FALL_STOP_SHIFT_CYCLES),
                   settle_cycles=SETTLE_CYCLES + rng.randint(*SETTLE_EXTRA_CYCLES))


def run_name(case: Case) -> str:
    """The run's name in the figures and the table (one transfer run plays one robot type): the case, with
    ``_start<k>`` for a varied lying start."""
    return f"{case.name}_start{case.start}" if case.start else case.name


def fixture_name(case: Case) -> str:
    """The name of the case's recorded real run: ``run_name`` with ``_type<N>`` after the case's name for robot
    types other than 0 (as ``motion-studio real skills --type N --fixture`` names its recordings)."""
    typed = f"{case.name}_type{case.robot_type}" if case.robot_type else case.name
    return f"{typed}_start{case.start}" if case.start else typed


def _every_case() -> list[Case]:
    """Every shipped case (``cases.CASES``) and the 20 m walks, in the order the report lists them."""
    return [*CASES.values(), *WALK_20M_CASES]


def plan(starts: int, seed: int, names: list[str] | None = None, robot_type: int = 0) -> list[Case]:
    """Every shipped case (stand-ups once per lying start) and the 20 m walk, played by a robot of
    ``robot_type`` with its own motions; ``names`` picks cases. The lying starts vary alike for every type."""
    cases = _every_case()
    if names:
        cases = [case for case in cases if case.name in names]
    cases = [replace(case, robot_type=robot_type) for case in cases]
    out: list[Case] = []
    for case in cases:
        out += [vary_fall(case, k, seed) for k in range(starts)] if case.name in STANDUP_CASES else [case]
    return out


def known_cases() -> list[str]:
    return [case.name for case in _every_case()]


@dataclass
class Pair:
    """One case run on both servers (or the real run recorded and ours replaying it)."""

    case: Case
    real: Run
    ours: Run
    notes: list[str] = field(default_factory=list)


# ---- live: both servers ----------------------------------------------------------------------------------
def run_live(cases: list[Case], motions: MotionSource, scripts: Path, workdir: Path, record: Path | None = None,
             progress: Callable[[int, int, str], None] | None = None,
             errors: list[str] | None = None) -> Iterator[Pair]:
    """Each case on the real server (this process inside netns.sh's namespace) and on ours; with ``record``
    the real runs are written there as fixtures. A real run that fails (the server stalls or drops the
    connection) is skipped, its error appended to ``errors``."""
    from motion_studio.realserver.skill_runs import run_real, run_sim

    errors = errors if errors is not None else []
    workdir.mkdir(parents=True, exist_ok=True)
    for done, case in enumerate(cases):
        if progress is not None:
            progress(done, len(cases), run_name(case))
        try:
            real, lines = run_real(case, motions, scripts, workdir, tool=TOOL)
        except (RealServerError, OSError) as error:
            errors.append(f"{run_name(case)}: real run failed ({error}); server log {workdir}")
            continue
        if record is not None:
            write_fixture(lines, fixture_path(record, fixture_name(case)))
        yield Pair(case, real, run_sim(case, motions))


# ---- replay: recorded real runs, ours open loop --------------------------------------------------------------
def case_of(fixture: Fixture) -> Case:
    """The case a fixture recorded, with its settle time and lying start number from the meta line (the
    replay sends the recorded commands, so the fall script itself is in the fixture).

    Raises:
        FixtureError: the meta line names no known case.
    """
    meta = fixture.meta
    base = {case.name: case for case in _every_case()}.get(str(meta["case"]))
    if base is None:
        raise FixtureError(fixture.path, 1, f"unknown case {meta['case']!r} in the meta line")
    base = with_dribble_config(base, meta.get("dribble_config", {}))   # a dribble recorded with --dribble settings
    return replace(base, settle_cycles=fixture.skill_cycle - int(meta["move_cycle"]), start=int(meta.get("start", 0)),
                   robot_type=int(meta.get("robot_type", 0)))


def replay_fixtures(cases: list[Case], folder: Path, scratch: Path,
                    progress: Callable[[int, int, str], None] | None = None,
                    errors: list[str] | None = None) -> Iterator[Pair]:
    """The recorded real run of each case (``folder/real_0.7.3_skill_<run>.jsonl.gz``) and ours replaying its
    commands open loop. A missing or unreadable fixture is skipped, its error (file and line) appended to
    ``errors``. Turn motions: our agent on the fixture's motions revision is fed the recorded messages again to
    learn when each motion ended (replay.agent_completions)."""
    from motion_studio.realserver.replay import agent_completions, replay

    errors = errors if errors is not None else []
    sources: dict[str, MotionSource | None] = {}
    for done, planned in enumerate(cases):
        name = fixture_name(planned)
        if progress is not None:
            progress(done, len(cases), name)
        try:
            fixture = read_fixture(fixture_path(folder, name))
            case = case_of(fixture)
        except FixtureError as error:
            errors.append(str(error))
            continue
        real, ours = replay(fixture)
        pair = Pair(case, real, ours, [f"replay of {fixture.path.name} (motions {fixture.meta.get('motions')})"])
        if case.name.startswith("turn_"):
            revision = str(fixture.meta.get("motions", "worktree"))
            if revision not in sources:
                try:
                    sources[revision] = motion_source(revision, scratch / revision)
                except subprocess.CalledProcessError:
                    sources[revision] = None
            source = sources[revision]
            if source is None:
                pair.notes.append(f"motions revision {revision!r} unknown: turn motions not counted")
            else:
                completions, agreement = agent_completions(fixture, case, source)
                real.completions = ours.completions = completions
                if agreement < 1.0:
                    pair.notes.append(f"our agent gave {agreement:.0%} of the recorded answers again")
        yield pair


def missing_starts(starts: int, folder: Path, seed: int, robot_type: int = 0) -> dict[str, list[int]]:
    """Lying starts of each stand-up case (played by ``robot_type``, as ``plan`` varies them) with no fixture in
    ``folder`` (reported once, not as errors)."""
    missing: dict[str, list[int]] = {name: [] for name in STANDUP_CASES}
    for case in plan(starts, seed, list(STANDUP_CASES), robot_type):
        if case.start and not fixture_path(folder, fixture_name(case)).exists():
            missing[case.name].append(case.start)
    return missing


# ---- figures ---------------------------------------------------------------------------------------------
@dataclass
class StandUpOutcome:
    """One lying start: ``outcome`` "stood", "lying" (never stood) or "no fall"; seconds from the end of the
    fall script to the start of the standing second."""

    outcome: str
    time_s: float = math.nan


def standup_outcome(run: Run) -> StandUpOutcome:
    """Did the robot stand up after the scripted fall (torso centre above 0.30 m for 1 s), and when."""
    fall = first_fall(run.truths)
    if fall is None:
        return StandUpOutcome("no fall")
    stood = stood_index(run.truths, max(fall + 1, FALL_SCRIPT_CYCLES))
    if stood is None:
        return StandUpOutcome("lying")
    return StandUpOutcome("stood", (stood - FALL_SCRIPT_CYCLES) * CYCLE_S)


def walk_speed_m_s(run: Run, case: Case) -> float:
    """Speed along the walk's direction over its requested cycles [m/s] (NaN: truth missing)."""
    first, last = known(run.truths, 0, backwards=False), known(run.truths, case.walk_cycles - 1)
    if first is None or last is None:
        return math.nan
    forward, left = displacement_m(first, last)
    along_x, along_y = WALK_DIRECTIONS[case.name]
    return (forward * along_x + left * along_y) / (case.walk_cycles * CYCLE_S)


def turn_per_motion_deg(run: Run) -> float:
    """Mean heading change per completed turn motion [deg] (NaN: no completion known)."""
    ends = [i for i, name in run.completions if name.startswith("turn_")]
    if not ends:
        return math.nan
    return turned_deg(run.truths, 0, ends[-1]) / len(ends)


def walk_20m(run: Run) -> tuple[float, int]:
    """(seconds until the torso is 20 m from its start, NaN if never; falls (count_falls) before then, or in
    the whole run)."""
    first = known(run.truths, 0, backwards=False)
    reached = next((i for i, t in enumerate(run.truths) if first is not None and t is not None
                    and math.dist(t.torso_m[:2], first.torso_m[:2]) >= WALK_20M_DISTANCE_M), None)
    falls = count_falls(run.truths, None if reached is None else reached + 1)
    return (math.nan if reached is None else reached * CYCLE_S), len(falls)


def walk_heading_change_deg(run: Run, case: Case) -> float:
    """Heading at the last walking cycle (the last known truth up to it) minus the first known heading [deg]."""
    first = known(run.truths, 0, backwards=False)
    return wrap_deg(known(run.truths, case.walk_cycles - 1).heading_deg - first.heading_deg)


def run_figures(pair: Pair) -> dict[str, dict[str, float | str]]:
    """The figures of one pair: {"real": {...}, "ours": {...}} (JSON-ready)."""
    out: dict[str, dict[str, float | str]] = {}
    for side, run in (("real", pair.real), ("ours", pair.ours)):
        case, figures = pair.case, {}
        truths = [t for t in run.truths if t is not None]
        if not truths:
            out[side] = {"truth cycles": 0}
            continue
        fall = first_fall(run.truths)
        figures["first fall [s]"] = math.nan if fall is None else fall * CYCLE_S
        if case.name in WALK_DIRECTIONS:
            figures["speed [m/s]"] = walk_speed_m_s(run, case)
        elif case.name in ("turn_left", "turn_right"):
            figures["turn per motion [deg]"] = turn_per_motion_deg(run)
            figures["turn motions"] = len([n for _, n in run.completions if n.startswith("turn_")])
        elif case.name == "turn_by_90":
            figures["turned [deg]"] = turned_deg(run.truths)
        elif case.kick:
            figures["ball travel [m]"] = ball_travel_m(truths[0], truths[-1])
            direction = math.degrees(math.atan2(truths[-1].ball_m[1] - truths[0].ball_m[1],
                                                truths[-1].ball_m[0] - truths[0].ball_m[0]))
            figures["ball direction [deg]"] = wrap_deg(direction - truths[0].heading_deg)
        elif case.fall:
            outcome = standup_outcome(run)
            figures["outcome"], figures["time to stand [s]"] = outcome.outcome, outcome.time_s
            figures["torso z max after the fall script [m]"] = max(
                (t.torso_m[2] for t in run.truths[FALL_SCRIPT_CYCLES:] if t is not None), default=math.nan)
        elif case.name in (c.name for c in WALK_20M_CASES):
            figures["20 m after [s]"], figures["falls"] = walk_20m(run)
            figures["heading change [deg]"] = walk_heading_change_deg(run, case)
        elif case.name == "stand":
            figures["torso z mean [m]"] = statistics.fmean(t.torso_m[2] for t in truths)
        elif case.dribble is not None:
            figures.update(dribble_figures(run, case))
        elif case.name.startswith("orbit_"):
            figures["heading change [deg]"] = walk_heading_change_deg(run, case)
            figures.update(orbit_figures(run, case))
        elif case.ball_m is not None and case.name in BALL_CASES:
            figures["ball moved [m]"] = ball_travel_m(truths[0], truths[-1])
        out[side] = figures
    return out


# ---- one transfer run --------------------------------------------------------------------------------------
@dataclass
class Transfer:
    """What a transfer run measured: ``mode`` "live" (both servers) or "replay" (fixtures)."""

    mode: str
    pairs: list[Pair]
    figures: dict[str, dict]
    """run name -> {"real": {...}, "ours": {...}} (run_figures)."""
    errors: list[str]
    """Fixtures that could not be used (file:line: what), real runs that failed."""
    notes: list[str]
    motions: str = "recorded"
    """The motions revision played live ("recorded": each fixture's own)."""


def measure(mode: str, cases: list[Case], *, motions_revision: str, fixtures: Path, scratch: Path,
            scripts: Path | None = None, workdir: Path | None = None, record: Path | None = None,
            seed: int = 0, starts: int = 1,
            progress: Callable[[int, int, str], None] | None = None) -> Transfer:
    """Run (live) or replay (replay) ``cases``; their figures.

    Args:
        mode: "live" needs ``scripts`` (the real-server scripts), ``workdir`` (server and monitor logs) and this
            process inside netns.sh's namespace; "replay" reads ``fixtures``.
        motions_revision: git revision of the motions played live ('worktree': the files as they are now).
        scratch: a folder for exported motions.
        record: live only: write the real runs there as fixtures.
        seed, starts: the lying starts' seed and number (replay notes the starts it has no fixture for).
    """
    errors: list[str] = []
    notes: list[str] = []
    played = "recorded"
    if mode == "live":
        motions = motion_source(motions_revision, scratch / "motions")
        played = motions.revision
        cases, skipped = playable(cases, motions)
        notes += skipped
        pairs = list(run_live(cases, motions, scripts, workdir, record, progress, errors))
    else:
        # a varied lying start is replayed only where it was recorded (the missing ones are one note below)
        cases = [case for case in cases if not case.start or fixture_path(fixtures, fixture_name(case)).exists()]
        pairs = list(replay_fixtures(cases, fixtures, scratch, progress, errors))
        robot_type = cases[0].robot_type if cases else 0
        for name, missing in missing_starts(starts, fixtures, seed, robot_type).items():
            if missing and any(case.name == name for case in cases):
                pattern = fixture_name(replace(CASES[name], robot_type=robot_type)) + "_start<k>"
                notes.append(f"{name}: no fixture for lying starts {_ranges(missing)} "
                             f"({fixture_path(fixtures, pattern)}; record them with --record)")
    figures = {run_name(pair.case): run_figures(pair) for pair in pairs}
    return Transfer(mode, pairs, figures, errors, notes, played)


def playable(cases: list[Case], motions: MotionSource) -> tuple[list[Case], list[str]]:
    """The cases whose motion their robot type plays (``motions/files/robot_types.toml`` withholds some), and a
    note per case left out (``MotionSource.unplayed``)."""
    kept, notes = [], {}
    libraries = {}
    for case in cases:
        available = libraries.setdefault(case.robot_type, motions.library(case.robot_type))
        reason = motions.unplayed(case, available)
        if reason is None:
            kept.append(case)
        else:
            notes.setdefault(case.name, f"{case.name}: not run ({reason})")
    return kept, list(notes.values())


def _ranges(numbers: list[int]) -> str:
    """[1, 2, 3, 5] -> "1-3, 5"."""
    parts, start = [], None
    for index, number in enumerate(numbers):
        if start is None:
            start = number
        if index + 1 == len(numbers) or numbers[index + 1] != number + 1:
            parts.append(str(start) if start == number else f"{start}-{number}")
            start = None
    return ", ".join(parts)
