"""motion-studio calibrate: real traces load with located errors, replay on the real MuJoCo world, and the
agreement measures tell a faithful world from a broken one."""

from __future__ import annotations

import gzip
import json
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


def test_the_real_kick_moves_our_ball_as_far_and_the_ode_friction_candidate_does_not() -> None:
    # The real kick of the shipped motions (recorded at 66e41c9): the real ball went 4.09 m. With the ball contacts
    # fitted on it (sim.physics_params: ball priority, mu 0.5 on robots, mu 10 on the field) the replayed commands
    # moved ours 4.01 m (the earlier defaults: 2.43 m, the ball jammed between foot and ground), with those fitted
    # on pushes too 3.88 m. The ode_friction candidate reproduced the older kick's jam (real 1.45 m, an older
    # motion) but jams this one too: 1.67 m.
    from sim.physics_params import load_physics_file

    kick = load_trace(FIXTURES / "real_0.7.3_skill_kick.jsonl.gz")
    travel = {m.name: m for m in measures(replay_trace(kick))}["ball_travel_m"]
    assert 3.5 < travel.real < 4.5
    assert abs(travel.ours - travel.real) < 0.1 * travel.real          # measured 3.877 m against 4.086
    candidate = Path(__file__).parents[2] / "sim" / "physics_candidates" / "ode_friction.toml"
    params = default_physics_params(**load_physics_file(candidate))
    jammed = {m.name: m for m in measures(replay_trace(kick, params))}["ball_travel_m"]
    assert jammed.ours < 0.5 * travel.real                             # measured 1.67 m
