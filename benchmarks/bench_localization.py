"""Self-localization error on our server (sim.engine, REFERENCE §3.5 vision noise): the EKF vs the seed.

Run: ``python benchmarks/bench_localization.py [--quick] [--json] [--plot out/localization_comparison.png]
[--record tests/agent/fixtures/oursim_localization.jsonl]``.

One robot (type 0, team frame = world frame, left team), head still, in three scenarios:
* standing: placed at 8 poses over the field (each with 2-4 landmarks in view), standing 3 s at each;
* walking: no walk motion exists yet, so the robot is teleported along a rounded rectangle (half sizes
  6 x 3.5 m around (-2, 0)) at 0.5 m/s, heading along the path: before every cycle ``World.move_robot``
  puts it on the path at z 0.4 (as beam does) and the torso is given the path's linear and yaw velocity,
  so the gyro reads the turn rate and the robot, 1.5 cm above the ground, moves along the path during the
  cycle (the accelerometer then reads free fall, which the orientation filter ignores);
* turning: the same teleporting, turning in place at 30 °/s (the thesis' turn speed) at 3 spots.
The EKF (default) and the seed (triangulation + FIFO, Algorithm 1) read the same sense messages (two
agents, the EKF's replies go to the server). Ground truth: the torso's ground point and heading in the
world at the time the message was made. Scored: every cycle from the first pose on; position error [m],
heading error [deg]; median and p90 per scenario, plus the share of cycles with no pose at all. The first
0.5 s of a scenario and after every jump (a new standing pose or turning spot: a kidnapping, which is a
different test) is not scored; nor is the settling after the first placement.
Figures, never assertions; goal: EKF median position error <= 0.10 m.
"""

from __future__ import annotations

import argparse
import itertools
import json
import math
import statistics
from collections.abc import Callable, Iterator
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

from agent import Agent, AgentConfig
from agent.world.frames import wrap_angle_rad
from sim.engine import FrozenReferee, SimEngine
from agent.protocol.constants import CYCLE_S

TEAM, UNUM = "Ours", 2
LOCALIZERS = ("ekf", "seed")
WALK_SPEED_M_S = 0.5
TURN_RATE_DEG_S = 30.0
PLACEMENT_HEIGHT_M = 0.4
SETTLE_CYCLES = 25
STANDING_POSES = [(-10.0, 0.0, 0.0), (-5.0, 5.0, -45.0), (0.0, 0.0, 90.0), (5.0, -6.0, 180.0),
                  (-12.0, -8.0, 30.0), (8.0, 3.0, -120.0), (-3.0, -2.0, 135.0), (12.0, 7.0, -30.0)]
TURN_SPOTS = [(-5.0, 0.0), (0.0, 3.0), (6.0, -4.0)]

# A target: (x, y, heading_deg, vx, vy, yaw_rate_deg_s) to teleport to before a cycle, or None to leave it.
Target = tuple[float, float, float, float, float, float] | None


def rounded_rectangle(centre=(-2.0, 0.0), half=(6.0, 3.5), radius=1.5, speed=WALK_SPEED_M_S) -> Iterator[Target]:
    """Targets along a closed rounded rectangle, counter-clockwise, one per cycle."""
    (cx, cy), (hx, hy) = centre, half
    long_side, short_side = 2 * (hx - radius), 2 * (hy - radius)
    straight = [(cx - hx + radius, cy - hy, 0.0, long_side), (cx + hx, cy - hy + radius, 90.0, short_side),
                (cx + hx - radius, cy + hy, 180.0, long_side), (cx - hx, cy + hy - radius, 270.0, short_side)]
    step = speed * CYCLE_S
    for sx, sy, heading, length in straight:
        h = math.radians(heading)
        for i in range(int(length / step)):
            yield (sx + math.cos(h) * i * step, sy + math.sin(h) * i * step, heading,
                   speed * math.cos(h), speed * math.sin(h), 0.0)
        # quarter circle to the next side, turning left
        ox, oy = sx + math.cos(h) * length - math.sin(h) * radius, sy + math.sin(h) * length + math.cos(h) * radius
        arc = int((math.pi / 2 * radius) / step)
        for i in range(arc):
            a = h + (math.pi / 2) * i / arc
            yield (ox + math.sin(a) * radius, oy - math.cos(a) * radius, math.degrees(a),
                   speed * math.cos(a), speed * math.sin(a), math.degrees(speed / radius))


def turning(cycles_per_spot: int) -> Iterator[Target]:
    for x, y in TURN_SPOTS:
        for i in range(cycles_per_spot):
            yield (x, y, -90.0 + TURN_RATE_DEG_S * CYCLE_S * i, 0.0, 0.0, TURN_RATE_DEG_S)


