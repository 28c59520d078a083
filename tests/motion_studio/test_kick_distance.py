"""The kick-distance sweep (motion_studio.realserver.kick_distance) on our simulator: kicks measured per stretch,
kept in the rows file one by one so a rerun measures only what is missing, the table built from the means, and
written into a dynamic elements file that loads back to it."""

from __future__ import annotations

import json
import shutil

import pytest

from agent.motion import load_dynamic_params
from agent.motion.dynamic import DEFAULT_PARAMS_PATH
from motion_studio.realserver import kick_distance


def test_an_ours_only_sweep_keeps_every_kick_and_a_rerun_measures_nothing_again(tmp_path, capsys):
    # 1 cm beyond the spot: both servers' kick is in its steady regime there; the spot itself lies 1-2 mm from
    # the boundary between the kick's two regimes (sim.physics_params, "Joints give").
    args = ["--ours-only", "--stretches", "1,2.25", "--offsets-cm", "1", "--out", str(tmp_path)]
    assert kick_distance.main(args) == 0
    rows = json.loads((tmp_path / "rows.json").read_text())
    assert sorted((r["stretch"], r["motion"]) for r in rows) == [(1.0, "kick"), (1.0, "kick_left"),
                                                                 (2.25, "kick"), (2.25, "kick_left")]
    by_stretch = {s: [r["distance_m"] for r in rows if r["stretch"] == s] for s in (1.0, 2.25)}
    assert min(by_stretch[1.0]) > max(by_stretch[2.25]) + 1.0  # the slower strike: a shorter kick
    assert (tmp_path / "kick_distance.png").stat().st_size > 10_000
    capsys.readouterr()
    assert kick_distance.main(args) == 0
    assert json.loads((tmp_path / "rows.json").read_text()) == rows
    assert "stretch 1 kick" not in capsys.readouterr().out  # nothing played again


def test_the_table_keeps_only_stretches_that_reach_beyond_the_slower_ones():
    per_stretch = {3.0: {"mean_m": 0.8}, 2.5: {"mean_m": 1.4}, 2.0: {"mean_m": 1.2}, 1.5: {"mean_m": 3.0},
                   1.0: {"mean_m": 4.1}}
    table = kick_distance.table_from(per_stretch, "test")
    assert table.stretch == (3.0, 2.5, 1.5, 1.0)
    assert table.distance_points_m == (0.8, 1.4, 3.0, 4.1)
    with pytest.raises(ValueError, match="no kicks measured"):
        kick_distance.table_from({}, "test")


def test_a_written_table_loads_back_and_the_other_sections_stay(tmp_path):
    path = tmp_path / "dynamic_elements.toml"
    shutil.copy(DEFAULT_PARAMS_PATH, path)
    before = load_dynamic_params(path)
    table = kick_distance.table_from({2.0: {"mean_m": 2.2}, 1.0: {"mean_m": 4.0}}, "written by a test")
    kick_distance.write_table(table, path)
    after = load_dynamic_params(path)
    assert after.kick_distance == table
    assert (after.walk_lean, after.slowdown, after.turn_gain) == (before.walk_lean, before.slowdown, before.turn_gain)
    assert path.read_text().startswith(DEFAULT_PARAMS_PATH.read_text().split("[walk_lean]")[0])


@pytest.mark.parametrize(("args", "words"), [
    (["--stretches", "1,fast"], "--stretches / --offsets-cm take comma-separated numbers"),
    (["--stretches", "0.5"], "every stretch must be >= 1"),
])
def test_bad_arguments_are_one_line(tmp_path, capsys, args, words):
    assert kick_distance.main(["--ours-only", "--out", str(tmp_path), *args]) == 2
    err = capsys.readouterr().err
    assert words in err and len(err.strip().splitlines()) == 1


def test_a_corrupt_rows_file_is_named_and_kept(tmp_path, capsys):
    rows = tmp_path / "rows.json"
    rows.write_text('[{"stretch": 1.0')
    assert kick_distance.main(["--ours-only", "--out", str(tmp_path), "--stretches", "1"]) == 2
    err = capsys.readouterr().err
    assert str(rows) in err and len(err.strip().splitlines()) == 1
    assert rows.read_text() == '[{"stretch": 1.0'  # nothing lost
