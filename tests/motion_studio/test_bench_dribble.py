"""The dribble benchmark (issue 14, item 4): its figures from ground truth, the quick run on our simulator, and the
same figures for the real server's dribble cases (``motion-studio real skills dribble``)."""

from __future__ import annotations

import json
import math

import pytest
from typer.testing import CliRunner

from motion_studio.cli import _register_commands, app
from motion_studio.realserver.cases import CASES, STAND_CYCLES
from motion_studio.realserver.skill_figures import figures
from motion_studio.realserver.skill_runs import Run
from motion_studio.scenarios import Truth
from motion_studio.skill_bench.dribble import MODE_GROUP_ORDER, KEEP_M, measure, passed, time_by_mode


def _truth(t: float, torso_x: float, ball_x: float, ball_y: float = 0.0, up_z: float = 1.0) -> Truth:
    return Truth(t, (torso_x, 0.0, 0.33), up_z, 0.0, (ball_x, ball_y, 0.042), False)


def test_measure_times_the_ball_over_its_way_and_counts_the_cycles_it_stayed_near():
    # The robot walks at 0.5 m/s; the ball lies 0.3 m ahead for 10 s, then rolls 0.8 m ahead for the rest.
    truths = []
    for i in range(1500):
        t = (i + 1) * 0.02
        torso = 0.5 * t
        truths.append(_truth(t, torso, torso + (0.3 if t <= 10.0 else 0.8)))
    figures_ = measure(truths, (0.0, 0.0), 0.0, 10.0)
    # the ball passes x = 10 when the torso is at 9.2: t = 18.4 s
    assert figures_["time_s"] == pytest.approx(18.4, abs=0.03)
    assert figures_["speed_m_s"] == pytest.approx(10.0 / 18.4, abs=0.002)
    assert figures_["keep_share"] == pytest.approx(10.0 / 18.4, abs=0.01)
    assert figures_["distance_max_m"] == pytest.approx(0.8)
    assert not figures_["fell"]
    assert not passed(figures_)  # 54 % of the time within 0.5 m


def test_measure_sees_a_fall_a_ball_off_the_line_and_a_way_never_finished():
    truths = [_truth((i + 1) * 0.02, 0.0, 0.2 + 0.001 * i, 0.3, up_z=1.0 if i < 100 else 0.2) for i in range(200)]
    figures_ = measure([None, *truths], (0.0, 0.0), 0.0, 10.0)
    assert figures_["fell"]
    assert figures_["time_s"] is None and figures_["speed_m_s"] is None
    assert figures_["off_line_m"] == pytest.approx(0.3)
    assert not passed(figures_)


def test_the_quick_dribble_benchmark_brings_the_ball_10_m_on_our_simulator(tmp_path):
    _register_commands()
    result = CliRunner().invoke(app, ["bench", "skills", "--skill", "dribble", "--quick", "--json", "--out",
                                      str(tmp_path)])
    assert result.exit_code == 0, result.output
    figures_ = json.loads(result.output.strip().splitlines()[-1])["dribble"]
    assert figures_["falls"] == 0
    assert figures_["straight"]["reached"] == 1
    assert figures_["straight"]["speed_mean_m_s"] > 0.3   # the issue asks 0.4; measured 0.47-0.53
    assert figures_["turn"]["reached"] == 1               # the ball brought round 90 deg, 4 m on the new line
    assert (tmp_path / "dribble_type0.png").stat().st_size > 10_000
    for trial in figures_["trials"]:   # the time per mode covers the trial's time, cycle for cycle
        assert sum(trial["time_by_mode_s"].values()) == pytest.approx(trial["time_s"], abs=0.03)
    assert figures_["straight"]["time_by_mode_mean_s"]["push"] > 5.0


def test_the_real_dribble_case_is_measured_like_the_benchmark_from_the_skill_start():
    case = CASES["dribble"]
    assert case.ball_m == pytest.approx((-7.8, 0.0)) and case.dribble == (0.0, 10.0)
    # The stand before the skill: the ball lies still 0.2 m ahead; then it is pushed 1 m per second and stays 0.4 m
    # ahead of the torso: 10 m after 10 s.
    truths: list[Truth | None] = [_truth(i * 0.02, -8.0, -7.8) for i in range(STAND_CYCLES)]
    for i in range(1, 600):
        ball = -7.8 + i * 0.02
        truths.append(_truth(STAND_CYCLES * 0.02 + i * 0.02, ball - 0.4, ball))
    out = figures(Run("real", truths), case)
    assert out["dribble time [s]"] == pytest.approx(10.0, abs=0.03)
    assert out["dribble speed [m/s]"] == pytest.approx(1.0, abs=0.01)
    assert out[f"ball within {KEEP_M} m [share]"] == pytest.approx(1.0)
    assert out["dribble fell"] == "no"
    assert not math.isnan(out["ball from torso max [m]"])


def test_time_by_mode_groups_the_dribble_modes_and_counts_only_cycles_with_a_dribble():
    modes = [None] * 5 + ["start"] + ["push"] * 50 + ["avoid"] * 10 + ["approach"] * 10 + ["turn"] * 25 \
        + ["near:walk_left"] * 20 + ["near:stop"] * 5 + ["blocked"] * 3 + ["search"] * 2
    split = time_by_mode(modes)
    assert list(split) == list(MODE_GROUP_ORDER)
    assert split == {"push": 1.0, "approach": 0.46, "turn": 0.5, "near-ball": 0.5, "search": 0.04}


def test_the_real_dribble_case_splits_its_time_by_the_skill_modes_it_recorded():
    """The same split on both servers: ``Run.modes`` (the dribble's mode per skill-phase cycle, the stand before
    it included) beside the truths; the split covers the way only (here 10 s, then 2 s more of pushing)."""
    case = CASES["dribble"]
    truths: list[Truth | None] = [_truth(i * 0.02, -8.0, -7.8) for i in range(STAND_CYCLES)]
    for i in range(1, 600):
        ball = -7.8 + i * 0.02
        truths.append(_truth(STAND_CYCLES * 0.02 + i * 0.02, ball - 0.4, ball))
    modes = [None] * STAND_CYCLES + ["turn"] * 100 + ["near:walk_right"] * 100 + ["push"] * 399
    out = figures(Run("real", truths, modes=modes), case)
    assert out["dribble time [s]"] == pytest.approx(10.0, abs=0.03)
    assert out["dribble turn [s]"] == pytest.approx(2.0)
    assert out["dribble near-ball [s]"] == pytest.approx(2.0)
    assert out["dribble push [s]"] == pytest.approx(6.0, abs=0.03)
    assert "dribble push [s]" not in figures(Run("real", truths), case)   # an open-loop replay has no modes
