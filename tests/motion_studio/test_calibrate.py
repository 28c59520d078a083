"""motion-studio calibrate: real traces load with located errors, replay on the real MuJoCo world, and the
agreement measures tell a faithful world from a broken one."""

from __future__ import annotations

import gzip
import json
import os
import subprocess
import sys
from dataclasses import replace
from pathlib import Path

import pytest

from motion_studio.calibration.agreement import Replay, measures, score
from motion_studio.calibration.fit import evaluate, with_values
from motion_studio.calibration.report import write_physics_file
from motion_studio.realserver.errors import FixtureError
from motion_studio.realserver.fixtures import find_fixture_files, read_fixture
from motion_studio.realserver.replay import replay_states
from sim.physics_params import default_physics_params, load_physics_file


def load_trace(path: Path):  # noqa: ANN201 - realserver.fixtures.Fixture
    return read_fixture(path, require_meta=False)


def replay_trace(trace, physics=None) -> Replay:  # noqa: ANN001
    return Replay(trace, replay_states(trace, physics))

FIXTURES = Path(__file__).parents[1] / "sim" / "fixtures"


def test_every_fixture_loads() -> None:
    paths = find_fixture_files(FIXTURES)
    assert len(paths) >= 15
    for path in paths:
        trace = load_trace(path)
        assert trace.received and -1 in trace.replies


def test_a_corrupt_line_is_named_with_file_and_line(tmp_path: Path) -> None:
    rows = [json.dumps({"k": "send", "i": -1, "msg": "(scene rsg/agent/nao/nao.rsg)"}),
            json.dumps({"k": "recv", "msg": "(time (now 1.00))"}), "{not json", ""]
    path = tmp_path / "real_0.7.3_broken.jsonl.gz"
    with gzip.open(path, "wt") as stream:
        stream.write("\n".join(rows))
    with pytest.raises(FixtureError, match=r"real_0.7.3_broken.jsonl.gz:3: not JSON"):
        load_trace(path)


def test_a_line_without_its_field_is_named(tmp_path: Path) -> None:
    path = tmp_path / "real_x.jsonl.gz"
    with gzip.open(path, "wt") as stream:
        stream.write(json.dumps({"k": "send", "i": -1, "msg": "(scene a)"}) + "\n" + json.dumps({"k": "recv"}) + "\n")
    with pytest.raises(FixtureError, match=r"real_x.jsonl.gz:2: missing field 'msg'"):
        load_trace(path)


def test_a_missing_trace_is_named(tmp_path: Path) -> None:
    with pytest.raises(FixtureError, match="no such fixture file"):
        load_trace(tmp_path / "real_none.jsonl.gz")


def test_the_standing_replay_agrees_and_a_turn_tells_broken_friction() -> None:
    stand = replay_trace(load_trace(FIXTURES / "real_0.7.3_skill_stand.jsonl.gz"))
    assert score(measures(stand)) < 0.2   # measured 0.02: height within 1 mm, no drift
    turn = load_trace(FIXTURES / "real_0.7.3_skill_turn_left.jsonl.gz")
    faithful = score(measures(replay_trace(turn)))
    icy = measures(replay_trace(turn, default_physics_params(friction=0.05)))
    assert faithful < 0.5                 # measured 0.22: 632 deg against the real 607
    turned = next(m for m in icy if m.name == "turn_deg")
    assert turned.ours < 0.5 * turned.real and score(icy) > faithful + 0.5   # measured 81 deg: feet slip


