"""Match runner: kick-off as a trainer, results, a crashing agent never ends the match, batches resume."""

import json

import pytest

from motion_studio.match_agents import make_idle_agent as make_agent
from sim.match import MatchConfig, run_match
from sim.match_batch import batch_configs, finished_ids, run_batch
from tests.sim.crashing_agent import CrashingAgent


def test_match_kicks_off_and_reports_results(tmp_path):
    log = tmp_path / "m.log"
    result = run_match(MatchConfig(players_per_team=2, duration_s=4.0, log_path=str(log)), make_agent)
    assert result.final_play_mode in {"KickOff_Left", "KickOff_Right", "PlayOn"}  # the trainer kicked off
    assert result.game_time_s == pytest.approx(4.0, abs=0.03)
    assert result.falls == {"left": 0, "right": 0}  # standing agents do not fall
    assert result.agent_errors == 0
    lines = log.read_text().splitlines()
    assert lines[0].startswith("((FieldLength 30)") and "(RSG 0 1)" in lines[0]
    assert any("matLeft" in line for line in lines) and any("matRight" in line for line in lines)


def test_a_crashing_agent_never_ends_the_match():
    result = run_match(MatchConfig(players_per_team=1, duration_s=2.0), CrashingAgent)
    assert result.game_time_s == pytest.approx(2.0, abs=0.03)
    assert result.agent_errors >= 10


def test_batch_checkpoints_each_match_and_resumes(tmp_path):
    checkpoint = tmp_path / "results.jsonl"
    base = MatchConfig(players_per_team=1, duration_s=1.0, match_id="t")
    run_batch(batch_configs(base, 2), make_agent, checkpoint)
    assert finished_ids(checkpoint) == {"t-0", "t-1"}
    with checkpoint.open("a") as handle:
        handle.write('{"match_id": "t-9", "sco')  # a crash mid-write leaves a torn line
    ran = []
    results = run_batch(batch_configs(base, 3), make_agent, checkpoint, on_result=ran.append)
    assert [r["match_id"] for r in ran] == ["t-2"]  # only the missing match ran
    assert {r["match_id"] for r in results} == {"t-0", "t-1", "t-2"}
    assert all(json.loads(line)["match_id"] for line in checkpoint.read_text().splitlines()[:2])
