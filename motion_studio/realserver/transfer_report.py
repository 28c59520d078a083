"""The transfer figures as a table of rows (real, ours, ours/real), as JSON, and as PNG plots."""

from __future__ import annotations

import math
import statistics
from collections.abc import Collection
from dataclasses import dataclass
from pathlib import Path

from motion_studio.realserver.cases import CONTROLLED_KICK_M, CYCLE_S, KICK_LINEUP_CM
from motion_studio.realserver.transfer import (LIES_ON, STANDUP_CASES, WALK_20M, WALK_20M_CASES, WALK_DIRECTIONS,
                                               WALK_FAST_20M, Pair, Transfer, run_name)
from motion_studio.skill_bench.dribble import KEEP_M

#: The dribble cases: (case, what the label calls it).
_DRIBBLES = (("dribble", "dribble 10 m straight"), ("dribble_turn_left", "dribble 4 m turning left"),
             ("dribble_turn_right", "dribble 4 m turning right"))

#: Row labels of the single-run cases, in table order: (case, figure key, label).
SINGLE_ROWS = (
    ("stand", "torso z mean [m]", "stand: torso height [m]"),
    ("walk_forward", "speed [m/s]", "walk forward: speed over 10 s [m/s]"),
    ("walk_fast", "speed [m/s]", "walk fast: speed over 10 s [m/s]"),
    ("walk_backward", "speed [m/s]", "walk backward: speed over 10 s [m/s]"),
    ("walk_left", "speed [m/s]", "walk left: speed over 10 s [m/s]"),
    ("walk_right", "speed [m/s]", "walk right: speed over 10 s [m/s]"),
    *(row for side in ("left", "right") for row in (
        (f"orbit_{side}", "heading change [deg]", f"orbit_{side}: turned in 5 s [deg]"),
        (f"orbit_{side}", "orbit centre ahead [m]", f"orbit_{side}: centre ahead of the start [m]"))),
    ("turn_left", "turn per motion [deg]", "turn_left: turn per motion [deg]"),
    ("turn_right", "turn per motion [deg]", "turn_right: turn per motion [deg]"),
    ("turn_by_90", "turned [deg]", "TurnBy(90): turned [deg]"),
    ("kick", "ball travel [m]", "kick: distance, ball on its spot [m]"),
    ("kick_left", "ball travel [m]", "kick_left: distance [m]"),
    ("kick_strong", "ball travel [m]", "kick_strong: distance [m]"),
    ("kick_strong_left", "ball travel [m]", "kick_strong_left: distance [m]"),
    *((f"kick_{d}m", "ball travel [m]", f"kick asked for {d} m: distance [m]") for d in CONTROLLED_KICK_M),
    # KickToward as a set-piece taker starts it (line-up and kick); the kick-off spot is 50 cm behind the ball
    *((f"kick_lineup_{d}cm", "ball moved [m]", f"KickToward from {d} cm behind the ball: ball moved [m]")
      for d in KICK_LINEUP_CM),
    ("walk_to_ball_beside", "ball moved [m]", "WalkToBall, ball beside the feet: ball moved [m]"),
    *(row for case, label in _DRIBBLES for row in (
        (case, "dribble speed [m/s]", f"{label}: speed [m/s]"),
        (case, f"ball within {KEEP_M} m [share]", f"{label}: ball within {KEEP_M} m of the torso [share]"))),
)


@dataclass
class Row:
    """One figure on both servers. ``real_of``/``ours_of``: the figure is a count out of that many."""

    figure: str
    real: float
    ours: float
    note: str = ""
    real_of: int | None = None
    ours_of: int | None = None

    @property
    def ratio(self) -> float:
        """ours / real (NaN when either is unknown or real is 0); counts compare as fractions."""
        real = self.real / self.real_of if self.real_of else self.real
        ours = self.ours / self.ours_of if self.ours_of else self.ours
        if math.isnan(real) or math.isnan(ours) or real == 0:
            return math.nan
        return ours / real

    def as_dict(self) -> dict:
        return {"figure": self.figure, "real": self.real, "ours": self.ours, "ratio": self.ratio,
                "real_of": self.real_of, "ours_of": self.ours_of, "note": self.note}