def test_fitted_values_round_trip_through_the_physics_file(tmp_path: Path) -> None:
    trace = load_trace(FIXTURES / "real_0.7.3_stand.jsonl.gz")
    base = default_physics_params()
    values = {"friction": 3.5, "contact_solimp[0]": 0.4, "contact_solimp[1]": 0.3}
    fitted = with_values(base, values)
    assert fitted.contact_solimp[:2] == (0.4, 0.4)   # dmax raised to dmin, as MuJoCo needs
    before, after = evaluate([trace], base), evaluate([trace], fitted, values)
    path = tmp_path / "physics.toml"
    write_physics_file(path, after, before, "motion-studio calibrate --generations 1", ["stand"])
    text = path.read_text()
    assert text.startswith("# Physical parameters") and "motion-studio calibrate --generations 1" in text
    loaded = load_physics_file(path)
    assert loaded["friction"] == 3.5 and loaded["contact_solimp"][:2] == (0.4, 0.4)
    assert replace(base, **loaded) == fitted


def test_cli_error_is_one_line(tmp_path: Path) -> None:
    result = subprocess.run([sys.executable, "-m", "motion_studio", "calibrate", "--traces", str(tmp_path)],
                            capture_output=True, text=True, timeout=120)
    assert result.returncode == 2
    assert result.stderr.strip().count("\n") == 0 and "no real_*.jsonl" in result.stderr


def test_the_slip_fit_starts_from_a_physics_file_that_sets_it(tmp_path: Path) -> None:
    # With the defaults (no slip) the fit cannot start: one line naming the field and the way out.
    run_dir = tmp_path / "run"
    result = subprocess.run([sys.executable, "-m", "motion_studio", "calibrate", "--only", "real_0.7.3_stand.",
                             "--parameters", "slip", "--generations", "1", "--popsize", "4", "--out", str(run_dir)],
                            capture_output=True, text=True, timeout=300,
                            env={**os.environ, "NAO3D_PHYSICS_FILE": ""})
    assert result.returncode == 2
    assert result.stderr.strip().splitlines()[-1].startswith("error: ")
    assert "foot_slip_m_s_per_n is off (None)" in result.stderr and "NAO3D_PHYSICS_FILE" in result.stderr
    # A fitted slip value lands in the world: the feet then carry the dampers.
    fitted = with_values(default_physics_params(), {"foot_slip_m_s_per_n": 0.004, "foot_slip_layer_m": 0.0005})
    assert fitted.foot_slip_m_s_per_n == 0.004 and fitted.foot_slip_layer_m == 0.0005
    trace = load_trace(FIXTURES / "real_0.7.3_stand.jsonl.gz")
    assert evaluate([trace], fitted).blow_ups == 0


def test_the_report_counts_the_replays_that_end_as_the_real_run_did() -> None:
    # The transfer issue's "same fall/no-fall outcome for every recorded open-loop command stream": standing
    # agrees; the real walk's commands make ours fall (the real robot walks on); the real back stand-up of the
    # motions at 35e251e stands the real robot up and ours only with the feet slipping as SimSpark's.
    from motion_studio.calibration.agreement import Outcome
    from motion_studio.calibration.report import agreement_table

    names = ["real_0.7.3_skill_stand", "real_0.7.3_skill_walk_forward", "real_0.7.3_skill_standup_front_35e251e"]
    traces = [load_trace(FIXTURES / f"{name}.jsonl.gz") for name in names]
    default = evaluate(traces, default_physics_params(), ball_roll=False)
    slipping = evaluate(traces, default_physics_params(foot_slip_m_s_per_n=0.005), ball_roll=False)
    assert default.outcomes["skill_stand"] == (Outcome(False, True), Outcome(False, True))
    assert default.outcomes["skill_walk_forward"] == (Outcome(False, True), Outcome(True, False))
    assert default.outcomes["skill_standup_front_35e251e"] == (Outcome(True, True), Outcome(True, False))
    assert slipping.outcomes["skill_standup_front_35e251e"] == (Outcome(True, True), Outcome(True, True))
    assert (default.same_outcomes(), slipping.same_outcomes()) == (1, 2)
    table = agreement_table(default, slipping).splitlines()
    assert table[-1] == (
        "same outcome as the real robot (fell or not, standing at the end or not): 1 -> 2 of 3 skill traces")
    # Each row says how both ended, the shown (after) side's, with a mark where they differ.
    rows = {line.split()[0]: line.split()[3] for line in table[1:-2]}
    assert rows == {"skill_stand": "stood/stood", "skill_walk_forward": "stood/down!",
                    "skill_standup_front_35e251e": "rose/rose"}
    assert agreement_table(default).splitlines()[3].split()[2] == "rose/down!"


