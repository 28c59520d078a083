"""Issue 15 "Speed": an 11 v 11 match of our agents and the engine alone with 1 robot, as ratios to real time.

Run: ``python benchmarks/bench_speed.py [--duration S] [--agent-processes N] [--json]`` (or
``motion-studio bench speed``). Targets: the match >= 1.5x real time on 2 cores (cycles x 20 ms / wall s), the
engine with 1 robot >= 100x. Figures, never assertions; on a machine busy with other work, read the CPU seconds.
"""

from __future__ import annotations

import sys

from motion_studio.cli import main as cli_main


def main(argv: list[str] | None = None) -> None:
    sys.argv = ["motion-studio", "bench", "speed", *(sys.argv[1:] if argv is None else argv)]
    cli_main()   # exits with the command's status


if __name__ == "__main__":
    main()
