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
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

from agent.protocol.constants import CYCLE_S
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

    def seconds_after_skill(self, cycle: int | None) -> str:
        """``cycle`` as seconds after the skill's start, for tables ("-" for None)."""
        return "-" if cycle is None else f"{(cycle - self.skill_cycle) * CYCLE_S:.2f}"


def _first(cycles: list[int], past: Callable[[int], bool]) -> int | None:
    return next((i for i in cycles if past(i)), None)


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
    return Divergence(fixture.name, start, cycles, joints, pose, contacts)


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
             f"{'joint':6s} {'past [s]':>9s} {'at 1 s':>8s} {'at 2 s':>8s} {'at 3 s':>8s} {'max':>8s}  (ours - real, deg)"]
    for joint in found.joints[:rows]:
        at = []
        for seconds in (1, 2, 3):
            cycle = found.skill_cycle + round(seconds / CYCLE_S)
            at.append(f"{joint.error_deg[cycle]:+8.2f}" if cycle in joint.error_deg else f"{'-':>8s}")
        lines.append(f"{joint.joint:6s} {s(joint.first_cycle):>9s} {' '.join(at)} {joint.max_abs_deg:8.2f}")
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


__all__ = ["ContactDivergence", "Divergence", "JointDivergence", "PoseDivergence", "divergence", "divergence_table", "plot_divergence"]
