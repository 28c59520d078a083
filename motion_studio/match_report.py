"""Runs `motion-studio match` batches with a progress bar and turns the results into a table and a plot."""

from __future__ import annotations

from dataclasses import asdict
from pathlib import Path
from typing import Any

from tqdm import tqdm

from motion_studio.match_agents import SideAgents
from motion_studio.match_settings import MatchSettings, prepare_folder
from sim.match import MatchConfig, run_match
from sim.match_batch import append_result, batch_configs, finished_ids, read_results, run_batch
from sim.ray_executor import RayExecutor

#: Agent worker processes of a single match (`sim.agent_processes`): with the engine's process, 3 processes
#: share the 2 cores of the project's machines; the agents are ~3/4 of a match's CPU (issue 15, "Speed").
DEFAULT_AGENT_PROCESSES = 2


def run_and_report(*, players: int, duration_s: float, matches: int, workers: int, seed: int, out: Path,
                   log: bool, team_left: str, team_right: str, resume: bool,
                   ray_address: str | None = None, left: str = "ours",
                   right: str = "ours", agent_processes: int | None = None) -> tuple[list[str], list[dict]]:
    """Play the matches (one with a live game-time bar, a batch with a per-match bar); return report lines.

    With ``ray_address`` the batch runs as Ray tasks (`sim.ray_executor`); the checkpoint stays here. A single
    match runs its agents in ``agent_processes`` worker processes (`sim.match.run_match`; None: 2); a batch
    hosts them in each match's process."""
    checkpoint = out / "results.jsonl"
    base = MatchConfig(team_left=team_left, team_right=team_right, players_per_team=players, duration_s=duration_s,
                       seed=seed, log_path=str(out / "match.log.gz") if log else None, match_id="match")
    # results are keyed by their settings: a resume with other settings is refused before anything is played
    prepare_folder(out, MatchSettings(players, duration_s, team_left, team_right, log, base.robot_types,
                                      base.kick_off_wait_s, left, right), resume)
    make_agent = SideAgents(left, right, team_left)
    configs = batch_configs(base, matches, seed)
    if ray_address is not None:
        executor = RayExecutor(ray_address, num_cpus=workers if workers > 1 else None)
        try:
            with tqdm(total=len(configs), desc=f"matches (Ray, {executor.cluster_cpus} CPUs)", unit="match") as bar:
                results = run_batch(configs, make_agent, checkpoint, on_result=lambda _: bar.update(1),
                                    executor=executor)
        finally:
            executor.shutdown()
    elif matches == 1 and workers <= 1:
        results = _single(configs[0], checkpoint, make_agent,
                          DEFAULT_AGENT_PROCESSES if agent_processes is None else agent_processes)
    else:
        with tqdm(total=len(configs), desc="matches", unit="match") as bar:
            results = run_batch(configs, make_agent, checkpoint, workers, on_result=lambda _: bar.update(1))
    plot = plot_results(results, out / "results.png")
    return summary_lines(results) + [f"results: {checkpoint}", f"plot: {plot}"], results


def _single(config: MatchConfig, checkpoint: Path, make_agent: SideAgents,
            agent_processes: int = 0) -> list[dict[str, Any]]:
    """One match run from this process (its agents in ``agent_processes`` workers), so the bar can follow its
    game time; checkpointed like a batch."""
    if config.match_id not in finished_ids(checkpoint):
        with tqdm(total=round(config.duration_s), desc="game time", unit="s") as bar:
            def progress(game_time_s: float, _duration_s: float) -> None:
                bar.n = min(round(game_time_s), bar.total)
                bar.refresh()

            append_result(checkpoint, asdict(run_match(config, make_agent, progress, agent_processes)))
    return read_results(checkpoint)


def summary_lines(results: list[dict[str, Any]]) -> list[str]:
    lines = ["match        score   falls L/R   possession L/R   game_s   wall_s   agent_errors"]
    for r in results:
        lines.append(f"{r['match_id']:<12} {r['score_left']}:{r['score_right']:<5} "
                     f"{r['falls']['left']:>4}/{r['falls']['right']:<6} "
                     f"{r['possession']['left']:>6.2f}/{r['possession']['right']:<8.2f} "
                     f"{r['game_time_s']:>7.1f} {r['wall_s']:>8.1f} {r['agent_errors']:>6}"
                     + (f"   ERROR {r['error']}" if r.get("error") else ""))
    return lines


def plot_results(results: list[dict[str, Any]], path: Path) -> Path:
    """Goals and falls per match, left vs right, as a PNG."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    ids = [r["match_id"] for r in results]
    fig, axes = plt.subplots(1, 2, figsize=(9, 3.5))
    for ax, key, title in ((axes[0], ("score_left", "score_right"), "goals"),
                           (axes[1], None, "falls")):
        left = [r[key[0]] for r in results] if key else [r["falls"]["left"] for r in results]
        right = [r[key[1]] for r in results] if key else [r["falls"]["right"] for r in results]
        x = range(len(ids))
        ax.bar([i - 0.2 for i in x], left, 0.4, label="left")
        ax.bar([i + 0.2 for i in x], right, 0.4, label="right")
        ax.set_xticks(list(x), ids, rotation=30, ha="right", fontsize=8)
        ax.set_title(title)
        ax.legend()
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)
    return path
