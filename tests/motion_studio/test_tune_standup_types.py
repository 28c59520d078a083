"""``motion-studio tune standup --type N``: the candidates are solved with that type's kinematics and played by a
robot of that type on every backend, and --write goes to the type's own parameter file (never to the shared
``standup.toml`` that types 0, 2 and 4 play)."""

from __future__ import annotations

import math

import pytest

from motion_studio import tune_standup
from motion_studio.realserver.rollout_standup import StandUpOutcome, transfer_starts
from motion_studio.realserver.standup_backend import RealEvaluator
from motions.authoring.standup import PARAMS_PATH, SagittalSolver, load_standup_params, read_meta


def test_longer_legs_may_crouch_higher():
    params = load_standup_params()["standup_front"]
    bounds = {d.name: (d.low, d.high) for d in tune_standup.dimensions(params)}
    typed = {d.name: (d.low, d.high) for d in tune_standup.dimensions(params, robot_type=3)}
    assert typed["crouch_height_m"][1] == pytest.approx(bounds["crouch_height_m"][1] + 0.0557, abs=1e-4)
    assert typed["crouch_height_m"][0] == pytest.approx(bounds["crouch_height_m"][0] + 0.0557 / 2, abs=1e-4)
    assert {k: v for k, v in typed.items() if k != "crouch_height_m"} == \
        {k: v for k, v in bounds.items() if k != "crouch_height_m"}
    assert tune_standup.leg_extra_m(1) == pytest.approx(0.0366, abs=1e-4) and tune_standup.leg_extra_m(4) == 0.0


def test_the_parameter_file_of_a_type():
    assert tune_standup.type_params_file(0) == PARAMS_PATH
    assert tune_standup.type_params_file(1).name == "standup_type1.toml"
    assert tune_standup.type_params_file(1).parent == PARAMS_PATH.parent


def test_our_simulator_plays_the_candidate_on_a_robot_of_the_type(monkeypatch):
    seen = []

    def fake_rollout(motion, side, start, seed=0, robot_type=0):
        seen.append((motion, robot_type))
        return tune_standup.Rollout(1.0, 1.0, 1.0, 1.0, 0, 0)

    monkeypatch.setattr(tune_standup, "rollout", fake_rollout)
    params = load_standup_params()["standup_back"]
    start = tune_standup.Start(None, 0.0, (0.0, 0.0, 0.0), (0.0, 0.0, 0.0))
    tune_standup.evaluate("standup_back", params, (start,), robot_type=1)
    tune_standup.evaluate("standup_back", params, (start,))
    (typed, kind), (shared, kind0) = seen
    assert (kind, kind0) == (1, 0)
    crouch = {w: t.angle_rad for w, t in typed.phase("crouch").targets.items()}
    crouch0 = {w: t.angle_rad for w, t in shared.phase("crouch").targets.items()}
    # the same crouch height on longer legs: the knees bend further
    assert crouch["llj4"] < crouch0["llj4"] - math.radians(5)
    rotation_pitch = params.crouch_pitch_deg
    from kinematics.fk import torso_rotation

    rotation = torso_rotation(math.radians(rotation_pitch))
    kinematics = SagittalSolver(1).kinematics
    sole = rotation @ kinematics.frame_pose("lsole", crouch).position_m
    assert -sole[2] == pytest.approx(params.crouch_height_m, abs=1e-3)


class _Pool:
    def __init__(self) -> None:
        self.requests = []

    def run(self, requests):
        self.requests += requests
        return [StandUpOutcome(None, 0.2, 0.5, 0.0, 0, 0.3, 0.0, 1.0) for _ in requests]


def test_the_real_backend_plays_the_candidate_on_a_robot_of_the_type():
    pool = _Pool()
    params = load_standup_params()["standup_front"]
    evaluator = RealEvaluator("standup_front", transfer_starts("front", 2), pool, use_skill=True, sim_too=True,
                              robot_type=3)
    evaluator.evaluate([params])
    assert len(pool.requests) == 4 and {r.robot_type for r in pool.requests} == {3}
    assert {r.world for r in pool.requests} == {"real", "sim"}
    shared = RealEvaluator("standup_front", transfer_starts("front", 1), _Pool())
    shared.evaluate([params])
    typed_crouch = pool.requests[0].motions["standup_front"].phase("crouch").targets["llj4"].angle_rad
    shared_crouch = shared.pool.requests[0].motions["standup_front"].phase("crouch").targets["llj4"].angle_rad
    assert typed_crouch != pytest.approx(shared_crouch, abs=math.radians(1))


