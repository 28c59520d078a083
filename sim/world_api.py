"""The contract between the physics world and the rules: what the referee and hosts may ask of the world.

Why a Protocol: the referee (rules of REFERENCE §4) is written against these calls only, so it never
touches MuJoCo arrays and the world can change its internals (substeps, layout) without breaking it.
All positions are in the world (field) frame of REFERENCE §1, metres; angles in degrees where noted.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Protocol


@dataclass(frozen=True)
class RobotState:
    """One robot as the referee sees it.

    team: "left" or "right"; unum: 1-11; robot_type: 0-4.
    torso_pos_m: torso centre (x, y, z) in the field frame.
    torso_vel_m_s: torso linear velocity in the field frame.
    torso_up_z: z component of the torso's up axis (1 upright, < 0.6 counts as fallen in benchmarks).
    heading_deg: torso yaw, 0 = facing +x (the field frame).
    """

    team: str
    unum: int
    robot_type: int
    torso_pos_m: tuple[float, float, float]
    torso_vel_m_s: tuple[float, float, float]
    torso_up_z: float
    heading_deg: float


class WorldView(Protocol):
    """What the referee needs from the physics world each cycle."""

    def ball_position(self) -> tuple[float, float, float]: ...

    def ball_velocity(self) -> tuple[float, float, float]: ...

    def set_ball(self, position_m: tuple[float, float, float],
                 velocity_m_s: tuple[float, float, float] = (0.0, 0.0, 0.0)) -> None: ...

    def robots(self) -> list[RobotState]: ...

    def move_robot(self, team: str, unum: int, x_m: float, y_m: float, heading_deg: float | None = None,
                   z_m: float = 0.4) -> None:
        """Place a robot upright (as beam does: rigid pose, velocities zeroed)."""

    def shift_robot(self, team: str, unum: int, x_m: float, y_m: float) -> None:
        """Translate a robot as it stands (posture, orientation, height kept; velocities zeroed): SimSpark's
        MoveAgent, with which its referee clears players."""

    def ball_touchers(self) -> list[tuple[str, int]]:
        """(team, unum) of robots whose geoms touch the ball in the last physics step."""

    def touching_robot_pairs(self) -> list[tuple[tuple[str, int], tuple[str, int]]]:
        """Pairs of robots in physical contact in the last physics step."""

    def freeze_joints(self, team: str, unum: int, effectors: list[str]) -> None:
        """Set these joints' target velocity to 0 (self-collision rule)."""
