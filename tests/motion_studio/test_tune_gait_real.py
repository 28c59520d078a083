"""The gait tuner's real-server backend without the real server: a recorded real walk measured and scored as
ours (``rollout_walk.walk_run`` + ``tune_gait.trial_score``), the cuts at a fall and at the x limit, the real
trials, the losses of ``--backend real|both`` (``gait_backend.RealJudge`` on a stand-in bench), a checkpointed
run on it, and the CLI's one-line error without the real-server scripts."""

from __future__ import annotations

import math
from pathlib import Path

import pytest

from motion_studio import tune_gait
from motion_studio.realserver import gait_backend
from motion_studio.realserver.fixtures import fixture_path, read_fixture
from motion_studio.realserver.gait_backend import RealJudge, combined_loss, real_note, real_trials
from motion_studio.realserver.rollout_walk import walk_run
from motion_studio.scenarios import Truth
from motions.authoring.gait_params import load_gait_params

#: The shipped forward walk of ac7dd4d on the real rcssserver3d 0.7.3 (``motion-studio real skills walk_forward``):
#: 10 s of walk (500 cycles) from (-8, 0), then its 2 s stop.
FIXTURES = Path(__file__).parents[1] / "sim" / "fixtures"
WALK_CYCLES = 500


@pytest.fixture(scope="module")
def recorded():
    fixture = read_fixture(fixture_path(FIXTURES, "walk_forward"))
    start = fixture.skill_cycle + 1  # the state the message after the first walk command reports
    truths = [fixture.truth.get(i) for i in range(start, len(fixture.received))]
    return truths


def _truth(x_m: float, z_m: float = 0.33, up_z: float = 0.97, y_m: float = 0.0, heading_deg: float = 0.0) -> Truth:
    return Truth(0.0, (x_m, y_m, z_m), up_z, heading_deg, (0.0, 9.8, 0.042), False)


def test_a_recorded_real_walk_is_scored_as_ours(recorded):
    run = walk_run(recorded, "walk_forward", 0.0, WALK_CYCLES, 0.0, 14.5)
    first, end = recorded[0], recorded[WALK_CYCLES - 1]
    assert first is not None and end is not None
    assert not run.fell and not run.fell_stopping and run.walk_cycles == WALK_CYCLES
    along, left = run.displacement_m()
    assert along == pytest.approx(end.torso_m[0] - first.torso_m[0])
    assert left == pytest.approx(end.torso_m[1] - first.torso_m[1])
    assert 4.0 < along < 7.0  # the shipped walk then: about 0.5 m/s on the real server
    score = tune_gait.trial_score(run, (1.0, 0.0))
    expected = along / 10.0 - 0.3 * abs(left) / 10.0 - 0.002 * abs(run.heading_change_deg)
    assert score["score"] == pytest.approx(expected)
    assert score["fell"] == 0.0 and score["time_s"] == pytest.approx(10.0)
    assert run.settled  # stopped standing within the 2 s after the walk


def test_a_fall_ends_the_walk_and_costs_its_penalty():
    truths = [_truth(0.01 * i) for i in range(30)] + [_truth(0.3, z_m=0.2, up_z=0.1)] * 40
    run = walk_run(truths, "walk_forward", 0.0, 60, 0.0, 14.5)
    assert run.fell and run.fall_cycle == 30 and run.walk_cycles == 31 and len(run.truths) == 31
    score = tune_gait.trial_score(run, (1.0, 0.0))
    assert score["fell"] == 1.0 and score["score"] < 0.0  # 0.3 m over 10 s - 2 m / 10 s - 0.5


def test_a_fall_while_stopping_is_not_a_fall_while_walking():
    truths = [_truth(0.01 * i) for i in range(60)] + [_truth(0.6, z_m=0.2, up_z=0.1)] * 10
    run = walk_run(truths, "walk_forward", 0.0, 60, 0.0, 14.5)
    assert not run.fell and run.fell_stopping and run.walk_cycles == 60
    assert tune_gait.trial_score(run, (1.0, 0.0))["fell_stopping"] == 1.0


def test_the_walk_is_cut_past_the_x_limit_and_gaps_take_the_truth_before():
    truths = [_truth(14.0 + 0.02 * i) for i in range(50)]
    truths[3] = truths[4] = None
    run = walk_run([None] + truths, "walk_forward", 0.0, 50, 0.0, 14.5)
    assert run.truths[0] == truths[0] and run.truths[4] == truths[2] and run.truths[5] == truths[2]
    assert run.walk_cycles == 27 and run.walk_end.torso_m[0] >= 14.5 and not run.fell
    with pytest.raises(ValueError, match="no truth"):
        walk_run([None, None], "walk_forward", 0.0, 2, 0.0, None)


