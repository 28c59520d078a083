"""The distance-controlled kick's table, measured: ball distance per stretch of the kick's strike phases, on the
real rcssserver3d 0.7.3 and on our simulator side by side (``agent.motion.dynamic.KickDistance``).

    python -m motion_studio.realserver.kick_distance --stretches 1,1.9,2.1,2.25,3 --write

Each stretch plays ``kick`` and ``kick_left`` from their spot with the ball moved along the kick line by each
offset (as ``kick_check``), on both servers (``--ours-only``: ours alone). Every kick is appended to the rows
file at once (``--rows``), and a rerun with the same file measures only what is missing, so a stalled or killed
run loses no kick. ``--write`` puts the table into the dynamic elements' file: the mean distance per stretch on
the judging server (the real one unless ``--ours-only``), keeping only stretches whose mean lies beyond the
previous, slower one's (the table must rise as the stretch falls). A PNG shows every kick per stretch and server.
It re-runs itself inside netns.sh; the real server never runs in tests.
"""

from __future__ import annotations

import argparse
import json
import sys
from collections.abc import Callable, Sequence
from dataclasses import fields, replace
from pathlib import Path

from agent.motion import MotionLibrary, default_library, load_dynamic_params
from agent.motion.dynamic import DEFAULT_PARAMS_PATH, DynamicParams, KickDistance
from motion_studio.figures import write_png
from motion_studio.kick_rollout import KickRun, Placement, run_kick
from motion_studio.tuning.dynamic_file import write_dynamic_section
from motion_studio.tuning.params_file import Provenance, section_text

#: The kicks measured (the mirrored kick shares the table).
MOTIONS = ("kick", "kick_left")
#: Ball offsets along the kick line [m] (kick_check's).
OFFSETS_M = (-0.02, -0.01, 0.0, 0.01, 0.02)
#: One kick on one server: (library, motion, placement, dynamic elements) -> the measured run.
Rollout = Callable[[MotionLibrary, str, Placement, DynamicParams], KickRun]


def fixed_stretch(dynamic: DynamicParams, stretch: float) -> DynamicParams:
    """``dynamic`` with a one-row kick-distance table, so that any request plays ``stretch``."""
    table = replace(dynamic.kick_distance, motions=MOTIONS, distance_points_m=(1.0,), stretch=(stretch,))
    return replace(dynamic, kick_distance=table)


def _key(row: dict) -> tuple[float, str, float, str]:
    return row["stretch"], row["motion"], row["offset_m"], row["server"]


def missing(rows: Sequence[dict], stretches: Sequence[float], offsets_m: Sequence[float], server: str) -> int:
    """How many kicks of the sweep ``server`` has not played yet."""
    done = {_key(row) for row in rows}
    return sum((s, m, o, server) not in done for s in stretches for m in MOTIONS for o in offsets_m)


def measure(stretches: Sequence[float], offsets_m: Sequence[float], servers: dict[str, Rollout],
            library: MotionLibrary, rows: list[dict], save: Callable[[list[dict]], None],
            report: Callable[[str], None] = lambda text: None) -> list[dict]:
    """Every (stretch, motion, offset, server) kick not in ``rows`` yet, appended and saved one by one."""
    done = {_key(row) for row in rows}
    base = load_dynamic_params()
    for stretch in stretches:
        dynamic = fixed_stretch(base, stretch)
        for motion in MOTIONS:
            for offset in offsets_m:
                for server, rollout in servers.items():
                    if (stretch, motion, offset, server) in done:
                        continue
                    figures = rollout(library, motion, Placement(offset), dynamic).figures()
                    rows.append({"stretch": stretch, "motion": motion, "offset_m": offset, "server": server,
                                 **figures})
                    save(rows)
                    report(f"stretch {stretch:g} {motion} {offset * 100:+.0f} cm {server}: "
                           f"{figures['distance_m']:.2f} m{', fell' if figures['fell'] else ''}")
    return rows


def summary(rows: Sequence[dict]) -> dict[str, dict[float, dict[str, float]]]:
    """Server -> stretch -> mean/min/max distance [m], falls and kicks."""
    out: dict[str, dict[float, dict[str, float]]] = {}
    for server in sorted({row["server"] for row in rows}):
        for stretch in sorted({row["stretch"] for row in rows if row["server"] == server}):
            distances = [r["distance_m"] for r in rows if r["server"] == server and r["stretch"] == stretch]
            falls = sum(r["fell"] for r in rows if r["server"] == server and r["stretch"] == stretch)
            out.setdefault(server, {})[stretch] = {
                "mean_m": round(sum(distances) / len(distances), 3), "min_m": round(min(distances), 3),
                "max_m": round(max(distances), 3), "falls": falls, "kicks": len(distances)}
    return out


