"""Frames and angles: the team frame (point reflection for the right team), egocentric <-> team, angle wrap.

* World frame: REFERENCE §1, the left team's goal at x = -15.
* Team frame: the agent's own frame, own goal at -x; equal to the world frame for the left team and its
  point reflection (x, y -> -x, -y; headings + 180°) for the right team. Beam and hear use it.
* Egocentric frame: origin at the torso's ground projection, x = the robot's forward direction projected on
  the ground, y = left, z up. (SimSpark body axes are x right, y forward: ego = (body y, -body x).)
A pose is (x, y, heading) in the team frame, heading = direction of the ego x axis, rad, counter-clockwise
from the team frame's +x.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

TWO_PI = 2.0 * math.pi


def wrap_angle_rad(angle_rad: float) -> float:
    """The angle in [-pi, pi)."""
    return (angle_rad + math.pi) % TWO_PI - math.pi


def circular_mean_rad(angles_rad: list[float] | tuple[float, ...], weights: list[float] | None = None) -> float:
    """Weighted circular mean of angles [rad]; 0.0 for an empty input."""
    if not angles_rad:
        return 0.0
    w = weights or [1.0] * len(angles_rad)
    s = sum(wi * math.sin(a) for wi, a in zip(w, angles_rad))
    c = sum(wi * math.cos(a) for wi, a in zip(w, angles_rad))
    return math.atan2(s, c)


@dataclass(frozen=True, slots=True)
class Pose2D:
    """A robot pose in the team frame."""

    x_m: float
    """Torso ground projection x [m], team frame."""
    y_m: float
    """Torso ground projection y [m], team frame."""
    heading_rad: float
    """Direction of the robot's forward axis [rad], counter-clockwise from the team frame's +x, in [-pi, pi)."""

    def to_team(self, forward_m: float, left_m: float) -> tuple[float, float]:
        """An egocentric ground point -> team frame (x, y) [m]."""
        c, s = math.cos(self.heading_rad), math.sin(self.heading_rad)
        return (self.x_m + c * forward_m - s * left_m, self.y_m + s * forward_m + c * left_m)

    def to_ego(self, x_m: float, y_m: float) -> tuple[float, float]:
        """A team-frame point -> egocentric (forward, left) [m]."""
        dx, dy = x_m - self.x_m, y_m - self.y_m
        c, s = math.cos(self.heading_rad), math.sin(self.heading_rad)
        return (c * dx + s * dy, -s * dx + c * dy)

    def distance_to(self, x_m: float, y_m: float) -> float:
        """Ground distance to a team-frame point [m]."""
        return math.hypot(x_m - self.x_m, y_m - self.y_m)


@dataclass(frozen=True, slots=True)
class TeamFrame:
    """Conversions between the world frame and one team's frame (involutions: the same map both ways)."""

    side: str
    """``left`` or ``right`` (an unknown side is treated as left until the server says otherwise)."""

    @property
    def sign(self) -> float:
        """+1 for the left team, -1 for the right team."""
        return -1.0 if self.side == "right" else 1.0

    def point_from_world(self, x_m: float, y_m: float) -> tuple[float, float]:
        """World (x, y) -> team (x, y)."""
        s = self.sign
        return (s * x_m, s * y_m)

    def point_to_world(self, x_m: float, y_m: float) -> tuple[float, float]:
        """Team (x, y) -> world (x, y)."""
        return self.point_from_world(x_m, y_m)

    def heading_from_world(self, heading_rad: float) -> float:
        """World heading -> team heading [rad]."""
        return wrap_angle_rad(heading_rad + (math.pi if self.side == "right" else 0.0))

    def heading_to_world(self, heading_rad: float) -> float:
        """Team heading -> world heading [rad]."""
        return self.heading_from_world(heading_rad)

    def pose_from_world(self, pose: Pose2D) -> Pose2D:
        """A world-frame pose -> team frame."""
        x, y = self.point_from_world(pose.x_m, pose.y_m)
        return Pose2D(x, y, self.heading_from_world(pose.heading_rad))

    def pose_to_world(self, pose: Pose2D) -> Pose2D:
        """A team-frame pose -> world frame."""
        return self.pose_from_world(pose)