def test_the_real_trials_are_the_tuners_without_pushes():
    assert real_trials("walk_forward", lean=False) == (tune_gait.Trial(20.0),)
    assert [t.lean for t in real_trials("walk_forward", lean=True)] == [0.0, 1.0, -1.0]
    assert real_trials("walk_forward", lean=True, quick=True) == (tune_gait.Trial(6.0),)
    assert all(not t.pushes for t in real_trials("walk_left", lean=True))
    place = tune_gait.trial_place(tune_gait.Trial(10.0, lean=1.0), (1.0, 0.0))
    assert place == {"position_m": (-8.0, 0.0), "x_limit_m": 14.5}


class StandInBench:
    """Walks as the recorded real walk, scaled by the candidate's speed constant (its step length)."""

    def __init__(self, recorded: list[Truth | None]) -> None:
        self.recorded = recorded
        self.calls: list[tuple] = []

    def walk(self, library, motion, duration_s, *, position_m, lean, x_limit_m, heading_deg=0.0):
        self.calls.append((motion, duration_s, position_m, lean, x_limit_m))
        scale = library.get(motion).constants["speed_m_s"] / 0.655
        x0 = self.recorded[0].torso_m[0]
        truths = [None if t is None else Truth(t.time_s, (x0 + scale * (t.torso_m[0] - x0), *t.torso_m[1:]),
                                               t.up_z, t.heading_deg, t.ball_m, False) for t in self.recorded]
        return walk_run(truths, motion, lean, WALK_CYCLES, heading_deg, x_limit_m)


def test_the_real_loss_is_the_mean_score_and_both_average_with_ours(recorded, monkeypatch):
    params = load_gait_params()["walk_forward"]
    bench = StandInBench(recorded)
    trials = (tune_gait.Trial(10.0), tune_gait.Trial(10.0, lean=1.0))
    real = RealJudge(bench, "walk_forward", trials)(params)
    assert [c[2:] for c in bench.calls] == [((-13.5, 0.0), 0.0, 14.5), ((-8.0, 0.0), 1.0, 14.5)]
    scores = [t["score"] for t in real["real"]["trials"]]
    assert real["loss"] == pytest.approx(-sum(scores) / 2, abs=1e-3) and "ours" not in real
    assert [t["lean"] for t in real["real"]["trials"]] == [0.0, 1.0]
    monkeypatch.setattr(tune_gait, "evaluate", lambda motion, p, trials, robust: {"loss": -0.25, "trials": []})
    both = RealJudge(bench, "walk_forward", trials, ours_trials=(tune_gait.Trial(6.0),))(params)
    assert both["loss"] == pytest.approx((real["real"]["loss"] - 0.25) / 2)
    assert combined_loss(-0.6, None) == -0.6 and combined_loss(-0.6, -0.2) == pytest.approx(-0.4)
    assert real_note(real).startswith("real rcssserver3d 0.7.3 trials: plain ") and "lean +1" in real_note(real)


def test_a_candidate_out_of_reach_is_a_large_loss_without_a_walk(recorded, monkeypatch):
    from kinematics.errors import IKError

    def unreachable(motion, params):
        raise IKError("foot out of reach", "lfoot", 0.05)

    monkeypatch.setattr(tune_gait, "candidate_library", unreachable)
    bench = StandInBench(recorded)
    result = RealJudge(bench, "walk_forward", (tune_gait.Trial(10.0),))(load_gait_params()["walk_forward"])
    assert result["loss"] == tune_gait.FAIL_LOSS and not bench.calls


def test_tuning_with_a_judge_checkpoints_and_resumes(recorded, tmp_path):
    """Two generations judged by a stand-in bench whose speed grows with the step: the best candidate steps
    longer than the start, and a second call resumes without judging again."""
    base = load_gait_params()["walk_forward"]
    bench = StandInBench(recorded)
    judge = RealJudge(bench, "walk_forward", (tune_gait.Trial(10.0),))
    space = [d for d in tune_gait.SPACES["walk_forward"] if d.name == "step_length_m"]
    run_dir = tmp_path / "gait"
    data = tune_gait.tune("walk_forward", base, space, (), 2, run_dir, popsize=4, progress=None, judge=judge)
    assert len(data["evaluations"]) == 8 and (run_dir / "checkpoint.pkl").is_file()
    assert data["best"]["params"]["step_length_m"] > base.step_length_m
    assert data["best"]["loss"] < -0.5 and not math.isnan(data["best"]["loss"])
    calls = len(bench.calls)
    again = tune_gait.tune("walk_forward", base, space, (), 2, run_dir, popsize=4, progress=None, judge=judge)
    assert len(again["evaluations"]) == 8 and len(bench.calls) == calls


def test_the_real_backend_without_the_scripts_is_one_line(tmp_path, monkeypatch, capsys):
    from motion_studio.cli import _register_commands, app
    from motion_studio.cli_errors import run_app

    monkeypatch.setenv("NAO3D_REAL_SERVER_DIR", str(tmp_path))
    _register_commands()
    code = run_app(app, ["tune", "gait", "walk_forward", "--backend", "real", "--checkpoint", str(tmp_path / "run")])
    err = capsys.readouterr().err.strip()
    assert code == 2 and len(err.splitlines()) == 1
    assert "no server.sh or netns.sh" in err and not (tmp_path / "run").exists()


