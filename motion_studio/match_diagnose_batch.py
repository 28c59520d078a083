"""Watched matches over many seeds: per-match means of where the on-ball time goes, goals and falls, checkpointed.

Why: one watched match (``motion_studio.match_diagnose``) says where its 120 s went, but a team change moves
these figures by less than one match's noise (3 v 3 against robots that only stand: 0-4 goals a match), so
each earlier judgement of a change took 16 seeds and a throw-away script to add them up. Here each finished
match is one JSON line in ``<out>/diagnoses.jsonl`` (``sim.match_batch``: a rerun skips the seeds already
there, so a crash loses no finished match), and the command prints the per-match means and draws them
(``<out>/on_ball.png``).

Run::

    python -m motion_studio.match_diagnose --players 3 --right standing --matches 16 --workers 2 --out out/diag
"""

from __future__ import annotations

import collections
import logging
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

from tqdm import tqdm

from motion_studio.match_diagnose import ZONE_NAMES, Diagnosis, diagnose
from sim.match import AgentFactory, MatchConfig
from sim.match_batch import batch_configs, finished_ids, run_batch

logger = logging.getLogger(__name__)

CHECKPOINT_NAME = "diagnoses.jsonl"
PLOT_NAME = "on_ball.png"
#: Joins zone and activity in a JSON key ("0-10 m|push"); neither a zone name nor an activity contains it.
KEY_SEPARATOR = "|"
SIDES = ("left", "right")


def summary(result: Diagnosis, config: MatchConfig) -> dict[str, Any]:
    """One watched match as a JSON-able row (the checkpoint's line)."""
    falls = collections.Counter(fall.team for fall in result.falls)
    return {
        "match_id": config.match_id, "seed": config.seed, "score": list(result.score),
        "game_time_s": round(result.game_time_s, 2), "robots": result.robots,
        "falls": {side: falls.get(side, 0) for side in SIDES},
        "fall_causes": [[fall.team, *fall.cause, fall.contact] for fall in result.falls],
        "touches": result.touches, "contacts": result.contacts,
        "on_ball_s": {side: {f"{zone}{KEY_SEPARATOR}{activity}": round(seconds, 2)
                             for (zone, activity), seconds in result.on_ball_s.get(side, {}).items()}
                      for side in SIDES},
        "play_modes_s": {mode: round(seconds, 2) for mode, seconds in result.play_modes_s.items()},
    }


def diagnose_one(config: MatchConfig, agents_of: AgentFactory) -> dict[str, Any]:
    """A batch's ``run`` (``sim.match_batch.run_batch``): one watched match; its failure becomes a result row."""
    try:
        return summary(diagnose(config, agents_of), config)
    except Exception as error:  # the batch goes on; the reason is kept in the checkpoint
        logger.exception("watched match %s failed", config.match_id)
        return {"match_id": config.match_id, "seed": config.seed, "error": f"{type(error).__name__}: {error}"}


@dataclass(frozen=True)
class BatchFigures:
    """Per-match means over the batch's matches that ran (rows with an ``error`` are counted apart)."""

    matches: int
    failed: int
    goals: tuple[float, float]
    """Left, right."""
    falls: tuple[float, float]
    on_ball_s: dict[str, dict[tuple[str, str], float]]
    """Side -> (zone, activity) -> mean seconds per match."""
    play_modes_s: dict[str, float]
    scores: list[tuple[int, int, int]]
    """(seed, left goals, right goals) per match, by seed."""

    def activity_rows(self, side: str) -> list[tuple[str, float]]:
        """(activity, mean seconds per match over every zone) of one side, longest first."""
        totals: collections.Counter[str] = collections.Counter()
        for (_, activity), seconds in self.on_ball_s.get(side, {}).items():
            totals[activity] += seconds
        return totals.most_common()


