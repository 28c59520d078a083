"""Match batches on Ray: a real local Ray instance runs the matches in its worker processes; the checkpoint
stays with the driver, results equal a run in this process, and an unreachable cluster fails fast."""

import os
import subprocess
import sys
from dataclasses import asdict

import pytest

from motion_studio.match_agents import make_idle_agent
from sim.match import MatchConfig, run_match
from sim.match_batch import batch_configs, run_batch
from sim.ray_executor import RayExecutor, RayUnavailable, check_reachable

pytest.importorskip("ray")


def worker_pid() -> int:
    return os.getpid()


@pytest.fixture(scope="module")
def executor():
    ray_executor = RayExecutor("local", num_cpus=2)
    yield ray_executor
    ray_executor.shutdown()


def test_a_batch_runs_in_ray_workers_and_matches_a_local_run(executor, tmp_path):
    assert executor.submit(worker_pid).result(timeout=120) != os.getpid()  # a Ray worker, not this process
    checkpoint = tmp_path / "results.jsonl"
    base = MatchConfig(players_per_team=1, duration_s=1.0, match_id="r")
    seen = []
    results = run_batch(batch_configs(base, 2), make_idle_agent, checkpoint, on_result=seen.append, executor=executor)
    assert sorted(r["match_id"] for r in results) == ["r-0", "r-1"]
    assert len(checkpoint.read_text().splitlines()) == 2 == len(seen)  # one line per match, written here
    local = asdict(run_match(batch_configs(base, 1)[0], make_idle_agent))
    remote = next(r for r in results if r["match_id"] == "r-0")
    for key in ("game_time_s", "score_left", "score_right", "falls", "final_play_mode", "agent_errors"):
        assert remote[key] == local[key], key
    # Resume: a second batch with one more match runs only that one.
    again = []
    run_batch(batch_configs(base, 3), make_idle_agent, checkpoint, on_result=again.append, executor=executor)
    assert [r["match_id"] for r in again] == ["r-2"]


def test_an_unreachable_cluster_fails_fast_with_its_address():
    with pytest.raises(RayUnavailable, match="127.0.0.1:1"):
        check_reachable("127.0.0.1:1", timeout_s=2.0)


def test_the_match_command_says_when_ray_is_unreachable(tmp_path):
    done = subprocess.run([sys.executable, "-m", "motion_studio", "match", "--ray", "ray://127.0.0.1:1",
                           "--out", str(tmp_path)], capture_output=True, text=True, timeout=120)
    assert done.returncode == 2
    assert "cannot reach the Ray cluster at 'ray://127.0.0.1:1'" in done.stderr
    assert "Traceback" not in done.stderr
    assert not (tmp_path / "results.jsonl").exists()
