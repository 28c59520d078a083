"""motion-studio calibrate --spread: each skill trace replayed with its commands perturbed by the wire format's last
digit, and the share of those replays that end as the real run did."""

from __future__ import annotations

import random
import subprocess
import sys
from pathlib import Path

from agent.protocol.effectors import split_joint_commands
from motion_studio.calibration.sensitivity import outcome_spread, perturbed_replies, spread_table
from motion_studio.realserver.fixtures import read_fixture

FIXTURES = Path(__file__).parents[1] / "sim" / "fixtures"
TURN = FIXTURES / "real_0.7.3_skill_turn_left.jsonl.gz"
BACK_START1 = FIXTURES / "real_0.7.3_skill_standup_back_start1.jsonl.gz"


def test_perturbed_replies_move_only_joint_values_by_about_the_last_digit() -> None:
    trace = read_fixture(TURN)
    same = perturbed_replies(trace, 0.0, random.Random(0))
    varied = perturbed_replies(trace, 1e-4, random.Random(0))
    assert perturbed_replies(trace, 1e-4, random.Random(0)) == varied   # seeded
    changed = 0
    for index, reply in trace.replies.items():
        split = split_joint_commands(reply.decode())
        if split is None or not split[0]:
            assert same[index] == reply and varied[index] == reply   # scene, init, beam: as recorded
            continue
        names, values, syn = split
        for copy in (same, varied):
            got = split_joint_commands(copy[index].decode())
            assert got is not None and got[0] == names and got[2] == syn
        assert split_joint_commands(same[index].decode())[1] == values
        moved = [abs(a - b) for a, b in zip(split_joint_commands(varied[index].decode())[1], values)]
        assert max(moved) <= 6e-4   # 5 sd and the rounding to 4 decimals
        changed += sum(m > 0 for m in moved)
    assert changed > 1000


def test_unperturbed_replays_repeat_to_the_bit() -> None:
    trace = read_fixture(TURN)
    spread = outcome_spread(trace, replays=2, sd_rad_s=0.0)
    assert spread is not None and all(o == spread.ours for o in spread.perturbed)
    assert spread.kind in ("holds", "differs")


def test_a_mismatch_that_the_last_digit_undoes() -> None:
    """The real back stand-up's start 1 replayed open loop: ours falls back where the real robot stood, but with its
    commands moved by the wire format's last digit ours stands in every one of 3 replays: the mismatch is the
    recording's chance, not our physics' (calibrate's single replay counts it as different)."""
    spread = outcome_spread(read_fixture(BACK_START1), replays=3, seed=0)
    assert spread is not None
    assert spread.ours != spread.real
    assert spread.same_share == 1.0 and spread.kind == "holds"
    table = spread_table([spread])
    assert "fell/down!" in table and "holds 1, marginal 0, differs 0; expected to end as the real run: 1.0" in table


def test_the_command_prints_the_spread_resumes_and_refuses_mixing(tmp_path: Path) -> None:
    command = [sys.executable, "-m", "motion_studio", "calibrate", "--only", "skill_turn_left", "--spread", "1",
               "--out", str(tmp_path)]
    run = subprocess.run(command, capture_output=True, text=True, timeout=300)
    assert run.returncode == 0, run.stderr
    assert "skill_turn_left" in run.stdout and "unperturbed:" in run.stdout
    checkpoint = tmp_path / "spread.jsonl"
    assert len(checkpoint.read_text().splitlines()) == 1
    assert (tmp_path / "spread.png").stat().st_size > 5_000
    again = subprocess.run(command, capture_output=True, text=True, timeout=300)   # from the checkpoint
    assert again.returncode == 0 and again.stdout == run.stdout
    assert len(checkpoint.read_text().splitlines()) == 1
    refused = subprocess.run([sys.executable, "-m", "motion_studio", "calibrate", "--only", "skill_turn_left",
                              "--spread", "2", "--divergence"], capture_output=True, text=True, timeout=120)
    assert refused.returncode == 2 and "--spread" in refused.stderr
    assert refused.stderr.strip().count("\n") == 0
