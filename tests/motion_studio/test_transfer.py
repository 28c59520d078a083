"""``motion-studio transfer`` without the real server (it never runs in tests): the recorded real runs of
tests/sim/fixtures replayed on our MuJoCo world, the ours/real rows and table, the stood-up rule, a corrupt
fixture named by file and line, the command's help and one-line errors."""

from __future__ import annotations

import gzip
import json
import math
import shutil
from pathlib import Path

import pytest
from typer.testing import CliRunner

from motion_studio.cli import _register_commands, app
from motion_studio.realserver import transfer, transfer_report
from motion_studio.realserver.cases import CASES, FALL_SCRIPT_CYCLES
from motion_studio.realserver.errors import FixtureError
from motion_studio.realserver.fixtures import fixture_path, read_fixture
from motion_studio.realserver.measures import stood_index
from motion_studio.realserver.skill_figures import figures
from motion_studio.realserver.skill_runs import Run
from motion_studio.scenarios import Truth

FIXTURES = Path(__file__).parents[1] / "sim" / "fixtures"


def _invoke(*args: str, env: dict[str, str] | None = None):
    _register_commands()
    return CliRunner().invoke(app, ["transfer", *args], env=env)


def _replayed(tmp_path: Path, *names: str) -> transfer.Transfer:
    cases = transfer.plan(1, 0, list(names))
    return transfer.measure("replay", cases, motions_revision="HEAD", fixtures=FIXTURES, scratch=tmp_path)


# ---- rows and ratios on recorded fixtures -----------------------------------------------------------------------
def test_turn_rows_compare_the_recorded_real_turn_with_ours_replaying_it(tmp_path: Path) -> None:
    result = _replayed(tmp_path, "turn_left", "walk_backward", "stand")
    assert result.errors == []
    rows = {row.figure: row for row in transfer_report.rows(result.pairs, result.figures, starts=1)}
    turn = rows["turn_left: turn per motion [deg]"]
    # the recorded real run: 16 turn motions (our agent fed the recorded messages again gives them all), 607 deg
    assert result.figures["turn_left"]["real"]["turn motions"] == 16
    assert turn.real == pytest.approx(37.9, abs=0.5)
    assert turn.ratio == pytest.approx(turn.ours / turn.real)
    assert 0.9 < turn.ratio < 1.15  # measured 1.04 (ours turns 39.5 deg a motion open loop)
    walk = rows["walk backward: speed over 10 s [m/s]"]
    assert walk.real == pytest.approx(0.276, abs=0.005)  # 2.76 m backwards in 10 s on the real server
    assert 0.9 < walk.ratio < 1.15
    assert rows["stand: torso height [m]"].ratio == pytest.approx(1.0, abs=0.01)
    assert math.isnan(rows["kick: distance, ball on its spot [m]"].ratio)  # not in this run
    table = transfer_report.table(list(rows.values()), "title")
    line = next(text for text in table.splitlines() if text.startswith("turn_left: turn per motion"))
    assert f"{turn.ratio:.2f}" in line and f"{turn.real:.1f}" in line


def test_ball_and_dribble_rows_compare_the_recorded_real_runs_with_ours(tmp_path: Path) -> None:
    # Recorded 2026-11-28 at f75c5fb (motion-studio real skills CASE --fixture): KickToward from the kick-off spot,
    # WalkToBall beside the ball, the 10 m dribble. Replayed open loop, ours kicks from the kick-off spot (real
    # 4.25 m, ours 3.91) and leaves the ball beside the feet where it lies; the dribble's replay loses the ball after
    # its first touches (closed-loop commands), so only its real figures are pinned here.
    result = _replayed(tmp_path, "kick_lineup_50cm", "walk_to_ball_beside", "dribble")
    assert result.errors == []
    rows = {row.figure: row for row in transfer_report.rows(result.pairs, result.figures, starts=1)}
    lineup = rows["KickToward from 50 cm behind the ball: ball moved [m]"]
    assert lineup.real == pytest.approx(4.25, abs=0.01)
    assert 0.85 < lineup.ratio < 1.1   # measured 0.92
    beside = rows["WalkToBall, ball beside the feet: ball moved [m]"]
    assert beside.real < 0.02 and beside.ours < 0.02
    dribble = rows["dribble 10 m straight: speed [m/s]"]
    assert dribble.real == pytest.approx(0.311, abs=0.005)   # 10 m in 32.2 s on the real server
    keep = rows["dribble 10 m straight: ball within 0.5 m of the torso [share]"]
    assert keep.real == pytest.approx(0.478, abs=0.01)
    assert math.isnan(rows["KickToward from 45 cm behind the ball: ball moved [m]"].real)   # not in this run


