"""One vision frame, from head-frame polar coordinates to the egocentric ground frame.

Chain (REFERENCE §3.5, §2.3): the camera sits at the head centre; a seen point's head-frame vector is
rel = (−d cosφ sinθ, d cosφ cosθ, d sinφ) in SimSpark axes (x right, y forward), since θ = atan2(y, x) − 90°.
The torso-frame vector is cam_pos + R_cam·rel (R_cam, cam_pos from the head joints hj1, hj2 via
:class:`~agent.world.body_model.BodyModel`), and the tilt (roll/pitch from the orientation filter) turns it
into the gravity-aligned frame whose yaw is the robot's heading. Ego = (forward, left) = (g_y, −g_x).

Distances on the ground: for points of known height z (flags, goal-post tops, the ball, lines) the ground
distance from the camera's ground point is √(d² − (h − z)²) with h the camera height above the soles
(REFERENCE §7.5 step 6; the thesis prints + by mistake). This is insensitive to tilt errors at the ranges
that matter; the bearing comes from the rotated direction. Close to the feet the sight line is steep and the
square root amplifies errors of h and d (d(range)/dh = -(h - z)/range: about 3 for a ball 0.15 m ahead, so
the 5 mm calibration error alone moved such a ball by up to 4 cm on our simulator); there the horizontal
length of the rotated vector is used, blended in between STEEP_FROM_DEG and STEEP_TO_DEG of depression
(measured: errors 3-5 cm -> under 1 cm for a ball 0.12-0.15 m ahead). Players' parts have no known height,
so they use the rotated 3-D vector.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from agent.protocol.perceptors import See
from agent.world import mat3
from agent.world.field import BALL_RADIUS_M, LANDMARKS

Ego = tuple[float, float]
_DEG = math.pi / 180.0
#: Depression of the sight line [deg] from which the rotated vector's horizontal length takes over from the
#: square-root range (linear blend up to STEEP_TO_DEG).
STEEP_FROM_DEG = 35.0
STEEP_TO_DEG = 55.0


@dataclass(frozen=True, slots=True)
class GroundObservation:
    """A seen point on (or at a known height above) the ground, egocentric."""

    range_m: float
    """Ground distance from the camera's ground point [m]."""
    bearing_rad: float
    """Direction from the camera's ground point [rad], 0 = forward, positive to the left."""
    forward_m: float
    """Ego x of the point: forward of the torso's ground projection [m]."""
    left_m: float
    """Ego y of the point: left of the torso's ground projection [m]."""
    distance_m: float
    """Raw 3-D distance from the camera as seen [m] (sets the noise level)."""


@dataclass(frozen=True, slots=True)
class SeenPlayer:
    """A robot seen this frame (own parts excluded)."""

    team: str
    """Team name as given at init."""
    unum: int | None
    """Uniform number, None when not sent."""
    forward_m: float
    """Ego x [m] (head if seen, else the mean of the visible parts)."""
    left_m: float
    """Ego y [m]."""
    parts: tuple[str, ...]
    """Visible part names."""


@dataclass(frozen=True, slots=True)
class VisionFrame:
    """Everything one ``See`` tells, in the egocentric frame."""

    time_s: float
    """Server time of the frame [s]."""
    camera_height_m: float
    """Camera height above the lowest sole corner [m]."""
    camera_offset: Ego
    """Ego position of the camera's ground point [m] (a few cm from the torso's when the torso leans)."""
    landmarks: dict[str, GroundObservation]
    """Flags and goal posts by name."""
    ball: GroundObservation | None
    """The ball, if seen."""
    players: tuple[SeenPlayer, ...]
    """Other robots, both teams."""
    lines: tuple[tuple[Ego, Ego], ...] = field(default=())
    """Field-line segments as ego end points [m]."""


def _head_vector(d: float, theta_deg: float, phi_deg: float) -> mat3.Vector:
    t, p = math.radians(theta_deg), math.radians(phi_deg)
    cp = math.cos(p)
    return (-d * cp * math.sin(t), d * cp * math.cos(t), d * math.sin(p))