def standing(cycles_per_pose: int) -> Iterator[Target]:
    for x, y, heading in STANDING_POSES:
        yield (x, y, heading, 0.0, 0.0, 0.0)
        for _ in range(cycles_per_pose - 1):
            yield None


class Harness:
    """Our server in-process with one robot and one agent per localizer on the same sense messages."""

    def __init__(self, seed: int, record: list[dict] | None = None) -> None:
        self.engine = SimEngine(seed=seed, referee=FrozenReferee())
        self.agents = {name: Agent(AgentConfig(TEAM, UNUM, localization=name), ) for name in LOCALIZERS}
        self.key = self.engine.connect()
        self.engine.receive(self.key, self.agents[LOCALIZERS[0]].connect_message())
        self.truth_previous: tuple[float, float, float] | None = None
        self.record = record
        for _ in range(6):  # scene, init, the first GS with unum and side
            self.cycle(None, score=None)

    def _truth(self) -> tuple[float, float, float] | None:
        world = self.engine.world
        if self.key not in world.by_key:
            return None
        x, y, _ = world.torso_position(self.key)
        return (float(x), float(y), world.heading_deg(self.key))

    def _teleport(self, target: Target) -> None:
        if target is None:
            return
        x, y, heading, vx, vy, yaw_rate = target
        world = self.engine.world
        world.move_robot("left", UNUM, x, y, heading, PLACEMENT_HEIGHT_M)
        dof = world.by_key[self.key].root_dof
        world.data.qvel[dof:dof + 3] = (vx, vy, 0.0)
        world.data.qvel[dof + 5] = math.radians(yaw_rate)  # torso z = world z when upright

    def cycle(self, target: Target, score: list | None) -> None:
        self._teleport(target)
        out = self.engine.step()
        truth, self.truth_previous = self.truth_previous, self._truth()  # out was made at the previous step's end
        message = out.get(self.key)
        if message is None:
            return
        replies = [agent.step(message) for agent in self.agents.values()]
        self.engine.receive(self.key, replies[0])
        if self.record is not None:
            self.record.append({"msg": message.decode("ascii"), "truth": truth})
        if score is None or truth is None:
            return
        row = {}
        for name, agent in self.agents.items():
            pose = agent.world.pose
            if pose is None:
                row[name] = None
            else:
                row[name] = (math.hypot(pose.x_m - truth[0], pose.y_m - truth[1]),
                             abs(math.degrees(wrap_angle_rad(pose.heading_rad - math.radians(truth[2])))))
        score.append(row)


def run_scenario(targets: Iterator[Target], seed: int, skip_after_placement: bool,
                 record: list[dict] | None = None) -> list[dict]:
    harness = Harness(seed, record)
    rows: list[dict] = []
    since_jump = 0
    previous: Target = None
    for target in targets:
        # A placement that is not a small step along a path is a jump (kidnapping): not what is measured here.
        jump = target is not None and (previous is None or math.hypot(target[0] - previous[0],
                                                                      target[1] - previous[1]) > 0.5)
        since_jump = 0 if jump and skip_after_placement else since_jump + 1
        previous = target if target is not None else previous
        harness.cycle(target, rows if since_jump > SETTLE_CYCLES else None)
    return rows


def percentile(values: list[float], q: float) -> float:
    ordered = sorted(values)
    return ordered[min(len(ordered) - 1, int(round(q / 100.0 * (len(ordered) - 1))))] if ordered else math.nan


def summarise(rows: list[dict]) -> dict[str, dict[str, float]]:
    out = {}
    for name in LOCALIZERS:
        errors = [row[name] for row in rows if row.get(name) is not None]
        pos = [e[0] for e in errors]
        head = [e[1] for e in errors]
        out[name] = {
            "cycles": len(rows),
            "no_pose_share": 1.0 - len(errors) / len(rows) if rows else math.nan,
            "pos_median_m": statistics.median(pos) if pos else math.nan,
            "pos_p90_m": percentile(pos, 90),
            "heading_median_deg": statistics.median(head) if head else math.nan,
            "heading_p90_deg": percentile(head, 90),
        }
    return out


def scenarios(quick: bool) -> dict[str, Callable[[], Iterator[Target]]]:
    scale = 0.4 if quick else 1.0
    return {
        "standing": lambda: standing(int(150 * scale)),
        "walking": lambda: itertools.islice(rounded_rectangle(), 1500 if quick else None),
        "turning": lambda: turning(int(600 * scale)),
    }


