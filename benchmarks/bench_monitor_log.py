"""Sizes of a match's monitor log and meshcat replay (issue 16: a 10-minute 11 v 11 log <= 20 MB gzipped,
replay.html <= 10 MB). Figures, never assertions.

Run: ``python benchmarks/bench_monitor_log.py --players 11 --duration 60 [--out DIR]``. Plays one match of our
soccer agents on our simulator with the default log writer (a line every 0.2 s, full state then diffs,
compact numbers), writes the replay page as ``motion-studio demo`` does, and prints the sizes, plus the
log's size scaled to a 10-minute match (duration x 600 / played; the first seconds before kick-off are
cheaper than play, so the scaled figure is a little low for short runs).
"""

from __future__ import annotations

import argparse
import gzip
import json
import tempfile
import time
from pathlib import Path

from motion_studio.match_agents import make_agent
from sim.match import MatchConfig, run_match
from sim.replay import replay_log

FULL_MATCH_S = 600.0


def measure(players: int, duration_s: float, out: Path, max_frames: int = 1500) -> dict[str, float | int]:
    """Play, log, replay; returns the figures (sizes in bytes)."""
    out.mkdir(parents=True, exist_ok=True)
    log = out / "match.log.gz"
    started = time.perf_counter()
    result = run_match(MatchConfig(players_per_team=players, duration_s=duration_s, log_path=str(log)), make_agent)
    match_wall_s = time.perf_counter() - started
    with gzip.open(log, "rb") as stream:
        raw = stream.read()
    html = Path(replay_log(log, html_out=out / "replay.html", max_frames=max_frames))
    scale = FULL_MATCH_S / max(result.game_time_s, 1e-9)
    return {"players_per_team": players, "game_time_s": result.game_time_s, "match_wall_s": round(match_wall_s, 1),
            "log_lines": raw.count(b"\n"), "log_full_states": raw.count(b"(RSG 0 1)"), "log_raw_bytes": len(raw),
            "log_gzip_bytes": log.stat().st_size, "log_gzip_bytes_per_600_s": round(log.stat().st_size * scale),
            "replay_html_bytes": html.stat().st_size}


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--players", type=int, default=11, choices=range(1, 12), metavar="1-11",
                        help="players per team (default 11)")
    parser.add_argument("--duration", type=float, default=60.0, help="game seconds to play (default 60)")
    parser.add_argument("--out", type=Path, default=None, help="folder for the log and the replay (default: temporary)")
    args = parser.parse_args(argv)
    if not 1.0 <= args.duration <= FULL_MATCH_S:
        parser.error(f"--duration must be within 1-600 s, got {args.duration}")
    if args.out is None:
        with tempfile.TemporaryDirectory() as folder:
            figures = measure(args.players, args.duration, Path(folder))
    else:
        figures = measure(args.players, args.duration, args.out)
    print(json.dumps(figures))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
