"""The turn-gain curve (agent.motion.dynamic.TurnGain): requested turn -> gain is monotone and clamped, and the
predicted turn inverts it over the curve's range."""

from __future__ import annotations

import pytest

from agent.motion.dynamic import TurnGain


def test_gain_is_smallest_below_the_offset_and_one_beyond_the_span():
    curve = TurnGain(min_gain=0.3, offset_deg=3.0, span_deg=37.0)
    assert curve.gain(0.0) == curve.gain(1.0) == curve.gain(3.0) == pytest.approx(0.3)
    assert curve.gain(40.0) == curve.gain(90.0) == pytest.approx(1.0)
    assert curve.gain(-21.5) == pytest.approx(0.3 + 0.7 * 18.5 / 37.0)


def test_gain_never_falls_as_the_request_grows():
    curve = TurnGain(min_gain=0.05, offset_deg=2.0, span_deg=38.0)
    gains = [curve.gain(0.25 * i) for i in range(200)]
    assert all(b >= a for a, b in zip(gains, gains[1:]))


@pytest.mark.parametrize("turn_deg", [2.0, 7.5, 20.0, 40.0])
def test_prediction_inverts_the_gain_when_fitted_consistently(turn_deg):
    curve = TurnGain(min_gain=0.05, offset_deg=2.0, span_deg=38.0, predicted_base_deg=2.0, predicted_slope_deg=38.0)
    assert curve.predicted_turn_deg(curve.gain(turn_deg)) == pytest.approx(turn_deg)
