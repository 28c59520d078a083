"""Editor speed: requests inside the server, and slider move -> updated 3D view in headless Chromium.

Run: ``python benchmarks/bench_editor.py [--moves N] [--motion FILE] [--screenshot PNG] [--json]`` (or
``motion-studio bench editor``). The browser part needs Debian's chromium (scripts/setup_browser.sh) and the
playwright package (dev extra); without them it is skipped with the reason. Figures only, never assertions.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from motion_studio.cli import _register_commands, app


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--motion", type=Path, help="motion file (a copy is edited); default: a built-in crouch")
    parser.add_argument("--moves", type=int, default=40, help="slider steps timed in the browser")
    parser.add_argument("--screenshot", type=Path, help="save a PNG of the editor here")
    parser.add_argument("--json", action="store_true", help="one JSON object")
    args = parser.parse_args(argv)
    command = ["bench", "editor", "--moves", str(args.moves)]
    if args.motion is not None:
        command += ["--motion", str(args.motion)]
    if args.screenshot is not None:
        command += ["--screenshot", str(args.screenshot)]
    if args.json:
        command.append("--json")
    _register_commands()
    app(command, standalone_mode=False)
    return 0


if __name__ == "__main__":
    sys.exit(main())
