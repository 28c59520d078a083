"""Heading from landmark bearings (REFERENCE §7.5 step 3): θ = world bearing(pose → landmark) − observed bearing.

The observed bearings here already include the head yaw hj1 (and the torso tilt): they are egocentric,
measured from the camera's ground point (:class:`agent.world.vision.GroundObservation`).
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping

from agent.world.frames import circular_mean_rad, wrap_angle_rad
from agent.world.vision import GroundObservation


def heading_from_bearings(camera_xy: tuple[float, float], observations: Iterable[tuple[str, GroundObservation]],
                          landmarks: Mapping[str, tuple[float, float]]) -> float | None:
    """Circular mean over landmarks of (world bearing from the camera point − observed bearing) [rad].

    Args:
        camera_xy: the camera's ground point in the team frame [m].
        observations: (landmark name, observation) pairs.
        landmarks: landmark name -> team-frame (x, y) [m].

    Returns:
        The heading in [-pi, pi), or None if no observation names a known landmark.
    """
    cx, cy = camera_xy
    headings = []
    for name, obs in observations:
        lx, ly = landmarks[name]
        headings.append(wrap_angle_rad(math.atan2(ly - cy, lx - cx) - obs.bearing_rad))
    return wrap_angle_rad(circular_mean_rad(headings)) if headings else None