def table_from(per_stretch: dict[float, dict[str, float]], provenance: str) -> KickDistance:
    """The kick-distance table of one server's summary: from the slowest stretch on, a stretch is kept when its
    mean distance lies beyond the last kept one's.

    Raises:
        ValueError: no stretch was measured.
    """
    if not per_stretch:
        raise ValueError("no kicks measured: nothing to build the table from")
    distances: list[float] = []
    stretches: list[float] = []
    for stretch in sorted(per_stretch, reverse=True):
        mean = per_stretch[stretch]["mean_m"]
        if not distances or mean > distances[-1]:
            distances.append(mean)
            stretches.append(stretch)
    return KickDistance(motions=MOTIONS, phases=load_dynamic_params().kick_distance.phases,
                        distance_points_m=tuple(distances), stretch=tuple(stretches), provenance=provenance)


def write_table(table: KickDistance, path: Path = DEFAULT_PARAMS_PATH) -> None:
    """Rewrite the ``[kick_distance]`` section of ``path`` through the tuning room's one writer (the other
    sections and comments stay) and check that the file loads back to ``table``.

    Raises:
        TuningError: the rewritten file does not load back to the table (the file is left unchanged).
    """
    values = {f.name: getattr(table, f.name) for f in fields(table)}
    write_dynamic_section("kick_distance", table, section_text("kick_distance", values), path)


def figures_text(figures: dict[str, dict[float, dict[str, float]]], judge: str) -> str:
    """The figures a written table carries in its provenance: every stretch's distances on each server."""
    parts = []
    for server, per_stretch in figures.items():
        cells = ", ".join(f"{stretch:g}: {f['mean_m']:.2f} ({f['min_m']:.2f}-{f['max_m']:.2f}, {f['kicks']} kicks"
                          f"{', ' + str(f['falls']) + ' falls' if f['falls'] else ''})"
                          for stretch, f in per_stretch.items())
        parts.append(f"{server}: {cells}")
    phases = "/".join(load_dynamic_params().kick_distance.phases)
    return (f"mean ball rest distance [m] per stretch of the {phases} phases of kick and kick_left, "
            f"{'; '.join(parts)}; the table holds the {judge} server's means")


