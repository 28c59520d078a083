"""Tuned curve shapes of the dynamic elements: the turn-gain curve through points (monotone, inverted for the
prediction) and the walk-lean command curve (odd in the request)."""

from __future__ import annotations

import pytest

from agent.motion.dynamic import KickDistance, TurnGain, WalkLean, load_dynamic_params


def test_a_turn_gain_curve_through_points_interpolates_and_inverts():
    curve = TurnGain(min_gain=0.05, request_points_deg=(2.0, 20.0, 38.0), curve_gains=(0.05, 0.5, 0.96))
    assert curve.gain(11.0) == pytest.approx(0.275)
    assert curve.gain(-11.0) == pytest.approx(0.275)  # the side comes from the motion
    assert curve.gain(60.0) == 0.96 and curve.gain(0.0) == 0.05
    for turn in (2.0, 7.5, 20.0, 33.0):
        assert curve.predicted_turn_deg(curve.gain(turn)) == pytest.approx(turn)


def test_a_turn_gain_curve_must_rise_and_start_at_min_gain():
    with pytest.raises(ValueError, match="increase strictly"):
        TurnGain(min_gain=0.1, request_points_deg=(2.0, 20.0), curve_gains=(0.1, 0.1))
    with pytest.raises(ValueError, match="min_gain 0.3 must be the curve's first gain 0.1"):
        TurnGain(min_gain=0.3, request_points_deg=(2.0, 20.0), curve_gains=(0.1, 0.5))


def test_the_lean_command_curve_shapes_both_sides_alike():
    lean = WalkLean(joint_offsets_deg={"le1": -4.0}, command_points=(0.0, 0.5, 1.0), command_scale=(0.0, 0.7, 1.0))
    assert lean.offset_deg("left_walk_lean_lle1", 0.5) == pytest.approx(-4.0 * 0.7)
    assert lean.offset_deg("right_walk_lean_rle1", -0.5) == pytest.approx(-4.0 * 0.7)
    assert lean.offset_deg("left_walk_lean_lle1", -0.5) == 0.0  # the other side stays
    assert lean.offset_deg("left_walk_lean_lle1", 1.0) == pytest.approx(-4.0)
    assert lean.offset_deg("left_walk_lean_lle1", 0.25) == pytest.approx(-4.0 * 0.35)


def test_the_shipped_file_has_no_tuned_shapes_yet():
    dynamic = load_dynamic_params()
    assert dynamic.walk_lean.command_points == () and dynamic.turn_gain.request_points_deg == ()


def test_a_kick_distance_request_gets_the_stretch_of_the_nearest_measured_distance():
    table = KickDistance(motions=("kick",), distance_points_m=(1.0, 2.5, 4.0), stretch=(3.0, 2.0, 1.0))
    assert [table.stretch_for(d) for d in (0.2, 1.7, 1.75, 1.8, 3.2, 9.0)] == [3.0, 3.0, 3.0, 2.0, 2.0, 1.0]
    assert table.expected_distance_m(3.3) == 4.0 and table.expected_distance_m(3.2) == 2.5
    assert table.applies("kick", "strike") and not table.applies("kick", "land")
    assert not table.applies("kick_strong", "strike")


@pytest.mark.parametrize(("points", "stretch", "words"), [
    ((1.0, 2.0), (1.0, 2.0), "must not increase"),
    ((1.0, 2.0), (2.0, 0.5), ">= 1"),
    ((2.0, 2.0), (2.0, 1.0), "increase strictly"),
    ((1.0, 2.0), (2.0,), "same non-zero length"),
])
def test_a_kick_distance_table_that_cannot_be_played_is_refused(points, stretch, words):
    with pytest.raises(ValueError, match=words):
        KickDistance(motions=("kick",), distance_points_m=points, stretch=stretch)


def test_the_shipped_kick_distance_table_spans_the_short_passes_to_the_full_kick():
    table = load_dynamic_params().kick_distance
    assert set(table.motions) == {"kick", "kick_left"}
    assert table.stretch[-1] == 1.0  # the longest request plays the kick as authored
    assert table.distance_points_m[0] < 1.5 and table.distance_points_m[-1] > 3.5
