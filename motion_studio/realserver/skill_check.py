"""Sim-to-real check of the shipped motions, case by case (``motion-studio real skills``): the same agent and
skill on the real rcssserver3d 0.7.3 and on our simulator, measured by ground truth, every figure side by side.

For each case a fresh real server (process.RealServer: sync mode, not real time) runs our ``agent.Agent`` with
``SkillBehavior`` over TCP; at the move cycle the monitor sends the case's trainer commands (cases.py); a full
state is requested every cycle (diffs round poses to 5 mm) and gives the torso pose and the ball. The same
session then runs on our simulator (skill_runs.run_sim). Motions come from a git revision (default HEAD), so
other people's unfinished files do not leak in. With a fixture folder each real run is also written as
``real_0.7.3_skill_<case>.jsonl.gz`` (tests/sim/test_real_skill_traces.py replays them).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import replace
from pathlib import Path

from motion_studio.realserver.cases import CASES, MotionSource, with_dribble_config
from motion_studio.realserver.fixtures import fixture_path, write_fixture
from motion_studio.realserver.skill_figures import figures, table
from motion_studio.realserver.skill_runs import run_real, run_sim

TOOL = "motion-studio real skills"


def check_skills(names: list[str], motions: MotionSource, scripts: Path, out: Path, fixture_dir: Path | None = None,
                 replay_sim: bool = False, report: Callable[[str], None] = lambda line: None,
                 robot_type: int = 0, dribble_config: Mapping[str, float] | None = None) -> dict:
    """Run ``names`` (cases.CASES) on both servers (this process inside netns.sh's namespace).

    Args:
        motions: the motions both servers' agents play.
        scripts: the real-server scripts folder; ``out``: server logs, monitor logs, rejected sense messages.
        fixture_dir: write each real trace there (``_simcmds`` suffix with ``replay_sim``).
        replay_sim: send the answers our agent gave on our simulator to the real server (the same joint
            commands on both: physics alone compared).
        report: called with each case's table (or why it was skipped).
        robot_type: the robot type (0-4) that plays every case, with its own motions.
        dribble_config: ``DribbleConfig`` fields for the dribble cases (``cases.with_dribble_config``).

    Returns:
        {"motions": revision, "robot_type": N, "dribble_config": overrides, case: {"real": figures, "sim":
        figures}} (JSON-ready).
    """
    out.mkdir(parents=True, exist_ok=True)
    results: dict = {"motions": motions.revision, "robot_type": robot_type, "dribble_config": dict(dribble_config or {})}
    available = motions.library(robot_type)
    for name in names:
        case = with_dribble_config(replace(CASES[name], robot_type=robot_type), dribble_config or {})
        reason = motions.unplayed(case, available)
        if reason is not None:
            report(f"{name}: skipped ({reason})")
            continue
        if replay_sim:  # physics alone: our agent's answers on our simulator, sent to both
            sim_run = run_sim(case, motions)
            real_run, lines = run_real(case, motions, scripts, out, script=sim_run.replies, tool=TOOL)
        else:
            real_run, lines = run_real(case, motions, scripts, out, tool=TOOL)
            sim_run = run_sim(case, motions)
        if fixture_dir is not None:
            suffix = (f"_type{robot_type}" if robot_type else "") + ("_simcmds" if replay_sim else "")
            write_fixture(lines, fixture_path(fixture_dir, name + suffix))
        real, sim = figures(real_run, case), figures(sim_run, case)
        results[name] = {"real": real, "sim": sim}
        report(table(case, real, sim))
    return results