def plot(rows: Sequence[dict], path: Path) -> Path:
    """Every kick's distance against its stretch, one colour per server, the means joined."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(7, 4.5))
    colours = {"real": "tab:red", "ours": "tab:blue"}
    for server, per_stretch in summary(rows).items():
        xs = [r["stretch"] for r in rows if r["server"] == server]
        ys = [r["distance_m"] for r in rows if r["server"] == server]
        ax.scatter(xs, ys, s=14, alpha=0.5, color=colours.get(server))
        stretches = sorted(per_stretch)
        ax.plot(stretches, [per_stretch[s]["mean_m"] for s in stretches], color=colours.get(server),
                label=f"{server} (mean)")
    ax.set_xlabel("stretch of the strike phases (1 = the kick as authored)")
    ax.set_ylabel("ball rest distance [m]")
    ax.set_title("distance-controlled kick: kick and kick_left, ball offsets along the line")
    ax.grid(alpha=0.3)
    ax.legend()
    return write_png(fig, path, dpi=110)


def _ours(library: MotionLibrary, motion: str, placement: Placement, dynamic: DynamicParams) -> KickRun:
    return run_kick(library, motion, placement, dynamic=dynamic, distance_m=1.0)


PROGRAM = "python -m motion_studio.realserver.kick_distance"


def main(argv: list[str] | None = None) -> int:
    """Run the sweep (see the module docstring); any error is one line on stderr and exit code 2."""
    from motion_studio.realserver.errors import RealServerError
    from motion_studio.tuning.errors import TuningError

    try:
        return _main(list(argv) if argv is not None else sys.argv[1:])
    except (ValueError, OSError, RealServerError, TuningError) as error:
        print(f"{PROGRAM}: error: {error}", file=sys.stderr)
        return 2


def _read_rows(path: Path) -> list[dict]:
    """The kicks kept by an earlier run (none if the file is missing).

    Raises:
        ValueError: the file is not a JSON list of kick rows (names the file).
    """
    if not path.exists():
        return []
    try:
        rows = json.loads(path.read_text())
    except json.JSONDecodeError as error:
        raise ValueError(f"{path}: not JSON ({error}); move it away to start afresh") from None
    if not isinstance(rows, list) or any(not isinstance(r, dict) or not {"stretch", "motion", "offset_m", "server",
                                                                         "distance_m"} <= set(r) for r in rows):
        raise ValueError(f"{path}: not a list of kick rows (stretch, motion, offset_m, server, distance_m)")
    return rows


def _main(argv: list[str]) -> int:
    parser = argparse.ArgumentParser(prog=PROGRAM, description=__doc__.splitlines()[0])
    parser.add_argument("--stretches", default="1,1.9,2.1,2.25,3",
                        help="stretch factors of the strike phases to measure, comma-separated (>= 1)")
    parser.add_argument("--offsets-cm", default=",".join(f"{o * 100:g}" for o in OFFSETS_M),
                        help="ball offsets along the kick line from the spot [cm], comma-separated")
    parser.add_argument("--out", type=Path, default=Path("out/kick_distance"),
                        help="folder of the rows file, the plot and the real server's logs")
    parser.add_argument("--rows", type=Path, default=None, help="rows file (default OUT/rows.json); kept rows "
                        "are not measured again")
    parser.add_argument("--ours-only", action="store_true", help="our simulator only (no real server)")
    parser.add_argument("--write", action="store_true", help="write the table into the dynamic elements' file")
    args = parser.parse_args(argv)
    try:
        stretches = [float(v) for v in args.stretches.split(",") if v.strip()]
        offsets = [float(v) / 100.0 for v in args.offsets_cm.split(",") if v.strip()]
    except ValueError as error:
        raise ValueError(f"--stretches / --offsets-cm take comma-separated numbers: {error}") from None
    if not stretches or any(not s >= 1.0 for s in stretches):
        raise ValueError(f"--stretches: every stretch must be >= 1, got {stretches}")
    rows_path = args.rows or args.out / "rows.json"
    rows = _read_rows(rows_path)
    real = not args.ours_only and missing(rows, stretches, offsets, "real") > 0
    if real:
        from motion_studio.realserver.rollout_kick import ensure_private_network

        ensure_private_network("motion_studio.realserver.kick_distance", argv)
    rows_path.parent.mkdir(parents=True, exist_ok=True)

    def save(current: list[dict]) -> None:
        rows_path.write_text(json.dumps(current, indent=1))

    library = default_library(0)
    servers: dict[str, Rollout] = {"ours": _ours}
    report = lambda text: print(text, flush=True)  # noqa: E731
    if not real:
        measure(stretches, offsets, servers, library, rows, save, report)
    else:
        from motion_studio.realserver.rollout_kick import RealKickBench

        with RealKickBench(args.out / "real") as bench:
            def real_kick(lib: MotionLibrary, motion: str, placement: Placement, dynamic: DynamicParams) -> KickRun:
                bench.dynamic = dynamic
                return bench.run(lib, motion, placement, distance_m=1.0).run

            measure(stretches, offsets, {"real": real_kick, **servers}, library, rows, save, report)
    chosen = [r for r in rows if r["stretch"] in stretches and r["offset_m"] in offsets]
    figures = summary(chosen)
    for server, per_stretch in figures.items():
        for stretch, f in per_stretch.items():
            print(f"{server:5s} stretch {stretch:5g}: mean {f['mean_m']:.2f} m, {f['min_m']:.2f}-{f['max_m']:.2f}, "
                  f"falls {f['falls']}/{f['kicks']}")
    print(f"plot: {plot(chosen, args.out / 'kick_distance.png')}")
    if args.write:
        judge = "ours" if args.ours_only else "real"
        command = ["python", "-m", "motion_studio.realserver.kick_distance", *argv]
        table = table_from(figures.get(judge, {}), Provenance.now(command).text(figures_text(figures, judge)))
        write_table(table)
        print(f"wrote [kick_distance] to {DEFAULT_PARAMS_PATH}: distances {list(table.distance_points_m)} m, "
              f"stretches {list(table.stretch)}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