class _Projector:
    """Head polar -> ego for one frame: R = tilt·R_cam, camera position c = tilt·cam_pos."""

    def __init__(self, tilt: mat3.Matrix, cam_rotation: mat3.Matrix, cam_position: mat3.Vector,
                 camera_height_m: float) -> None:
        self.rotation = mat3.matmul(tilt, cam_rotation)
        self.camera = mat3.apply(tilt, cam_position)
        self.height = camera_height_m
        self.offset: Ego = (self.camera[1], -self.camera[0])

    def ground(self, d: float, theta_deg: float, phi_deg: float, z_m: float) -> GroundObservation:
        gx, gy, gz = mat3.apply(self.rotation, _head_vector(d, theta_deg, phi_deg))
        dh = self.height - z_m
        horizontal = math.hypot(gx, gy)
        squared = d * d - dh * dh
        # Below |dh| (noise on a point right under the camera) fall back on the rotated vector.
        rng = math.sqrt(squared) if squared > 0.0 and horizontal > 1e-9 else horizontal
        depression_deg = math.degrees(math.atan2(-gz, horizontal))
        if depression_deg > STEEP_FROM_DEG:  # steep: the rotated vector is the better range (module docstring)
            weight = min(1.0, (depression_deg - STEEP_FROM_DEG) / (STEEP_TO_DEG - STEEP_FROM_DEG))
            rng += weight * (horizontal - rng)
        bearing = math.atan2(-gx, gy)
        forward = self.offset[0] + rng * math.cos(bearing)
        left = self.offset[1] + rng * math.sin(bearing)
        return GroundObservation(rng, bearing, forward, left, d)

    def ground_point(self, d: float, theta_deg: float, phi_deg: float) -> Ego:
        """Ego (forward, left) of a seen point on the ground (z = 0): :meth:`ground` without the record, for
        the ~40 line end points per frame."""
        t, p = theta_deg * _DEG, phi_deg * _DEG
        cp = math.cos(p)
        hx, hy, hz = -d * cp * math.sin(t), d * cp * math.cos(t), d * math.sin(p)
        (r0, r1, r2) = self.rotation
        gx = r0[0] * hx + r0[1] * hy + r0[2] * hz
        gy = r1[0] * hx + r1[1] * hy + r1[2] * hz
        horizontal = math.hypot(gx, gy)
        squared = d * d - self.height * self.height
        rng = math.sqrt(squared) if squared > 0.0 and horizontal > 1e-9 else horizontal
        if horizontal <= 1e-9:
            return self.offset
        scale = rng / horizontal
        return (self.offset[0] + gy * scale, self.offset[1] - gx * scale)

    def free(self, d: float, theta_deg: float, phi_deg: float) -> Ego:
        gx, gy, _ = mat3.apply(self.rotation, _head_vector(d, theta_deg, phi_deg))
        return (self.offset[0] + gy, self.offset[1] - gx)


def _finite3(a: float, b: float, c: float) -> bool:
    """All three finite (as ``math.isfinite`` each), without a generator: x * 0.0 is 0.0 for a finite x and NaN
    for an infinite or NaN one, and a sum with a NaN is NaN (this runs for every sighting of every frame)."""
    return a * 0.0 + b * 0.0 + c * 0.0 == 0.0


def vision_frame(see: See, time_s: float, tilt: mat3.Matrix, cam_rotation: mat3.Matrix,
                 cam_position: mat3.Vector, camera_height_m: float, own_team: str | None,
                 own_unum: int | None) -> VisionFrame:
    """Project one ``See`` into the ego frame.

    Args:
        see: the parsed vision predicate.
        time_s: server time of the message [s].
        tilt: torso orientation with yaw removed (3x3).
        cam_rotation, cam_position: camera pose in the torso frame (from the head joint angles).
        camera_height_m: camera height above the soles [m].
        own_team, own_unum: to drop the agent's own arms and feet, which it sees as a player.
    """
    projector = _Projector(tilt, cam_rotation, cam_position, camera_height_m)
    landmarks: dict[str, GroundObservation] = {}
    ball = None
    for obj in see.objects:
        if not _finite3(obj.distance_m, obj.azimuth_deg, obj.elevation_deg):
            continue  # the real server can send (pol nan nan nan); such a sighting tells nothing
        if obj.name == "B":
            ball = projector.ground(obj.distance_m, obj.azimuth_deg, obj.elevation_deg, BALL_RADIUS_M)
        else:
            position = LANDMARKS.get(obj.name)
            if position is not None:
                landmarks[obj.name] = projector.ground(obj.distance_m, obj.azimuth_deg, obj.elevation_deg,
                                                       position[2])
    players = []
    for player in see.players:
        if player.team == own_team and player.unum == own_unum:
            continue
        parts = {name: polar for name, polar in player.parts.items() if _finite3(*polar)}
        if "head" in parts:
            forward, left = projector.free(*parts["head"])
        else:
            points = [projector.free(*polar) for polar in parts.values()]
            if not points:
                continue
            forward = sum(p[0] for p in points) / len(points)
            left = sum(p[1] for p in points) / len(points)
        players.append(SeenPlayer(player.team, player.unum, forward, left, tuple(parts)))
    point = projector.ground_point
    lines = [(point(*line.begin), point(*line.end)) for line in see.lines
             if _finite3(*line.begin) and _finite3(*line.end)]
    return VisionFrame(time_s, camera_height_m, projector.offset, landmarks, ball, tuple(players), tuple(lines))
