"""Where an open-loop replay leaves the real recording: the first cycle each joint, each foot's ground contact and
the torso part ways.

Why: `agreement` says how far a replay ended from the real run, not where it started to differ. An open-loop
replay of a closed-loop skill replays the real agent's corrections of the real robot's errors, so one joint that
follows its command differently (a motor that saturates under load on one server only) drifts a little at every
step and the rest follows. The first joint past a small threshold, and how fast its error grows, point at the
physics to look at; a foot that touches the ground on one server only (its FRP) says where the contact differs,
often before any joint does; the torso's pose says when the drift became a different motion.

Angles are the HJ perceptors' [deg] (SimSpark signs); cycles are sense-message indices of the trace.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace
from functools import lru_cache
from pathlib import Path

from agent.protocol.constants import CYCLE_S
from agent.protocol.effectors import JointVelocity, parse_actions
from agent.protocol.errors import ProtocolError
from kinematics.spec import robot_spec
from motion_studio.calibration.agreement import Replay
from motion_studio.realserver.measures import fallen, wrap_deg
from motion_studio.scenarios import Truth

#: A joint has left the real one when its angle differs by more than this [deg] (the real HJ's resolution is
#: 0.01 deg; a joint that follows the same command on both servers stays within 0.3 deg, see sim.physics_params).
JOINT_THRESHOLD_DEG = 1.0
#: The torso has left the real one when its centre is this far off [m], ...
POSITION_THRESHOLD_M = 0.05
#: ... its height this far [m], ...
HEIGHT_THRESHOLD_M = 0.01
#: ... its up axis z this far, ...
UP_Z_THRESHOLD = 0.05
#: ... or its heading this far [deg].
HEADING_THRESHOLD_DEG = 5.0
#: The robots have parted when one is fallen and the other not for this many cycles in a row (0.5 s).
PARTED_HOLD_CYCLES = 25
#: A foot touches the ground in a cycle when its FRP reports more than this normal force [N] (a lifting real foot
#: still inside ODE's surface layer reads about 0 N).
TOUCH_FORCE_N = 1.0
#: A commanded joint is held still in a cycle when its HJ reading moves less than this [deg] ...
STILL_DEG = 0.01
#: ... although the velocity it was sent is at least this [rad/s] (0.3 rad/s moves a free joint 0.34 deg a cycle) ...
STILL_COMMAND_RAD_S = 0.3
#: ... and a cycle is frozen when this many joints are held so: SimSpark's self-collision foul freezes the joints of
#: both colliding limbs (4-6 each) for a second; one joint resting against its stop is not a freeze.
FROZEN_MIN_JOINTS = 3


@dataclass(frozen=True)
class JointDivergence:
    """One joint over the compared cycles: ours minus real [deg]."""

    joint: str
    first_cycle: int | None
    """First cycle whose error is above the threshold; None if it never is."""
    error_deg: dict[int, float]
    """Ours - real per compared cycle."""

    @property
    def max_abs_deg(self) -> float:
        return max((abs(e) for e in self.error_deg.values()), default=0.0)


@dataclass(frozen=True)
class PoseDivergence:
    """The torso: the first cycle each pose figure is past its threshold (None: never), and the falls."""

    position_cycle: int | None
    height_cycle: int | None
    up_cycle: int | None
    heading_cycle: int | None
    real_fall_cycle: int | None
    ours_fall_cycle: int | None
    parted_cycle: int | None
    """First cycle of the first half second in which one robot is fallen and the other not (None: never)."""


@dataclass(frozen=True)
class ContactDivergence:
    """One foot-pressure sensor (``lf``, ``rf``; type 4's toes too): the cycles on which one robot's foot touches
    the ground and the other's does not (`TOUCH_FORCE_N`), and the normal forces [N] on both sides."""

    sensor: str
    differing_cycles: list[int]
    real_force_n: dict[int, float]
    ours_force_n: dict[int, float]

    @property
    def first_cycle(self) -> int | None:
        return self.differing_cycles[0] if self.differing_cycles else None


@dataclass(frozen=True)
class FrozenEpisode:
    """Cycles in a row on which several commanded joints did not move on one server (``side``: "real" or "ours"):
    the referee froze them (a self-collision foul, 1 s). An open-loop replay follows such a freeze only when the same
    foul is called here in the same cycle; the real front stand-up's recording has one that ours does not call."""

    side: str
    first_cycle: int
    last_cycle: int
    joints: tuple[str, ...]
    """The joints held still in the episode's first cycle (HJ names, sorted)."""


@dataclass(frozen=True)
class Divergence:
    """A replay's divergence from its real recording, over the cycles from the skill's start until one robot has been
    fallen and the other not for half a second (open loop, what follows says nothing more; both falling, as a
    stand-up trace's scripted fall, is compared on, a cycle apart too)."""

    trace: str
    skill_cycle: int
    cycles: list[int]
    joints: list[JointDivergence]
    """Every joint both sides report, earliest divergence first (never-diverging joints last, by name)."""
    pose: PoseDivergence
    contacts: list[ContactDivergence]
    """Every foot sensor either side reports, earliest difference first."""
    frozen: list[FrozenEpisode]
    """Frozen joints on either server over the compared cycles, in order of their first cycle."""

    def seconds_after_skill(self, cycle: int | None) -> str:
        """``cycle`` as seconds after the skill's start, for tables ("-" for None)."""
        return "-" if cycle is None else f"{(cycle - self.skill_cycle) * CYCLE_S:.2f}"


def _first(cycles: list[int], past: Callable[[int], bool]) -> int | None:
    return next((i for i in cycles if past(i)), None)


@lru_cache(maxsize=1)
def _perceptor_of() -> dict[str, str]:
    """Effector name -> HJ perceptor name (``lae1`` -> ``laj1``) over every robot type's joints."""
    return {joint.effector: joint.perceptor for robot_type in range(5) for joint in robot_spec(robot_type).joints}


def _commanded_rad_s(reply: bytes | None) -> dict[str, float]:
    """HJ name -> velocity [rad/s] the agent's answer sent (empty for no answer or one that does not parse)."""
    if not reply:
        return {}
    perceptor = _perceptor_of()
    try:
        actions = parse_actions(reply)   # the usual all-joints answer takes its fast path
    except ProtocolError:
        return {}
    return {perceptor[a.effector]: a.velocity_rad_s for a in actions
            if isinstance(a, JointVelocity) and a.effector in perceptor}


def frozen_episodes(replay: Replay, side: str, cycles: Sequence[int]) -> list[FrozenEpisode]:
    """The runs of cycles on ``side`` in which `FROZEN_MIN_JOINTS` or more joints commanded at least
    `STILL_COMMAND_RAD_S` moved less than `STILL_DEG`. The answer to sense message i moves the joints between
    messages i + 1 and i + 2 (both servers apply it in the step after the next message), so cycle i is judged on
    those two readings."""
    last = len(replay.fixture.received) if side == "real" else len(replay.states.messages)
    frozen: list[tuple[int, tuple[str, ...]]] = []
    for i in cycles:
        if i + 2 >= last:
            break
        commanded = _commanded_rad_s(replay.fixture.replies.get(i))
        before, after = replay.sense(side, i + 1).joints, replay.sense(side, i + 2).joints
        still = tuple(sorted(j for j, v in commanded.items() if abs(v) >= STILL_COMMAND_RAD_S
                             and j in before and j in after and abs(after[j] - before[j]) < STILL_DEG))
        if len(still) >= FROZEN_MIN_JOINTS:
            frozen.append((i, still))
    episodes: list[FrozenEpisode] = []
    for i, still in frozen:
        if episodes and episodes[-1].last_cycle == i - 1:
            episodes[-1] = replace(episodes[-1], last_cycle=i)
        else:
            episodes.append(FrozenEpisode(side, i, i, still))
    return episodes


def _parted(cycles: list[int], real: dict[int, Truth], ours: dict[int, Truth]) -> int | None:
    """First cycle of the first run of `PARTED_HOLD_CYCLES` in which one robot is fallen and the other not (a
    scripted fall that lands a cycle earlier on one server is not a parting)."""
    run_start, run = None, 0
    for i in cycles:
        if i in real and i in ours and fallen(real[i]) != fallen(ours[i]):
            run_start, run = (i if run == 0 else run_start), run + 1
            if run >= PARTED_HOLD_CYCLES:
                return run_start
        else:
            run = 0
    return None


def divergence(replay: Replay, threshold_deg: float = JOINT_THRESHOLD_DEG) -> Divergence:
    """Compare ``replay`` with its real recording cycle by cycle from the skill's start (see `Divergence`).

    Raises:
        ValueError: the trace has no skill-phase cycle that both sides report.
    """
    fixture = replay.fixture
    start = fixture.skill_cycle
    shared = list(range(start, min(len(fixture.received), len(replay.states.messages))))
    if not shared:
        raise ValueError(f"{fixture.name}: no cycle from the skill's start ({start}) on both sides")
    real_truth, ours_truth = replay.real, replay.ours
    real_fall = _first(shared, lambda i: i in real_truth and fallen(real_truth[i]))
    ours_fall = _first(shared, lambda i: i in ours_truth and fallen(ours_truth[i]))
    parted = _parted(shared, real_truth, ours_truth)
    cycles = [i for i in shared if parted is None or i <= parted]
    errors: dict[str, dict[int, float]] = {}
    real_force: dict[str, dict[int, float]] = {}
    ours_force: dict[str, dict[int, float]] = {}
    for i in cycles:
        real_sense, ours_sense = replay.sense("real", i), replay.sense("ours", i)
        real, ours = real_sense.joints, ours_sense.joints
        for joint in real.keys() & ours.keys():
            errors.setdefault(joint, {})[i] = ours[joint] - real[joint]
        for side, sense in ((real_force, real_sense), (ours_force, ours_sense)):
            for name, contact in sense.frp.items():
                side.setdefault(name, {})[i] = contact.force_n[2]
    joints = [JointDivergence(name, next((i for i, e in found.items() if abs(e) > threshold_deg), None), found)
              for name, found in errors.items()]
    joints.sort(key=lambda j: (j.first_cycle is None, j.first_cycle or 0, j.joint))
    posed = [i for i in cycles if i in real_truth and i in ours_truth]

    def gap(i: int, measure: Callable[[Truth], float]) -> float:
        return abs(measure(ours_truth[i]) - measure(real_truth[i]))

    pose = PoseDivergence(
        _first(posed, lambda i: math.dist(ours_truth[i].torso_m[:2], real_truth[i].torso_m[:2]) > POSITION_THRESHOLD_M),
        _first(posed, lambda i: gap(i, lambda t: t.torso_m[2]) > HEIGHT_THRESHOLD_M),
        _first(posed, lambda i: gap(i, lambda t: t.up_z) > UP_Z_THRESHOLD),
        _first(posed, lambda i: abs(wrap_deg(ours_truth[i].heading_deg - real_truth[i].heading_deg))
               > HEADING_THRESHOLD_DEG),
        real_fall, ours_fall, parted)
    contacts = []
    for sensor in sorted(real_force.keys() | ours_force.keys()):
        real_n, ours_n = real_force.get(sensor, {}), ours_force.get(sensor, {})
        differing = [i for i in cycles
                     if (real_n.get(i, 0.0) > TOUCH_FORCE_N) != (ours_n.get(i, 0.0) > TOUCH_FORCE_N)]
        contacts.append(ContactDivergence(sensor, differing, real_n, ours_n))
    contacts.sort(key=lambda c: (c.first_cycle is None, c.first_cycle or 0, c.sensor))
    frozen = sorted(frozen_episodes(replay, "real", cycles) + frozen_episodes(replay, "ours", cycles),
                    key=lambda e: (e.first_cycle, e.side))
    return Divergence(fixture.name, start, cycles, joints, pose, contacts, frozen)


def divergence_table(found: Divergence, rows: int = 8) -> str:
    """The torso's divergence, then the ``rows`` earliest-diverging joints: when each passed the threshold (s
    after the skill's start), its error 1, 2 and 3 s after the skill's start and its largest [deg]."""
    s = found.seconds_after_skill
    pose = found.pose
    lines = [f"{found.trace}: skill from cycle {found.skill_cycle}, compared over {len(found.cycles)} cycles",
             f"torso past its threshold [s after the skill's start]: position {s(pose.position_cycle)}, height "
             f"{s(pose.height_cycle)}, up axis {s(pose.up_cycle)}, heading {s(pose.heading_cycle)}; fell: real "
             f"{s(pose.real_fall_cycle)}, ours {s(pose.ours_fall_cycle)}; one fallen and the other not for 0.5 s from: {s(pose.parted_cycle)}",
             "feet touching on one side only (FRP above 1 N): " + (", ".join(
                 f"{c.sensor} first at {s(c.first_cycle)} s ({c.real_force_n.get(c.first_cycle, 0.0):.1f} N real, "
                 f"{c.ours_force_n.get(c.first_cycle, 0.0):.1f} N ours), {len(c.differing_cycles)} of "
                 f"{len(found.cycles)} cycles" for c in found.contacts if c.first_cycle is not None) or "never"),
             "joints held still although commanded (a referee freeze): " + (", ".join(
                 f"{e.side} at {s(e.first_cycle)} s for {(e.last_cycle - e.first_cycle + 1) * CYCLE_S:.2f} s "
                 f"({' '.join(e.joints)})" for e in found.frozen) or "never"),
             f"{'joint':6s} {'past [s]':>9s} {'at 1 s':>8s} {'at 2 s':>8s} {'at 3 s':>8s} {'max':>8s}  (ours - real, deg)"]
    for joint in found.joints[:rows]:
        at = []
        for seconds in (1, 2, 3):
            cycle = found.skill_cycle + round(seconds / CYCLE_S)
            at.append(f"{joint.error_deg[cycle]:+8.2f}" if cycle in joint.error_deg else f"{'-':>8s}")
        lines.append(f"{joint.joint:6s} {s(joint.first_cycle):>9s} {' '.join(at)} {joint.max_abs_deg:8.2f}")
    return "\n".join(lines)


def cycle_table(found: Divergence, replay: Replay, first_s: float, last_s: float, joints: Sequence[str] = ()) -> str:
    """Cycle by cycle from ``first_s`` to ``last_s`` after the skill's start: the torso's height [m] and its change
    since the cycle before [mm], each foot sensor's normal force [N] and the ``joints``' HJ angles [deg] (default:
    the three earliest-diverging), real then ours.

    Why: the divergence table says when a replay left the real run; these rows say how. They showed that the real
    forward walk has a cycle with both feet off the ground before every left landing (its torso drops 5.3 mm in it,
    ours 3.1 mm while the right foot still carries 10 N), and that the real front stand-up's joints stood still for a
    second while commanded on (a self-collision freeze).

    Raises:
        ValueError: a joint neither side reports, or ``last_s`` before ``first_s``.
    """
    if last_s < first_s:
        raise ValueError(f"the window {first_s:g}:{last_s:g} s ends before it starts")
    start = found.skill_cycle
    last_message = min(len(replay.fixture.received), len(replay.states.messages)) - 1
    cycles = [i for i in range(start + round(first_s / CYCLE_S), start + round(last_s / CYCLE_S) + 1)
              if 0 <= i <= last_message]
    chosen = list(joints) or [j.joint for j in found.joints[:3]]
    sensors = [c.sensor for c in found.contacts] or ["lf", "rf"]
    if cycles:
        known = replay.sense("real", cycles[0]).joints.keys() | replay.sense("ours", cycles[0]).joints.keys()
        unknown = [j for j in chosen if j not in known]
        if unknown:
            raise ValueError(f"no joint {', '.join(unknown)} in {found.trace} (it has {' '.join(sorted(known))})")
    header = ["  cycle", "t [s]", "torso z real / ours [m]", "dz [mm]"] + [f"{f} [N]" for f in sensors] + \
        [f"{j} [deg]" for j in chosen]
    lines = [f"{found.trace}: cycles {first_s:g}-{last_s:g} s after the skill's start, real / ours",
             " | ".join(header)]
    previous: dict[str, float] = {}
    for i in cycles:
        real, ours = replay.sense("real", i), replay.sense("ours", i)
        cells = [f"{i:7d}", f"{(i - start) * CYCLE_S:5.2f}"]
        heights = {side: truth[i].torso_m[2] for side, truth in (("real", replay.real), ("ours", replay.ours))
                   if i in truth}
        cells.append(" / ".join(f"{heights[side]:.4f}" if side in heights else "-" for side in ("real", "ours")))
        cells.append(" / ".join(f"{1000 * (heights[side] - previous[side]):+5.2f}"
                                if side in heights and side in previous else "-" for side in ("real", "ours")))
        previous = heights
        for sensor in sensors:
            cells.append(" / ".join(f"{sense.frp[sensor].force_n[2]:6.1f}" if sensor in sense.frp else "     -"
                                    for sense in (real, ours)))
        for joint in chosen:
            cells.append(" / ".join(f"{sense.joints[joint]:7.2f}" if joint in sense.joints else "      -"
                                    for sense in (real, ours)))
        lines.append(" | ".join(cells))
    return "\n".join(lines)


def plot_divergence(found: Divergence, replay: Replay, path: Path, joints: int = 4) -> Path:
    """The torso's height and up axis, real and ours, over the compared cycles, the error of the ``joints``
    earliest-diverging joints, and the normal force of the foot whose touching differs first, as PNG."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from motion_studio.figures import write_png

    def seconds(cycles: list[int]) -> list[float]:
        return [(i - found.skill_cycle) * CYCLE_S for i in cycles]

    fig, axes = plt.subplots(4, 1, figsize=(10, 10), sharex=True)
    posed = [i for i in found.cycles if i in replay.real and i in replay.ours]
    for side, truth in (("real", replay.real), ("ours", replay.ours)):
        axes[0].plot(seconds(posed), [truth[i].torso_m[2] for i in posed], label=side)
        axes[1].plot(seconds(posed), [truth[i].up_z for i in posed], label=side)
    axes[0].set_ylabel("torso height [m]")
    axes[1].set_ylabel("torso up axis z")
    for joint in found.joints[:joints]:
        cycles = sorted(joint.error_deg)
        axes[2].plot(seconds(cycles), [joint.error_deg[i] for i in cycles], label=joint.joint)
    axes[2].set_ylabel("joint angle, ours - real [deg]")
    contact = found.contacts[0] if found.contacts else None
    if contact is not None:
        for side, forces in (("real", contact.real_force_n), ("ours", contact.ours_force_n)):
            axes[3].plot(seconds(found.cycles), [forces.get(i, 0.0) for i in found.cycles], label=f"{side} {contact.sensor}")
    axes[3].set_ylabel("foot normal force [N]")
    axes[3].set_xlabel("time after the skill's start [s]")
    for ax in axes:
        ax.legend(loc="upper left")
        ax.grid(alpha=0.3)
    axes[0].set_title(f"{found.trace}: open-loop replay on ours against the real recording")
    return write_png(fig, path)


__all__ = ["ContactDivergence", "Divergence", "FrozenEpisode", "JointDivergence", "PoseDivergence", "cycle_table",
           "divergence", "divergence_table", "frozen_episodes", "plot_divergence"]