def _fall_note(figures: dict[str, dict]) -> str:
    fell = [f"{side} fell at {figures[side]['first fall [s]']:.1f} s" for side in ("real", "ours")
            if not math.isnan(figures.get(side, {}).get("first fall [s]", math.nan))]
    return ", ".join(fell)


def rows(pairs: list[Pair], figures: dict[str, dict], starts: int, absent: str = "no run",
         selected: Collection[str] | None = None) -> list[Row]:
    """The table's rows from the runs' figures (``figures[run name]`` = run_figures of that pair); a case with
    no run is a row of unknowns noted ``absent``, or "not run" when ``selected`` (the cases asked for) leaves it
    out (a replay of one case said "no fixture" of all the others)."""
    by_name = {run_name(pair.case): pair for pair in pairs}

    def missing(case: str) -> str:
        return "not run" if selected is not None and case not in selected else absent

    out: list[Row] = []
    for case, key, label in SINGLE_ROWS:
        if case not in by_name:
            out.append(Row(label, math.nan, math.nan, missing(case)))
            continue
        pair_figures = figures[case]
        walking = case in WALK_DIRECTIONS or case.startswith(("turn", "dribble"))
        note = _fall_note(pair_figures) if walking else ""
        out.append(Row(label, pair_figures["real"].get(key, math.nan), pair_figures["ours"].get(key, math.nan),
                       "; ".join(filter(None, [note, *by_name[case].notes[1:]]))))
    for case in STANDUP_CASES:
        side = f"lying on its {LIES_ON[case]} (case {case})"
        runs = [name for name, pair in by_name.items() if pair.case.name == case]
        if not runs:
            out.append(Row(f"stand-up {side}: stood 1 s > 0.30 m", math.nan, math.nan, missing(case)))
            continue
        counts, times, falls = {}, {}, {}
        for where in ("real", "ours"):
            outcomes = [figures[name][where].get("outcome") for name in runs]
            counts[where] = sum(o == "stood" for o in outcomes)
            falls[where] = sum(o == "no fall" for o in outcomes)
            stood_times = [figures[name][where]["time to stand [s]"] for name in runs
                           if figures[name][where].get("outcome") == "stood"]
            times[where] = statistics.median(stood_times) if stood_times else math.nan
        note = f"{len(runs)} of {starts} starts" if len(runs) < starts else ""
        no_fall = ", ".join(f"{where}: {n} did not fall" for where, n in falls.items() if n)
        out.append(Row(f"stand-up {side}: stood 1 s > 0.30 m", counts["real"], counts["ours"],
                       "; ".join(filter(None, [note, no_fall])), len(runs), len(runs)))
        out.append(Row(f"stand-up {side}: median time [s]", times["real"], times["ours"]))
    for case, label in ((WALK_20M, "20 m forward walk"), (WALK_FAST_20M, "20 m fast walk")):
        if case.name in by_name:
            walk = figures[case.name]
            out.append(Row(f"{label}: falls", walk["real"].get("falls", math.nan), walk["ours"].get("falls", math.nan)))
            out.append(Row(f"{label}: time to 20 m [s]", walk["real"].get("20 m after [s]", math.nan),
                           walk["ours"].get("20 m after [s]", math.nan)))
            out.append(Row(f"{label}: heading change [deg]", walk["real"].get("heading change [deg]", math.nan),
                           walk["ours"].get("heading change [deg]", math.nan)))
        elif case is WALK_20M:
            out.append(Row(f"{label}: falls", math.nan, math.nan, missing(case.name)))
    return out


def _cell(value: float, of: int | None = None, digits: int = 3) -> str:
    if math.isnan(value):
        return "-"
    if of is not None:
        return f"{value:g}/{of}"
    if float(value).is_integer() and abs(value) < 1000 and digits == 0:
        return f"{value:.0f}"
    return f"{value:.{digits}f}"


def _digits(figure: str) -> int:
    if "[deg]" in figure:
        return 1
    if "falls" in figure:
        return 0
    if "[s]" in figure:
        return 2
    return 3


def table(rows_: list[Row], title: str) -> str:
    """The rows as aligned text: figure, real, ours, ours/real, note."""
    width = max(len(row.figure) for row in rows_)
    lines = [title, f"{'figure':<{width}}  {'real 0.7.3':>10}  {'ours':>10}  {'ours/real':>9}  note"]
    for row in rows_:
        digits = _digits(row.figure)
        ratio = "-" if math.isnan(row.ratio) else f"{row.ratio:.2f}"
        lines.append(f"{row.figure:<{width}}  {_cell(row.real, row.real_of, digits):>10}  "
                     f"{_cell(row.ours, row.ours_of, digits):>10}  {ratio:>9}  {row.note}".rstrip())
    return "\n".join(lines)