def plot(results: dict[str, list[dict]], summary: dict, path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(2, len(results), figsize=(5 * len(results), 7), squeeze=False)
    colours = {"ekf": "tab:blue", "seed": "tab:orange"}
    for column, (scenario, rows) in enumerate(results.items()):
        for name in LOCALIZERS:
            pos = [row[name][0] if row.get(name) else math.nan for row in rows]
            head = [row[name][1] if row.get(name) else math.nan for row in rows]
            s = summary[scenario][name]
            label = f"{name}: median {s['pos_median_m']:.3f} m, p90 {s['pos_p90_m']:.3f} m"
            axes[0][column].plot([i * CYCLE_S for i in range(len(rows))], pos, lw=0.8, color=colours[name],
                                 label=label)
            axes[1][column].plot([i * CYCLE_S for i in range(len(rows))], head, lw=0.8, color=colours[name],
                                 label=f"{name}: median {s['heading_median_deg']:.2f}°,"
                                       f" p90 {s['heading_p90_deg']:.2f}°")
        axes[0][column].set_title(f"{scenario}")
        axes[0][column].set_yscale("log")
        axes[1][column].set_yscale("log")
        axes[0][column].set_ylabel("position error [m]")
        axes[1][column].set_ylabel("heading error [deg]")
        axes[1][column].set_xlabel("scored time [s]")
        axes[0][column].legend(fontsize=7)
        axes[1][column].legend(fontsize=7)
    fig.suptitle("Self-localization on our server (REFERENCE §3.5 noise): "
                 "EKF (default) vs seed (triangulation + FIFO)")
    fig.tight_layout()
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=110)
    plt.close(fig)


def record_fixture(path: Path, seed: int) -> None:
    """A short continuous trace for tests (no jumps): 45 cycles standing at the walk's start, 120 walking,
    75 turning left in place where the walk ended; every sense message with its ground truth (< 300 kB)."""
    record: list[dict] = []
    walk = rounded_rectangle()
    start = next(walk)
    steps = [next(walk) for _ in range(120)]
    x, y, heading = steps[-1][0], steps[-1][1], steps[-1][2]
    turn = [(x, y, heading + TURN_RATE_DEG_S * CYCLE_S * i, 0.0, 0.0, TURN_RATE_DEG_S) for i in range(1, 76)]
    targets = [start[:3] + (0.0, 0.0, 0.0)] + [None] * 44 + steps + turn
    run_scenario(iter(targets), seed, skip_after_placement=False, record=record)
    header = {"source": "our server (sim.engine.SimEngine, FrozenReferee)", "seed": seed, "team": TEAM,
              "unum": UNUM, "side": "left", "made_by": "benchmarks/bench_localization.py --record",
              "motion": "45 cycles standing, 120 teleported walking at 0.5 m/s, 75 turning at 30 deg/s",
              "truth": "torso ground point x, y [m] and heading [deg], world frame, when the message was made"}
    with path.open("w", encoding="ascii") as stream:
        stream.write(json.dumps(header) + "\n")
        for row in record:
            stream.write(json.dumps(row, separators=(",", ":")) + "\n")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="shorter scenarios")
    parser.add_argument("--json", action="store_true", help="print one JSON object")
    parser.add_argument("--seed", type=int, default=1, help="server seed (vision, calibration and beam noise)")
    parser.add_argument("--plot", type=Path, default=ROOT / "out" / "localization_comparison.png",
                        help="comparison PNG (default out/localization_comparison.png)")
    parser.add_argument("--record", type=Path, help="also write a short test trace (JSONL) here")
    args = parser.parse_args()
    results = {}
    for name, make in scenarios(args.quick).items():
        results[name] = run_scenario(make(), args.seed, skip_after_placement=True)
    summary = {name: summarise(rows) for name, rows in results.items()}
    plot(results, summary, args.plot)
    if args.record:
        record_fixture(args.record, args.seed)
    if args.json:
        print(json.dumps({"seed": args.seed, "summary": summary, "plot": str(args.plot)}))
        return
    print(f"Self-localization on our server, seed {args.seed} (goal: EKF median position error <= 0.10 m)")
    for scenario, per in summary.items():
        for name, s in per.items():
            print(f"  {scenario:<9} {name:<5} {s['cycles']:>5} cycles  position median {s['pos_median_m']:.3f} m"
                  f"  p90 {s['pos_p90_m']:.3f} m  |  heading median {s['heading_median_deg']:.2f} deg"
                  f"  p90 {s['heading_p90_deg']:.2f} deg  |  no pose {100 * s['no_pose_share']:.1f} %")
    print(f"plot: {args.plot}")


if __name__ == "__main__":
    main()
