"""Escape-angle obstacle avoidance (agent.skills.avoid, REFERENCE §7.6)."""

from __future__ import annotations

import math

import pytest

from agent.skills.avoid import AvoidConfig, escape_bearing_deg

CONFIG = AvoidConfig(danger_m=0.55)


def test_a_free_path_keeps_the_target_bearing():
    assert escape_bearing_deg((3.0, 1.0), [], CONFIG) == pytest.approx(math.degrees(math.atan2(1.0, 3.0)))
    # beside the path, or beyond the target: no detour
    assert escape_bearing_deg((3.0, 0.0), [(1.0, 1.2)], CONFIG) == pytest.approx(0.0)
    assert escape_bearing_deg((1.0, 0.0), [(1.5, 0.0)], CONFIG) == pytest.approx(0.0)


def test_an_obstacle_ahead_is_passed_at_the_edge_of_its_cone_on_the_shorter_side():
    half = math.degrees(math.asin(0.55 / 1.0))
    bearing = escape_bearing_deg((3.0, 0.3), [(1.0, 0.0)], CONFIG)
    assert bearing == pytest.approx(half)  # the target lies a little left: pass on the left
    bearing = escape_bearing_deg((3.0, -0.3), [(1.0, 0.0)], CONFIG)
    assert bearing == pytest.approx(-half)


def test_a_second_obstacle_closes_one_side():
    # Obstacles ahead and ahead-left: the left edges lie inside the other cone or are longer; go right.
    bearing = escape_bearing_deg((3.0, 0.0), [(1.0, 0.0), (1.2, 0.6)], CONFIG)
    assert bearing < 0.0


def test_surrounded_stands():
    ring = [(0.4 * math.cos(a), 0.4 * math.sin(a)) for a in (0.0, 2.1, 4.2)]
    assert escape_bearing_deg((3.0, 0.0), ring, CONFIG) is None


def test_hysteresis_keeps_the_previous_side_while_it_is_nearly_as_short():
    half = math.degrees(math.asin(0.55 / 1.0))
    # Target a hair to the right: alone it would pass right, but the walk already goes left.
    assert escape_bearing_deg((3.0, -0.02), [(1.0, 0.0)], CONFIG) == pytest.approx(-half)
    assert escape_bearing_deg((3.0, -0.02), [(1.0, 0.0)], CONFIG, previous_deg=half) == pytest.approx(half)