def test_a_real_transition_trial_is_reported_as_ours():
    from motion_studio.walk_trials import trial_result

    upright = [_truth(0.01 * i) for i in range(20)]
    tilting = [_truth(0.2, up_z=0.8), _truth(0.2, up_z=0.7), _truth(0.2, z_m=0.2, up_z=0.3), _truth(0.2, up_z=0.1)]
    phases = [(0, "stand", "hold")] * 10 + [(1, "walk_forward", "cycle_3")] * 10 + [(2, "walk_forward", "stop_1")] * 4
    result = trial_result("walk_forward:stand", [None] + upright[1:] + tilting, phases)
    assert result.fell and result.fall_segment == 2 and (result.fall_motion, result.fall_phase) == ("walk_forward",
                                                                                                     "stop_1")
    assert len(result.truths) == 22 and result.min_up_z == pytest.approx(0.3)  # ends at the first fallen cycle
    assert result.distance_m == pytest.approx(0.2 - 0.01)
    calm = trial_result("walk_forward:turn", upright, phases[:20])
    assert not calm.fell and calm.fall_segment is None and calm.fall_time_s is None
    assert calm.distance_m == pytest.approx(0.19) and calm.min_up_z == pytest.approx(0.97)


def test_bounds_narrow_the_search_and_bad_ones_are_errors():
    from motion_studio.tuning.errors import TuningError

    space = tune_gait.bounded(tune_gait.SPACES["walk_forward"], ["step_length_m=0.072:0.09"])
    step = next(d for d in space if d.name == "step_length_m")
    assert (step.low, step.high) == (0.072, 0.09) and len(space) == len(tune_gait.SPACES["walk_forward"])
    for item, message in (("foo=1:2", "unknown parameter 'foo'"), ("step_length_m=a:b", "NAME=LOW:HIGH"),
                          ("step_length_m=0.09:0.07", "lower bound")):
        with pytest.raises(TuningError, match=message):
            tune_gait.bounded(tune_gait.SPACES["walk_forward"], [item])


def test_a_lean_trial_credits_its_path_and_its_curving_not_the_way_ahead():
    """Two lean trials at the same pace along their paths: the one that curves its way scores the bonus on top;
    the way along the start heading (shorter for the curving one) does not count."""
    def lean_run(curve_deg_per_cycle: float) -> object:
        truths, x, y, heading = [], 0.0, 0.0, 0.0
        for _ in range(500):
            truths.append(_truth(x, y_m=y, heading_deg=heading))
            heading += curve_deg_per_cycle
            x, y = x + 0.012 * math.cos(math.radians(heading)), y + 0.012 * math.sin(math.radians(heading))
        return walk_run(truths, "walk_forward", 1.0, 500, 0.0, None)

    straight, curving = lean_run(0.0), lean_run(0.2)
    a, b = tune_gait.trial_score(straight, (1.0, 0.0)), tune_gait.trial_score(curving, (1.0, 0.0))
    assert a["score"] == pytest.approx(0.6, abs=0.02) and a["curvature_deg_m"] == pytest.approx(0.0)
    assert b["along_m"] < a["along_m"] - 0.5 and b["curvature_deg_m"] == pytest.approx(17.0, abs=0.5)
    assert b["score"] == pytest.approx(0.6 + 0.02 * b["curvature_deg_m"], abs=0.02)


def test_writing_a_tuned_walk_keeps_every_other_sections_measured_figures(tmp_path, monkeypatch):
    """``--write`` rewrites the parameter file: the tuned walk gets its new measured figures and every other
    walk keeps its own (they are copied into the motion files' constants, which the skills' odometry and stop
    distances read; the writer once dropped them)."""
    import shutil
    import tomllib

    from motion_studio import tune_gait
    from motions.authoring.gait_params import GAIT_PARAMS_PATH, load_gait_params

    params = tmp_path / "gait.toml"
    shutil.copy(GAIT_PARAMS_PATH, params)
    before = tomllib.loads(params.read_text(encoding="utf-8"))
    monkeypatch.setattr(tune_gait, "measure", lambda motion, p: {"forward_m_s": 0.5, "left_m_s": 0.01,
                                                                 "time_s": 20.0, "fell": False, "stop_m": 0.2})
    monkeypatch.setattr(tune_gait, "write_gait_files", lambda path, names: [])
    best = {"params": tune_gait._as_dict(load_gait_params(params)["walk_backward"]), "loss": -0.3}
    tune_gait.write_best("walk_backward", best, "test", params_path=params)
    after = tomllib.loads(params.read_text(encoding="utf-8"))
    assert after["walk_backward"]["measured_forward_m_s"] == 0.5
    for name in ("walk_forward", "walk_fast", "walk_left", "walk_right"):
        for key in ("measured_forward_m_s", "measured_left_m_s", "measured_stop_m"):
            assert after[name][key] == before[name][key], (name, key)
