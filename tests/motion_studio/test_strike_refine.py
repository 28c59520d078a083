"""The strike keyframe refined by rollouts (motion_studio.strike_refine) on a tiny budget: the seed comes from
the IPOPT keyframe, the refined candidate is no worse than the start on the same rollouts, and re-running a
candidate gives the loss the run recorded (so "no worse" is a property of the kick, not of luck)."""

from dataclasses import replace

import pytest

from motion_studio.kick_rollout import Placement
from motion_studio.strike_keyframe import optimise_strike
from motion_studio.strike_refine import REFINED, refine_strike, seeded_values
from motion_studio.tune_kick import SPACE, Objective, evaluate
from motion_studio.tuning import subset
from motions.authoring.kick import kick_params, stance_params

PLACEMENTS = (Placement(0.0, 0.0, 0.0), Placement(-0.01, 0.005, 2.0))


def test_seed_is_the_keyframes_contact_within_the_tuner_bounds():
    strike = optimise_strike(0)
    values = seeded_values(strike)
    assert set(values) == set(REFINED)
    for parameter in subset(SPACE, REFINED):
        assert parameter.low <= values[parameter.name] <= parameter.high
    assert values["ball_side_m"] == pytest.approx(-strike.toe_position_m[0], abs=1e-3)
    assert values["ball_ahead_m"] > strike.toe_position_m[1]  # the ball lies ahead of the toe it meets
    assert values["strike_hip_offset_deg"] == pytest.approx(strike.angles_deg["llj1"], abs=1e-3)


def test_refined_kick_is_at_least_as_good_as_the_start_on_the_same_rollouts(tmp_path):
    refinement = refine_strike("kick", generations=1, placements=PLACEMENTS, popsize=2, run_dir=tmp_path / "run")
    assert refinement.best_loss <= refinement.start_loss
    assert refinement.rollouts == (1 + 2) * len(PLACEMENTS)
    assert (tmp_path / "run" / "trace.jsonl").is_file()
    # the recorded losses are the kick's: the best candidate rolled out again scores the same
    params = replace(kick_params("kick"), **refinement.best)
    again = evaluate(params, stance_params(), Objective(), PLACEMENTS)
    assert float(again["loss"]) == pytest.approx(refinement.best_loss, abs=1e-3)


def test_bad_budget_one_line_error(tmp_path):
    with pytest.raises(ValueError, match="generations"):
        refine_strike(generations=0, run_dir=tmp_path)
    with pytest.raises(ValueError, match="placements"):
        refine_strike(placements=(), run_dir=tmp_path)


def test_strike_cli_prints_keyframe_and_seed():
    import json

    from typer.testing import CliRunner

    from motion_studio.cli import _register_commands, app

    _register_commands()
    result = CliRunner().invoke(app, ["strike", "--json"])
    assert result.exit_code == 0, result.output
    figures = json.loads(result.output)
    assert figures["strike"]["solver_status"] == "Solve_Succeeded" and set(figures["seeded"]) == set(REFINED)
    bad = CliRunner().invoke(app, ["strike", "--refine", "--section", "nope"])
    assert bad.exit_code != 0 and "nope" in bad.output
