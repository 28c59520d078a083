"""Watched matches over seeds (``motion_studio.match_diagnose_batch``): per-match means, checkpoint and resume."""

from __future__ import annotations

import pytest

from motion_studio.match_diagnose import main
from motion_studio.match_diagnose_batch import CHECKPOINT_NAME, PLOT_NAME, aggregate, report
from sim.match_batch import read_results


def _row(seed: int, score: tuple[int, int], falls: int, push_s: float, turn_s: float) -> dict:
    return {"match_id": f"diagnose-{seed}", "seed": seed, "score": list(score), "game_time_s": 120.0, "robots": 6,
            "falls": {"left": falls, "right": 0}, "fall_causes": [], "touches": {}, "contacts": 0,
            "on_ball_s": {"left": {"0-10 m|push": push_s, "13 m-goal line|push": 1.0, "0-10 m|turn": turn_s},
                          "right": {}},
            "play_modes_s": {"PlayOn": 90.0, "KickOff_Right": 10.0 * score[0]}}


def test_the_means_are_per_match_and_a_failed_match_only_counts_as_failed():
    rows = [_row(0, (2, 0), 1, 30.0, 10.0), _row(1, (1, 0), 0, 20.0, 30.0),
            {"match_id": "diagnose-2", "seed": 2, "error": "RuntimeError: boom"}]
    figures = aggregate(rows)
    assert (figures.matches, figures.failed) == (2, 1)
    assert figures.goals == (1.5, 0.0) and figures.falls == (0.5, 0.0)
    assert figures.on_ball_s["left"][("0-10 m", "push")] == pytest.approx(25.0)
    assert figures.activity_rows("left") == [("push", pytest.approx(26.0)), ("turn", pytest.approx(20.0))]
    assert figures.activity_rows("right") == []
    assert figures.play_modes_s["KickOff_Right"] == pytest.approx(15.0)
    assert figures.scores == [(0, 2, 0), (1, 1, 0)]
    text = report(figures, ("ours", "standing"))
    assert "2 matches (1 failed" in text and "goals 1.50 : 0.00" in text and "0 2:0, 1 1:0" in text
    assert "left (ours) on-ball time in PlayOn per match, 46.0 s" in text and "right (standing)" not in text


def test_watched_matches_are_checkpointed_and_a_rerun_plays_only_the_missing_seeds(tmp_path, capsys):
    args = ["--players", "2", "--duration", "10", "--right", "standing", "--matches", "2", "--out", str(tmp_path)]
    assert main(args) == 0
    checkpoint = tmp_path / CHECKPOINT_NAME
    rows = read_results(checkpoint)
    assert sorted(row["seed"] for row in rows) == [0, 1]
    assert all(row["on_ball_s"]["left"] and not row["on_ball_s"]["right"] for row in rows)
    assert (tmp_path / PLOT_NAME).stat().st_size > 10_000
    assert "2 matches; per match: goals 0.00 : 0.00" in capsys.readouterr().out
    # a crash mid-write leaves a torn line; the rerun keeps the finished seeds and plays seed 2 only
    checkpoint.write_text(checkpoint.read_text() + '{"match_id": "diagnose-2", "se')
    assert main(args[:-3] + ["3", "--out", str(tmp_path)]) == 0
    assert sorted(row["seed"] for row in read_results(checkpoint)) == [0, 1, 2]   # the torn line skipped
    assert "3 matches" in capsys.readouterr().out


def test_matches_without_an_out_folder_is_a_one_line_error():
    with pytest.raises(SystemExit, match="--matches needs --out"):
        main(["--matches", "2"])
