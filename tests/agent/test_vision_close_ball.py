"""Close to the feet the ball's range comes from the rotated sight line, not from √(d² − (h − z)²), which
amplifies camera-height errors about threefold for a ball 0.15 m ahead (agent/world/vision.py)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from agent.world.field import BALL_RADIUS_M
from agent.world.vision import _Projector


def _polar(rel: np.ndarray) -> tuple[float, float, float]:
    """Head-frame vector (x right, y forward, z up) -> SimSpark (d, θ, φ) in degrees."""
    d = float(np.linalg.norm(rel))
    theta = math.degrees(math.atan2(rel[1], rel[0])) - 90.0
    phi = math.degrees(math.atan2(rel[2], math.hypot(rel[0], rel[1])))
    return d, theta, phi


@pytest.mark.parametrize("forward_m, left_m", [(0.12, -0.03), (0.15, -0.05), (0.15, 0.0), (0.25, 0.05)])
@pytest.mark.parametrize("height_error_m", [-0.01, 0.01])
def test_ball_at_the_feet_is_placed_within_a_centimetre_despite_a_camera_height_error(forward_m, left_m,
                                                                                       height_error_m):
    height = 0.48
    pitch = math.radians(-45.0)  # head pitched down: camera forward axis rotated about x
    c, s = math.cos(pitch), math.sin(pitch)
    rotation = ((1.0, 0.0, 0.0), (0.0, c, -s), (0.0, s, c))
    camera = np.array([0.0, 0.0, height])
    ball = np.array([-left_m, forward_m, BALL_RADIUS_M])  # SimSpark axes: x right, y forward
    rel = np.array(rotation).T @ (ball - camera)
    projector = _Projector(((1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0)), rotation, (0.0, 0.0, 0.0),
                           height + height_error_m)
    seen = projector.ground(*_polar(rel), BALL_RADIUS_M)
    assert math.hypot(seen.forward_m - forward_m, seen.left_m - left_m) < 0.01


def test_far_points_keep_the_square_root_range():
    """A flag 5 m away at a shallow angle: the range is √(d² − (h − z)²) exactly (tilt-insensitive)."""
    height, z = 0.48, 0.0
    rel = np.array([0.0, 5.0, z - height])
    projector = _Projector(((1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0)),
                           ((1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0)), (0.0, 0.0, 0.0), height)
    seen = projector.ground(*_polar(rel), z)
    assert seen.forward_m == pytest.approx(5.0, abs=1e-9)
