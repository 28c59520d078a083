"""Match results are keyed by their settings: a rerun with other settings never shows the old results."""

from __future__ import annotations

import json
import subprocess
import sys

import pytest

from motion_studio.match_settings import SETTINGS_FILE, MatchFolderError, MatchSettings, prepare_folder

CLI = [sys.executable, "-m", "motion_studio"]


def settings(**changes) -> MatchSettings:
    values = dict(players_per_team=3, duration_s=600.0, team_left="Left", team_right="Right", log=True,
                  robot_types=(0, 2, 4), kick_off_wait_s=3.0)
    return MatchSettings(**{**values, **changes})


def test_same_settings_resume_and_other_settings_are_refused_naming_the_option(tmp_path):
    prepare_folder(tmp_path, settings(), resume=True)
    (tmp_path / "results.jsonl").write_text('{"match_id": "match-0"}\n')
    prepare_folder(tmp_path, settings(), resume=True)
    assert (tmp_path / "results.jsonl").exists()  # same settings: the finished match is kept
    with pytest.raises(MatchFolderError, match=r"--duration 600.0 -> 10.0"):
        prepare_folder(tmp_path, settings(duration_s=10.0), resume=True)
    with pytest.raises(MatchFolderError, match=r"--players 3 -> 1"):
        prepare_folder(tmp_path, settings(players_per_team=1), resume=True)
    assert (tmp_path / "results.jsonl").exists()  # refused: nothing was thrown away
    prepare_folder(tmp_path, settings(duration_s=10.0), resume=False)
    assert not (tmp_path / "results.jsonl").exists()
    assert json.loads((tmp_path / SETTINGS_FILE).read_text())["duration_s"] == 10.0


def test_results_of_unrecorded_settings_are_not_resumed(tmp_path):
    (tmp_path / "results.jsonl").write_text('{"match_id": "match-0"}\n')
    with pytest.raises(MatchFolderError, match="unrecorded settings"):
        prepare_folder(tmp_path, settings(), resume=True)


def test_match_command_refuses_a_changed_duration_in_one_line(tmp_path):
    first = subprocess.run(CLI + ["match", "--players", "1", "--duration", "0.5", "--no-log", "--out", str(tmp_path)],
                           capture_output=True, text=True, timeout=300)
    assert first.returncode == 0, first.stderr
    second = subprocess.run(CLI + ["match", "--players", "1", "--duration", "1", "--no-log", "--out", str(tmp_path)],
                            capture_output=True, text=True, timeout=300)
    assert second.returncode == 2
    assert second.stderr.strip().count("\n") == 0 and "--duration 0.5 -> 1.0" in second.stderr
    assert "match-0" not in second.stdout  # the old result is not shown as if it had been played