def aggregate(rows: list[dict[str, Any]]) -> BatchFigures:
    """The per-match means of checkpoint rows (``summary``); rows with an ``error`` only count as failed."""
    ran = [row for row in rows if "error" not in row]
    n = max(1, len(ran))
    on_ball: dict[str, collections.Counter[tuple[str, str]]] = {side: collections.Counter() for side in SIDES}
    modes: collections.Counter[str] = collections.Counter()
    for row in ran:
        for side in SIDES:
            for key, seconds in row["on_ball_s"].get(side, {}).items():
                zone, activity = key.split(KEY_SEPARATOR, 1)
                on_ball[side][(zone, activity)] += seconds / n
        for mode, seconds in row["play_modes_s"].items():
            modes[mode] += seconds / n
    return BatchFigures(
        matches=len(ran), failed=len(rows) - len(ran),
        goals=(sum(r["score"][0] for r in ran) / n, sum(r["score"][1] for r in ran) / n),
        falls=(sum(r["falls"]["left"] for r in ran) / n, sum(r["falls"]["right"] for r in ran) / n),
        on_ball_s={side: dict(counter) for side, counter in on_ball.items() if counter},
        play_modes_s=dict(modes.most_common()),
        scores=sorted((r["seed"], r["score"][0], r["score"][1]) for r in ran))


def report(figures: BatchFigures, kinds: tuple[str, str], rows: int = 12) -> str:
    """The batch's table: goals and falls per match, play modes, each side's on-ball time by activity."""
    lines = [f"{figures.matches} matches" + (f" ({figures.failed} failed: see the checkpoint)" if figures.failed else "")
             + f"; per match: goals {figures.goals[0]:.2f} : {figures.goals[1]:.2f}, "
             f"falls {figures.falls[0]:.2f} / {figures.falls[1]:.2f}",
             "scores by seed: " + ", ".join(f"{seed} {left}:{right}" for seed, left, right in figures.scores),
             "play modes per match [s]: " + ", ".join(f"{mode} {s:.1f}" for mode, s in figures.play_modes_s.items())]
    for side, kind in zip(SIDES, kinds):
        activities = figures.activity_rows(side)
        if not activities:
            continue
        total = sum(s for _, s in activities)
        lines.append(f"{side} ({kind}) on-ball time in PlayOn per match, {total:.1f} s, by activity (all zones):")
        lines += [f"  {activity:22s} {seconds:6.1f} s  {100 * seconds / total:4.0f} %"
                  for activity, seconds in activities[:rows]]
    return "\n".join(lines)


def plot(figures: BatchFigures, kinds: tuple[str, str], path: Path, rows: int = 12) -> Path:
    """Horizontal bars per side: mean on-ball seconds per match by activity, stacked by ball zone."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    sides = [(side, kind) for side, kind in zip(SIDES, kinds) if figures.activity_rows(side)]
    fig, axes = plt.subplots(1, max(1, len(sides)), figsize=(7 * max(1, len(sides)), 5), squeeze=False)
    for ax, (side, kind) in zip(axes[0], sides):
        activities = [a for a, _ in figures.activity_rows(side)[:rows]][::-1]
        left = [0.0] * len(activities)
        for zone in ZONE_NAMES:
            widths = [figures.on_ball_s[side].get((zone, a), 0.0) for a in activities]
            ax.barh(activities, widths, left=left, label=zone)
            left = [x + w for x, w in zip(left, widths)]
        ax.set_xlabel("mean seconds per match (PlayOn, on-ball role)")
        ax.set_title(f"{side} ({kind}): goals {figures.goals[SIDES.index(side)]:.2f} a match, "
                     f"{figures.matches} matches")
        ax.legend(title="ball zone", fontsize=8)
    fig.tight_layout()
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=100)
    plt.close(fig)
    return path


def run(base: MatchConfig, agents_of: AgentFactory, matches: int, first_seed: int, out: Path,
        workers: int = 1) -> list[dict[str, Any]]:
    """Watch ``matches`` matches (seeds first_seed..) in ``workers`` processes; every row of the checkpoint
    ``out/diagnoses.jsonl`` afterwards (earlier runs' rows of these seeds are kept, not played again)."""
    configs = batch_configs(replace(base, match_id="diagnose"), matches, first_seed)
    wanted = {config.match_id for config in configs}
    with tqdm(total=len(configs), desc="watched matches", unit="match") as bar:
        bar.update(len(wanted & finished_ids(out / CHECKPOINT_NAME)))
        rows = run_batch(configs, agents_of, out / CHECKPOINT_NAME, workers, on_result=lambda _: bar.update(1),
                         run=diagnose_one)
    return [row for row in rows if row.get("match_id") in wanted]
