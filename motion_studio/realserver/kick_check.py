"""Kick figures on both servers: each kick motion from its spot and from small placement errors, on the real
rcssserver3d 0.7.3 (``rollout_kick.RealKickBench``) and on our simulator (``motion_studio.kick_rollout``),
side by side: ball rest distance, direction error against the aim, the strike's time, the foot's and the
ball's speeds at the strike, how high the ball went, falls.

    python -m motion_studio.realserver.kick_check kick kick_strong --motions HEAD --json out/kick_check.json

(It re-runs itself inside netns.sh; the real server never runs in tests.)
"""

from __future__ import annotations

import argparse
import json
import math
import sys
import tempfile
from collections.abc import Callable, Sequence
from pathlib import Path

from agent.motion import MotionLibrary
from motion_studio.kick_rollout import KickRun, Placement, run_kick
from motion_studio.realserver.cases import motion_source

#: Ball offsets along the kick line from the motion's spot [m] (issue 12: the spot and +-1, +-2 cm).
OFFSETS_M = (-0.02, -0.01, 0.0, 0.01, 0.02)
#: Rollout per server: (library, motion, placement) -> KickRun.
Rollout = Callable[[MotionLibrary, str, Placement], KickRun]


def measure_kicks(library: MotionLibrary, motions: Sequence[str], offsets_m: Sequence[float],
                  servers: dict[str, Rollout], report: Callable[[str], None] = lambda text: None) -> list[dict]:
    """One row per motion, offset and server: the run's figures (``KickRun.figures``) with those three."""
    rows = []
    for motion in motions:
        for offset in offsets_m:
            for server, rollout in servers.items():
                figures = rollout(library, motion, Placement(offset)).figures()
                rows.append({"motion": motion, "offset_m": offset, "server": server, **figures})
                report(f"{motion} {offset * 100:+.1f} cm {server}: {figures['distance_m']:.2f} m, "
                       f"{figures['direction_error_deg']:+.1f} deg{', fell' if figures['fell'] else ''}")
    return rows


def summary(rows: Sequence[dict]) -> dict[str, dict[str, dict[str, float]]]:
    """Motion -> server -> mean/min distance [m], mean and worst |direction error| [deg], falls, kicks."""
    out: dict[str, dict[str, dict[str, float]]] = {}
    for row in rows:
        out.setdefault(row["motion"], {}).setdefault(row["server"], {})
    for motion, servers in out.items():
        for server in servers:
            group = [r for r in rows if r["motion"] == motion and r["server"] == server]
            distances = [r["distance_m"] for r in group]
            errors = [abs(r["direction_error_deg"]) for r in group]
            servers[server] = {"mean_m": round(sum(distances) / len(distances), 3), "min_m": round(min(distances), 3),
                               "direction_mean_deg": round(sum(errors) / len(errors), 2),
                               "direction_max_deg": round(max(errors), 2), "falls": sum(r["fell"] for r in group),
                               "kicks": len(group)}
    return out


def table(rows: Sequence[dict]) -> str:
    """Per motion and offset a line per server, then each server's summary."""
    keys = ("distance_m", "direction_error_deg", "contact_s", "foot_speed_m_s", "ball_speed_m_s",
            "ball_max_height_m", "fell")
    lines = [f"{'motion':18s} {'offset':>6s} {'server':6s} " + " ".join(f"{k:>19s}" for k in keys)]
    for row in rows:
        cells = " ".join(f"{_cell(row[k]):>19s}" for k in keys)
        lines.append(f"{row['motion']:18s} {row['offset_m'] * 100:+5.1f}cm {row['server']:6s} {cells}")
    for motion, servers in summary(rows).items():
        for server, figures in servers.items():
            lines.append(f"{motion} on {server}: mean {figures['mean_m']:.2f} m, min {figures['min_m']:.2f} m, "
                         f"direction error mean {figures['direction_mean_deg']:.1f} deg (worst "
                         f"{figures['direction_max_deg']:.1f}), falls {figures['falls']}/{figures['kicks']}")
    return "\n".join(lines)


def _cell(value: object) -> str:
    if value is None:
        return "-"
    if isinstance(value, float):
        return "-" if math.isnan(value) else f"{value:.3f}"
    return str(value)


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("motions", nargs="*", default=["kick", "kick_strong"], help="kick motions (default: "
                        "kick kick_strong)")
    parser.add_argument("--offsets-cm", default=",".join(f"{o * 100:g}" for o in OFFSETS_M),
                        help="ball offsets along the kick line from the spot [cm], comma-separated")
    parser.add_argument("--motions-rev", default="worktree",
                        help="git revision of motions/files to play (default: the working tree)")
    parser.add_argument("--out", type=Path, default=Path("out/kick_check"), help="the real server's logs")
    parser.add_argument("--json", type=Path, help="also write the rows and the summary as JSON")
    parser.add_argument("--ours-only", action="store_true", help="our simulator only (no real server)")
    parser.add_argument("--type", type=int, default=0, choices=range(5), dest="robot_type",
                        help="robot type that kicks, with that type's motions (default 0)")
    args = parser.parse_args(argv)
    offsets = [float(value) / 100.0 for value in args.offsets_cm.split(",") if value.strip()]
    if not args.ours_only:
        from motion_studio.realserver.rollout_kick import ensure_private_network

        ensure_private_network("motion_studio.realserver.kick_check", list(argv) if argv is not None else sys.argv[1:])
    source = motion_source(args.motions_rev, Path(tempfile.mkdtemp(prefix="motions_")))
    library = source.library(args.robot_type, include_withheld=True)   # a named motion is measured, played or not
    robot_type = args.robot_type
    servers: dict[str, Rollout] = {
        "ours": lambda lib, motion, placement: run_kick(lib, motion, placement, robot_type=robot_type)}
    print(f"motions: {source.revision}", flush=True)
    if args.ours_only:
        rows = measure_kicks(library, args.motions, offsets, servers, lambda text: print(text, flush=True))
    else:
        from motion_studio.realserver.rollout_kick import RealKickBench

        with RealKickBench(args.out, robot_type=robot_type) as bench:
            servers = {"real": lambda lib, motion, placement: bench.run(lib, motion, placement).run, **servers}
            rows = measure_kicks(library, args.motions, offsets, servers, lambda text: print(text, flush=True))
    print(table(rows))
    if args.json is not None:
        args.json.parent.mkdir(parents=True, exist_ok=True)
        args.json.write_text(json.dumps({"motions": source.revision, "rows": rows, "summary": summary(rows)},
                                        indent=1))


if __name__ == "__main__":
    main()
