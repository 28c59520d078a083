"""Simulation speed on one core: in-process agents against sim.engine (figures, never assertions).

Run: ``python benchmarks/bench_sim.py [--robots N ...] [--cycles C] [--json]`` (or ``motion-studio bench sim``).
Each agent parses its whole sense message and answers 22 joint velocities every cycle (sim.benchmark).
Targets: 1 robot >= 100x real time, 22 robots >= 5x.
"""

from __future__ import annotations

import argparse
import json

from sim.benchmark import TARGET_REALTIME_FACTOR, run


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--robots", type=int, nargs="+", default=[1, 22], help="robot counts to time")
    parser.add_argument("--cycles", type=int, default=500, help="timed cycles per run (20 ms each)")
    parser.add_argument("--json", action="store_true", help="one JSON object per line")
    parser.add_argument("--no-parse", action="store_true",
                        help="agents skip parsing: the simulator's own speed (not the benchmark's figure)")
    args = parser.parse_args(argv)
    for robots in args.robots:
        figures = run(robots, args.cycles, parse=not args.no_parse).as_dict()
        if args.json:
            print(json.dumps(figures))
            continue
        target = TARGET_REALTIME_FACTOR.get(robots)
        goal = f" (target {target:g}x)" if target else ""
        label = "" if figures["agents_parse"] else " [agents do not parse]"
        print(f"{robots:2d} robots{label}: {figures['realtime_factor']:6.1f}x real time{goal}, physics alone "
              f"{figures['raw_mujoco_realtime_factor']:.1f}x, {figures['wall_seconds']:.2f} s for "
              f"{figures['sim_seconds']:.1f} s simulated")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
