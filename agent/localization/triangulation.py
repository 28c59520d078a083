"""Landmark triangulation, REFERENCE §7.5 steps 1-4 (the seed agent's per-frame pose estimate).

1. For each pair of visible flags/goal posts, intersect the circles centred on their team-frame positions
   with radii = the ground distances from the camera (√(d² − Δh²), see :mod:`agent.world.vision`).
2. Of the two intersections keep the one whose bearings give the observed left-right order of the pair
   (the signed angle from the first to the second landmark); a candidate far outside the field loses a tie.
3. Heading from the bearings (:mod:`agent.localization.heading`).
4. Average the pairs (circular mean for the heading); fewer than 2 landmarks -> no estimate.

The circles are centred on the landmarks and the radii are measured from the camera, so the intersection is
the camera's ground point; the torso's ground point is that minus the camera offset turned by the heading.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Mapping

from agent.localization.heading import heading_from_bearings
from agent.world.frames import Pose2D, circular_mean_rad, wrap_angle_rad
from agent.world.vision import GroundObservation, VisionFrame

#: A candidate farther than this outside the field lines is implausible [m] (walls are at 25 m, REFERENCE §4.1).
FIELD_MARGIN_M = 1.0
_HALF_X, _HALF_Y = 15.0, 10.0


def _outside(x: float, y: float) -> float:
    return max(0.0, abs(x) - _HALF_X - FIELD_MARGIN_M) + max(0.0, abs(y) - _HALF_Y - FIELD_MARGIN_M)


def intersect_pair(a_xy: tuple[float, float], a: GroundObservation, b_xy: tuple[float, float],
                   b: GroundObservation) -> tuple[float, float] | None:
    """The camera ground point seen from landmarks a and b (team frame), or None for coincident landmarks.

    When noise makes the circles miss each other, the point on the line between the centres is used (the
    closest approach), which is what the radii agree on best.
    """
    (ax, ay), (bx, by) = a_xy, b_xy
    dx, dy = bx - ax, by - ay
    d = math.hypot(dx, dy)
    if d < 1e-9:
        return None
    ra, rb = a.range_m, b.range_m
    along = (ra * ra - rb * rb + d * d) / (2.0 * d)
    across = math.sqrt(max(0.0, ra * ra - along * along))
    ux, uy = dx / d, dy / d
    px, py = ax + along * ux, ay + along * uy
    observed = wrap_angle_rad(b.bearing_rad - a.bearing_rad)
    best, best_score = None, math.inf
    for sign in (1.0, -1.0):
        cx, cy = px - sign * across * uy, py + sign * across * ux
        seen = wrap_angle_rad(math.atan2(by - cy, bx - cx) - math.atan2(ay - cy, ax - cx))
        score = abs(wrap_angle_rad(seen - observed)) + _outside(cx, cy)
        if score < best_score:
            best, best_score = (cx, cy), score
    return best


def triangulate(frame: VisionFrame, landmarks: Mapping[str, tuple[float, float]]) -> Pose2D | None:
    """The seed agent's pose estimate from one vision frame.

    Args:
        frame: the projected vision frame.
        landmarks: landmark name -> team-frame (x, y) [m].

    Returns:
        The torso pose in the team frame, or None with fewer than 2 known landmarks in view.
    """
    seen = [(name, obs) for name, obs in frame.landmarks.items() if name in landmarks]
    if len(seen) < 2:
        return None
    xs, ys, headings = [], [], []
    for (name_a, a), (name_b, b) in itertools.combinations(seen, 2):
        camera = intersect_pair(landmarks[name_a], a, landmarks[name_b], b)
        if camera is None:
            continue
        heading = heading_from_bearings(camera, ((name_a, a), (name_b, b)), landmarks)
        if heading is None:
            continue
        xs.append(camera[0])
        ys.append(camera[1])
        headings.append(heading)
    if not xs:
        return None
    heading = wrap_angle_rad(circular_mean_rad(headings))
    camera_x, camera_y = sum(xs) / len(xs), sum(ys) / len(ys)
    c, s = math.cos(heading), math.sin(heading)
    of, ol = frame.camera_offset
    return Pose2D(camera_x - (c * of - s * ol), camera_y - (s * of + c * ol), heading)