def summary(result: Transfer, rows_: list[Row], *, code: str, starts: int, seed: int, wall_s: float,
            plots: list[Path], robot_type: int = 0) -> dict:
    """Everything a transfer run measured, JSON-ready (transfer.json)."""
    return {"mode": result.mode, "code": code, "motions": result.motions, "robot_type": robot_type,
            "starts": starts, "seed": seed,
            "wall_s": round(wall_s, 1), "rows": [row.as_dict() for row in rows_], "runs": result.figures,
            "run_notes": {run_name(pair.case): pair.notes for pair in result.pairs if pair.notes},
            "errors": result.errors, "notes": result.notes, "plots": [str(path) for path in plots]}


# ---- plots ---------------------------------------------------------------------------------------------
def plot(pairs: list[Pair], rows_: list[Row], out_dir: Path) -> list[Path]:
    """PNGs: ours/real per figure; torso height of every stand-up start on both servers; the walks' paths."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    out_dir.mkdir(parents=True, exist_ok=True)
    written = []
    shown = [row for row in rows_ if not math.isnan(row.ratio)]
    if shown:
        fig, ax = plt.subplots(figsize=(8, 0.35 * len(shown) + 1.2))
        ax.barh([row.figure for row in shown], [row.ratio for row in shown], color="tab:orange")
        ax.axvline(1.0, color="black", linewidth=1)
        ax.invert_yaxis()
        ax.set_xlabel("ours / real")
        ax.set_title("transfer: our simulator against rcssserver3d 0.7.3")
        fig.tight_layout()
        written.append(out_dir / "transfer_ratios.png")
        fig.savefig(written[-1], dpi=110)
        plt.close(fig)
    standups = [pair for pair in pairs if pair.case.name in STANDUP_CASES]
    if standups:
        fig, axes = plt.subplots(1, len(STANDUP_CASES), figsize=(5.5 * len(STANDUP_CASES), 4), sharey=True)
        for ax, case in zip(axes, STANDUP_CASES):
            for pair in (p for p in standups if p.case.name == case):
                for run, style, colour in ((pair.real, "-", "tab:blue"), (pair.ours, "--", "tab:orange")):
                    times = [i * CYCLE_S for i, t in enumerate(run.truths) if t is not None]
                    heights = [t.torso_m[2] for t in run.truths if t is not None]
                    ax.plot(times, heights, style, color=colour, linewidth=0.8, alpha=0.7)
            ax.axhline(0.30, color="grey", linewidth=0.8)
            ax.set_title(f"{case} (lies on its {LIES_ON[case]}): torso height\n(real solid, ours dashed)")
            ax.set_xlabel("time since the skill phase began [s]")
        axes[0].set_ylabel("torso centre z [m]")
        fig.tight_layout()
        written.append(out_dir / "transfer_standups.png")
        fig.savefig(written[-1], dpi=110)
        plt.close(fig)
    walks = [pair for pair in pairs if pair.case.name in (*WALK_DIRECTIONS, *(c.name for c in WALK_20M_CASES))]
    if walks:
        fig, ax = plt.subplots(figsize=(9, 6))
        for pair in walks:
            for run, style, colour in ((pair.real, "-", "tab:blue"), (pair.ours, "--", "tab:orange")):
                xs = [t.torso_m[0] for t in run.truths if t is not None]
                ys = [t.torso_m[1] for t in run.truths if t is not None]
                ax.plot(xs, ys, style, color=colour, linewidth=1)
            start = next((t for t in pair.real.truths if t is not None), None)
            if start is not None:
                ax.annotate(pair.case.name, start.torso_m[:2], fontsize=8)
        ax.set_aspect("equal")
        ax.set_xlabel("x [m]")
        ax.set_ylabel("y [m]")
        ax.set_title("walk paths (real solid, ours dashed)")
        fig.tight_layout()
        written.append(out_dir / "transfer_walks.png")
        fig.savefig(written[-1], dpi=110)
        plt.close(fig)
    return written