def test_orbit_rows_give_the_recorded_real_orbit_and_its_centre(tmp_path: Path) -> None:
    # Recorded 2026-11-29 (motion-studio real skills orbit_left orbit_right --fixture): 5 s of each orbit from standing
    # on the real server. Its torso circles a point 0.54-0.56 m ahead of the start, on the line ahead (the gait is
    # authored for 0.45 m: 0.06 m / 7.6 deg a stride). Ours replays the real commands open loop (shorter turn).
    result = _replayed(tmp_path, "orbit_left", "orbit_right")
    assert result.errors == []
    rows = {row.figure: row for row in transfer_report.rows(result.pairs, result.figures, starts=1)}
    assert rows["orbit_left: turned in 5 s [deg]"].real == pytest.approx(108.8, abs=0.2)
    assert rows["orbit_right: turned in 5 s [deg]"].real == pytest.approx(-106.0, abs=0.2)
    for side in ("left", "right"):
        real = result.figures[f"orbit_{side}"]["real"]
        assert real["orbit centre ahead [m]"] == pytest.approx(0.55, abs=0.015)
        assert abs(real["orbit centre left [m]"]) < 0.04
        assert real["orbit radius [m]"] == pytest.approx(0.53, abs=0.015)
        assert rows[f"orbit_{side}: turned in 5 s [deg]"].ours * (1 if side == "left" else -1) > 60.0


def test_a_circle_fit_finds_the_centre_and_radius_of_points_on_an_arc() -> None:
    from motion_studio.realserver.skill_figures import circle_fit

    arc = [(1.0 + 0.5 * math.cos(a / 10.0), -2.0 + 0.5 * math.sin(a / 10.0)) for a in range(20)]
    (x, y), radius = circle_fit(arc)
    assert (x, y, radius) == (pytest.approx(1.0), pytest.approx(-2.0), pytest.approx(0.5))
    assert circle_fit([(0.0, 0.0), (1.0, 1.0), (2.0, 2.0)]) is None   # on a line
    assert circle_fit([(0.0, 0.0), (1.0, 1.0)]) is None


def test_cases_left_out_of_a_selection_read_not_run_and_missing_fixtures_no_fixture() -> None:
    """A replay of some cases (``--case``) notes the others "not run", not "no fixture" (it said "no fixture" of
    every case it was not asked for); a selected case without runs keeps the caller's note."""
    rows = {row.figure: row for row in transfer_report.rows([], {}, starts=1, absent="no fixture",
                                                              selected=["kick", "standup_side"])}
    assert rows["kick: distance, ball on its spot [m]"].note == "no fixture"
    assert rows["turn_left: turn per motion [deg]"].note == "not run"
    assert rows["stand-up lying on its side (case standup_side): stood 1 s > 0.30 m"].note == "no fixture"
    assert rows["stand-up lying on its back (case standup_front): stood 1 s > 0.30 m"].note == "not run"
    assert rows["20 m forward walk: falls"].note == "not run"
    unselected = {row.figure: row.note for row in transfer_report.rows([], {}, starts=1, absent="no fixture")}
    assert set(unselected.values()) == {"no fixture"}


def test_counts_compare_as_fractions() -> None:
    row = transfer_report.Row("stood", 8, 9, real_of=10, ours_of=10)
    assert row.ratio == pytest.approx(9 / 8)
    assert "8/10" in transfer_report.table([row], "t")


# ---- the stood-up rule -----------------------------------------------------------------------------------------
def _truths(heights_m: list[float], up_z: list[float]) -> list[Truth | None]:
    return [Truth(i * 0.02, (0.0, 0.0, z), u, 0.0, (0.0, 8.0, 0.04), False)
            for i, (z, u) in enumerate(zip(heights_m, up_z))]


def test_an_upright_torso_below_030_m_has_not_stood() -> None:
    # fallen flat for the fall script, then sitting upright (up axis z = 1) at 0.28 m for 5 s
    lying = FALL_SCRIPT_CYCLES + 20
    run = Run("real", _truths([0.1] * lying + [0.28] * 250, [0.0] * lying + [1.0] * 250))
    assert stood_index(run.truths) is None
    assert transfer.standup_outcome(run).outcome == "lying"
    # the per-case check uses the same rule (it used to report this robot as stood up: up axis z > 0.9)
    assert math.isnan(figures(run, CASES["standup_front"])["stood up after [s]"])


def test_stood_needs_a_full_second_above_030_m() -> None:
    lying = FALL_SCRIPT_CYCLES + 20
    short = _truths([0.1] * lying + [0.33] * 49 + [0.2] * 50, [0.0] * lying + [1.0] * 99)
    assert transfer.standup_outcome(Run("ours", short)).outcome == "lying"
    stood = _truths([0.1] * lying + [0.33] * 50, [0.0] * lying + [1.0] * 50)
    outcome = transfer.standup_outcome(Run("ours", stood))
    assert outcome.outcome == "stood"
    assert outcome.time_s == pytest.approx(20 * 0.02)  # from the end of the fall script
    assert transfer.standup_outcome(Run("ours", _truths([0.38] * 300, [1.0] * 300))).outcome == "no fall"