def test_write_goes_to_the_type_s_own_file(tmp_path, monkeypatch, capsys):
    params = load_standup_params()["standup_back"]
    monkeypatch.setattr(tune_standup, "tune", lambda *a, **k: {
        "loss": 2.5, "values": {"crouch_ms": 333}, "result": {"times_s": [2.5]}, "run_dir": str(tmp_path)})
    target = tmp_path / "standup_type1.toml"
    shared_before = PARAMS_PATH.read_text(encoding="utf-8")
    assert tune_standup.main(["standup_back", "--type", "1", "--params", str(target), "--write",
                              "--checkpoint", str(tmp_path / "run")]) == 0
    written = load_standup_params(target)
    assert written["standup_back"].crouch_ms == 333 and written["standup_back"].ground == params.ground
    assert written["standup_front"] == load_standup_params()["standup_front"]  # seeded from standup.toml
    text = target.read_text(encoding="utf-8")
    assert "--type 1" in text and "robot type 1" in text
    assert PARAMS_PATH.read_text(encoding="utf-8") == shared_before
    assert "wrote" not in capsys.readouterr().out  # not the shipped file: no motion files regenerated


def test_the_type_option_is_offered(capsys):
    with pytest.raises(SystemExit):
        tune_standup.main(["standup_back", "--help"])
    assert "--type N" in capsys.readouterr().out
    with pytest.raises(SystemExit):
        tune_standup.main(["standup_back", "--type", "7"])


def test_write_only_writes_the_best_of_a_stopped_run(tmp_path):
    import json

    run = tmp_path / "run"
    run.mkdir()
    rows = [{"kind": "run", "problem": "standup:standup_back:type3"},
            {"kind": "evaluation", "iteration": -1, "index": 0, "loss": 9.0, "values": {"crouch_ms": 400},
             "result": {"times_s": [None]}},
            {"kind": "evaluation", "iteration": 0, "index": 0, "loss": 4.5, "values": {"crouch_ms": 350},
             "result": {"times_s": [2.2]}},
            {"kind": "iteration", "iteration": 0, "evaluations": 2, "best_loss": 4.5},
            {"kind": "evaluation", "iteration": 1, "index": 0, "loss": 7.0, "values": {"crouch_ms": 300},
             "result": {"times_s": [None]}},
            {"kind": "iteration", "iteration": 1, "evaluations": 3, "best_loss": 4.5}]
    (run / "trace.jsonl").write_text("".join(json.dumps(r) + "\n" for r in rows))
    best = tune_standup.run_folder_best(run)
    assert (best["loss"], best["generation"], best["generations"]) == (4.5, 1, 2)
    target = tmp_path / "standup_type3.toml"
    assert tune_standup.main(["standup_back", "--type", "3", "--params", str(target), "--checkpoint", str(run),
                              "--write-only", "--backend", "real"]) == 0
    assert load_standup_params(target)["standup_back"].crouch_ms == 350
    text = target.read_text(encoding="utf-8")
    assert "best of generation 1 of 2" in text and "[2.2]" in text
    assert "a run whose trace does not record its command" in text
    # an empty run folder: nothing to write (one line, exit code 2)
    assert tune_standup.main(["standup_back", "--type", "3", "--params", str(target), "--checkpoint",
                              str(tmp_path / "none"), "--write-only"]) == 2


def test_write_only_writes_the_run_s_own_command_into_the_provenance(tmp_path):
    """The provenance names the options of the run that made the trace, not those of the --write-only call (which
    only needs the folder): before, a run with --starts 6 --sim-weight 0.5 was written down as --starts 4
    --sim-weight 1, the defaults of the call."""
    import json

    run = tmp_path / "run"
    run.mkdir()
    command = "motion-studio tune standup standup_back --starts 6 --type 3 --backend both --sim-weight 0.5"
    rows = [{"kind": "run", "problem": "standup:standup_back:type3", "command": command},
            {"kind": "evaluation", "iteration": 0, "index": 0, "loss": 4.5, "values": {"crouch_ms": 350},
             "result": {"times_s": [2.2]}},
            {"kind": "iteration", "iteration": 0, "evaluations": 1, "best_loss": 4.5}]
    (run / "trace.jsonl").write_text("".join(json.dumps(r) + "\n" for r in rows))
    target = tmp_path / "standup_type3.toml"
    assert tune_standup.main(["standup_back", "--type", "3", "--params", str(target), "--checkpoint", str(run),
                              "--write-only"]) == 0
    provenance = read_meta(target, "standup_back")["provenance"]
    assert command in provenance and "--starts 4" not in provenance, provenance
    assert "best of generation 1 of 1 run, written with --write-only" in provenance
