"""Turn-gain fitting (motion_studio.tune_turn): the fitted curve predicts the measured turns and inverts
them, falls refuse a fit, and rewriting [turn_gain] keeps every other section and comment."""

from __future__ import annotations

import pytest

from agent.motion.dynamic import DEFAULT_PARAMS_PATH, load_dynamic_params
from motion_studio.tune_turn import fit_turn_gain, write_curve


def _rows(turn_at, gains=(0.1, 0.4, 0.7, 1.0)):
    return [{"gain": g, "left_deg": turn_at(g) + 0.1, "right_deg": turn_at(g) - 0.1, "left_fell": False,
             "right_fell": False} for g in gains]


def test_fit_predicts_and_inverts_a_linear_turn():
    curve, residual = fit_turn_gain(_rows(lambda g: 1.0 + 36.0 * g), min_gain=0.05)
    assert residual == pytest.approx(0.1)
    for gain in (0.05, 0.5, 1.0):
        assert curve.predicted_turn_deg(gain) == pytest.approx(1.0 + 36.0 * gain)
    for turn in (5.0, 20.0, 36.0):
        assert curve.predicted_turn_deg(curve.gain(turn)) == pytest.approx(turn)


def test_fit_refuses_falls_and_a_falling_line():
    rows = _rows(lambda g: 40.0 * g)
    rows[1]["left_fell"] = True
    with pytest.raises(ValueError, match="fell"):
        fit_turn_gain(rows)
    with pytest.raises(ValueError, match="does not grow"):
        fit_turn_gain(_rows(lambda g: 10.0 - g))


def test_rewrite_keeps_the_other_sections(tmp_path):
    path = tmp_path / "dynamic_elements.toml"
    original = DEFAULT_PARAMS_PATH.read_text()
    path.write_text(original)
    curve, _ = fit_turn_gain(_rows(lambda g: 2.0 + 30.0 * g), provenance="test fit")
    write_curve(curve, path)
    loaded = load_dynamic_params(path)
    assert loaded.turn_gain == curve
    assert loaded.walk_lean == load_dynamic_params(DEFAULT_PARAMS_PATH).walk_lean
    text = path.read_text()
    assert text.split("[turn_gain]")[0] == original.split("[turn_gain]")[0]  # header and earlier sections intact


def test_a_tuned_curve_through_points_is_written_and_read_back_with_provenance(tmp_path):
    from motion_studio.tuning.params_file import Provenance
    from motion_studio.turn_problem import turn_curve

    path = tmp_path / "dynamic_elements.toml"
    path.write_text(DEFAULT_PARAMS_PATH.read_text())
    provenance = Provenance("motion-studio tune turn --evaluations 40", "2026-11-26", "abc1234").text("test")
    curve = turn_curve({"gain_at_5_deg": 0.12, "gain_at_20_deg": 0.5, "gain_at_38_deg": 0.96}, (5.0, 20.0, 38.0),
                       provenance)
    write_curve(curve, path)
    loaded = load_dynamic_params(path).turn_gain
    assert loaded == curve and loaded.curve_gains == (0.12, 0.5, 0.96)
    assert loaded.provenance.endswith("motion-studio tune turn --evaluations 40 on 2026-11-26 at abc1234")