def test_the_real_robot_sitting_up_from_its_front_has_not_stood() -> None:
    # recorded (motions 66e41c9, lying start 5): after the fall the real torso comes upright (up-axis z 1.0) but
    # its centre never gets above 0.28 m. (The start-0 recording of the older motions did this too; since the
    # back stand-up was retuned the real robot stands from start 0, in 5.6 s.)
    fixture = read_fixture(fixture_path(FIXTURES, "standup_front_start5"))
    truths = [fixture.truth.get(i) for i in range(fixture.skill_cycle + 1, len(fixture.received) + 1)]
    lying = [t for t in truths[FALL_SCRIPT_CYCLES:] if t is not None]
    assert max(t.up_z for t in lying) > 0.85
    assert max(t.torso_m[2] for t in lying) < 0.30
    assert transfer.standup_outcome(Run("real", truths)).outcome == "lying"


# ---- fixtures that cannot be used ----------------------------------------------------------------------------
def _corrupt_copy(folder: Path, name: str, line: int) -> Path:
    rows = gzip.open(fixture_path(FIXTURES, name), "rt").read().splitlines()
    rows[line - 1] = rows[line - 1][: len(rows[line - 1]) // 2]  # cut mid-object
    path = fixture_path(folder, name)
    with gzip.open(path, "wt") as handle:
        handle.write("\n".join(rows) + "\n")
    return path


@pytest.mark.parametrize("start", [0, 2, 5])
def test_on_ours_the_robot_lying_on_its_back_stands_up_at_once(start: int) -> None:
    # Issue 12: the real robot lying on its back (case standup_front) slides its buttocks 0.30-0.37 m forward
    # while it sits up and crouches; with mu 2 on every body part ours got 0.17 m at most, fell back and never
    # stood (0 of 10 starts). With body_friction 0.95 (feet 2) ours stands at the first attempt (~2.5 s after
    # the fall script, real median 2.54 s) in 10 of 10 starts of seeds 0 and 1.
    from motion_studio.realserver.cases import MotionSource
    from motion_studio.realserver.skill_runs import run_sim

    case = next(case for case in transfer.plan(start + 1, 0, ["standup_front"]) if case.start == start)
    outcome = transfer.standup_outcome(run_sim(case, MotionSource()))
    assert outcome.outcome == "stood" and outcome.time_s < 3.0


def test_a_corrupt_fixture_is_named_with_its_line(tmp_path: Path) -> None:
    path = _corrupt_copy(tmp_path, "stand", 5)
    with pytest.raises(FixtureError) as caught:
        read_fixture(path)
    assert caught.value.path == path and caught.value.line == 5
    assert str(caught.value).startswith(f"{path}:5: not JSON")
    (tmp_path / "plain.jsonl.gz").write_text("not gzip\n")
    with pytest.raises(FixtureError, match=r"plain.jsonl.gz:1: unreadable"):
        read_fixture(tmp_path / "plain.jsonl.gz")
    with pytest.raises(FixtureError, match="no such fixture file"):
        read_fixture(tmp_path / "missing.jsonl.gz")


def test_transfer_names_the_corrupt_fixture_and_goes_on(tmp_path: Path) -> None:
    fixtures = tmp_path / "fixtures"
    fixtures.mkdir()
    shutil.copy(fixture_path(FIXTURES, "turn_right"), fixtures)
    bad = _corrupt_copy(fixtures, "stand", 3)
    out = tmp_path / "out"
    # SS_PREFIX with no server: the command replays the fixtures and says how to build the real server
    result = _invoke("--fixtures", str(fixtures), "--out", str(out), "--case", "stand", "--case", "turn_right",
                     "--case", "kick", env={"SS_PREFIX": str(tmp_path / "nothing")})
    assert result.exit_code == 0, result.output
    assert f"transfer: {bad}:3: not JSON" in result.output
    assert f"{fixture_path(fixtures, 'kick')}: no such fixture file" in result.output
    assert "turn_right: turn per motion [deg]" in result.output
    assert "bash " in result.output and "real-server/build.sh <git dir of BerlinUnited/SimSpark-SPL>" in result.output
    summary = json.loads((out / "transfer.json").read_text())
    assert summary["mode"] == "replay"
    assert list(summary["runs"]) == ["turn_right"]
    assert len(summary["errors"]) == 2
    row = next(r for r in summary["rows"] if r["figure"].startswith("turn_right"))
    assert row["ratio"] == pytest.approx(row["ours"] / row["real"])
    assert (out / "transfer_ratios.png").stat().st_size > 10_000


# ---- robot types ----------------------------------------------------------------------------------------------
def test_a_robot_type_s_runs_are_its_fixtures_and_its_lying_starts_are_type_0_s() -> None:
    cases = {transfer.run_name(case): case for case in transfer.plan(3, 7, ["kick_strong", "standup_front"], 2)}
    assert set(cases) == {"kick_strong", "standup_front", "standup_front_start1", "standup_front_start2"}
    assert {case.robot_type for case in cases.values()} == {2}
    assert transfer.fixture_name(cases["kick_strong"]) == "kick_strong_type2"   # as real skills --type 2 names it
    assert transfer.fixture_name(cases["standup_front_start2"]) == "standup_front_type2_start2"
    type0 = {transfer.run_name(case): case for case in transfer.plan(3, 7, ["standup_front"])}
    assert transfer.fixture_name(type0["standup_front_start2"]) == "standup_front_start2"
    for name in ("standup_front_start1", "standup_front_start2"):   # every type falls the same scripted way
        assert cases[name].fall_speed_scale == type0[name].fall_speed_scale != 1.0
        assert cases[name].fall_stop_shift_cycles == type0[name].fall_stop_shift_cycles
        assert cases[name].settle_cycles == type0[name].settle_cycles


def test_a_robot_type_s_withheld_motions_are_not_run_and_say_so(tmp_path: Path) -> None:
    from motion_studio.realserver.cases import MotionSource

    files = tmp_path / "files"
    shutil.copytree(Path(__file__).parents[2] / "motions" / "files", files)
    (files / "robot_types.toml").write_text('[type2]\nwithheld = ["kick_strong"]\n')
    cases, notes = transfer.playable(transfer.plan(1, 0, ["kick", "kick_strong", "stand"], 2),
                                     MotionSource(tmp_path, "test"))
    assert [case.name for case in cases] == ["stand", "kick"]
    assert notes == ["kick_strong: not run (robot type 2 does not play 'kick_strong': motions/files/robot_types.toml)"]
    kept, notes = transfer.playable(transfer.plan(1, 0, ["kick_strong"], 1), MotionSource(tmp_path, "test"))
    assert [case.name for case in kept] == ["kick_strong"] and notes == []


def test_transfer_type_1_replays_type_1_s_recorded_long_kick(tmp_path: Path) -> None:
    # real_0.7.3_skill_kick_strong_type1 was recorded by motion-studio real skills kick_strong --type 1 --fixture
    # (2026-11-28): type 1's own long kick moved the real ball 5.77 m; its commands replayed open loop on ours.
    out = tmp_path / "out"
    result = _invoke("--type", "1", "--case", "kick_strong", "--case", "stand", "--replay", "--out", str(out))
    assert result.exit_code == 0, result.output
    assert "robot type 1" in result.output
    assert f"{fixture_path(FIXTURES, 'stand_type1')}: no such fixture file" in result.output   # never recorded
    summary = json.loads((out / "transfer.json").read_text())
    assert summary["robot_type"] == 1 and list(summary["runs"]) == ["kick_strong"]
    row = next(r for r in summary["rows"] if r["figure"].startswith("kick_strong: distance"))
    assert row["real"] == pytest.approx(5.77, abs=0.02)
    assert 0.85 < row["ratio"] < 1.1   # measured 0.97 (ours 5.60 m)
    assert "real_0.7.3_skill_kick_strong_type1" in summary["run_notes"]["kick_strong"][0]


# ---- the command -------------------------------------------------------------------------------------------------
def test_help_lists_the_options_with_their_defaults() -> None:
    result = _invoke("--help")
    assert result.exit_code == 0
    for option in ("--starts", "--seed", "--out", "--record", "--fixtures", "--case", "--motions", "--type",
                   "--replay", "--real-server-dir"):
        assert option in result.output
    assert "10" in result.output and "out/transfer" in result.output


@pytest.mark.parametrize("args, message", [
    (["--starts", "0"], "'--starts': Input should be greater than or equal to 1; expected 1 to 1000"),
    (["--case", "fly", "--replay"], "unknown case fly; known: stand"),
    (["--replay", "--record", "x"], "--record needs the real server"),
    (["--type", "5", "--replay"], "'--type': Input should be less than or equal to 4"),
])
def test_bad_options_are_one_line_and_exit_2(args: list[str], message: str, capsys) -> None:
    from motion_studio.cli_errors import run_app

    _register_commands()
    assert run_app(app, ["transfer", *args]) == 2  # as `motion-studio transfer ...` runs it
    output = capsys.readouterr()
    assert message in output.err
    assert len((output.out + output.err).strip().splitlines()) == 1