def test_a_physics_file_named_by_the_environment_is_used(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    path = tmp_path / "candidate.toml"
    path.write_text("[physics]\nfriction = 7.5\ncontact_solref = [0.03, 1.2]\n")
    monkeypatch.setenv("NAO3D_PHYSICS_FILE", str(path))
    params = default_physics_params(substeps=1)
    assert params.friction == 7.5 and params.contact_solref == (0.03, 1.2)
    monkeypatch.setenv("NAO3D_PHYSICS_FILE", str(tmp_path / "missing.toml"))
    with pytest.raises(ValueError, match="no such physics file"):
        default_physics_params()
    path.write_text("[physics]\nfrictoin = 1\n")
    monkeypatch.setenv("NAO3D_PHYSICS_FILE", str(path))
    with pytest.raises(ValueError, match="unknown physics parameter 'frictoin'"):
        default_physics_params()


def test_ball_roll_is_compared_with_the_real_figure() -> None:
    from motion_studio.calibration.reference_figures import ball_roll_measures

    faithful = ball_roll_measures(default_physics_params())
    assert [m.name for m in faithful] == ["roll_at_2_m_s", "roll_at_4_m_s", "roll_at_6_m_s", "roll_at_8_m_s"]
    # within the 3 % at every speed: measured 0.6847 m per m/s at 2-8 m/s (+1.1 %; 0.685-0.709 before the
    # ball-field contact pair)
    assert all(m.error < 1.0 for m in faithful)
    draggy = ball_roll_measures(default_physics_params(ball_linear_drag_n_s_m=0.05))
    assert all(m.ours < 0.5 and m.error == 5.0 for m in draggy)   # five times the drag: rolls far shorter


@pytest.mark.xfail(strict=True, reason=(
    "measured disagreement (2026-11-28): the shipped kick's real commands from its spot (recorded at 66e41c9) move "
    "the real ball 4.09 m and ours 3.0 m (1.99 m before the kicking foot met the ground where its drift puts it, "
    "sim.physics_params; 3.88 m before the legs got ODE's joint drift, sim.joint_slack, which met the ball with a "
    "foot 9 mm too high). Both servers' kick has two regimes along its line (python -m "
    "motion_studio.realserver.kick_check kick --offsets-cm=-1,...,3): the real ball goes 3.2-3.3 m at -0.6 deg "
    "from up to 2.5 mm short of the spot and 4.0-4.4 m at -8.5 deg from 1 mm short on; ours 3.9 m at -2.9 deg "
    "and 4.3 m at -8.2 deg with the same boundary, but a 3 mm pocket on it (1.2-2.3 m, the ball scooped up): "
    "one cycle before the strike our stance toe leaves the ground for a step and the robot drops 4.4 mm where "
    "the real one stays (ODE's 1 mm surface layer keeps a lightly loaded toe in contact), so our foot meets the "
    "ball 4 mm lower, its centre nearer the foot's top face than its front face. The kick's spot has since moved "
    "4 mm out (motions/params/kick.toml), where both servers kick in the far regime (live: real 4.07 m, ours "
    "4.33 m); this recording has the ball on the spot before"))
def test_the_real_kick_from_its_spot_moves_our_ball_as_far() -> None:
    kick = load_trace(FIXTURES / "real_0.7.3_skill_kick.jsonl.gz")
    travel = {m.name: m for m in measures(replay_trace(kick))}["ball_travel_m"]
    assert 3.5 < travel.real < 4.5
    assert abs(travel.ours - travel.real) < 0.1 * travel.real          # measured 3.0 m against 4.09
