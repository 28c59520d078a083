"""The rule numbers of rcssserver3d 0.7.3 (REFERENCE §4, naosoccersim.rb): field, play modes, fouls, timers.

Every number here is a server parameter; the referee reads them from one `RefereeConfig` so tests and tools
can change them by name (`default_config(drop_ball_time_s=5.0)`).
"""

from __future__ import annotations

import dataclasses
import enum
from dataclasses import dataclass
from agent.protocol.constants import (AGENT_RADIUS_M, BALL_MASS_KG, BALL_RADIUS_M, CENTRE_CIRCLE_RADIUS_M, CYCLE_S,
                                      DROP_BALL_TIME_S, FIELD_LENGTH_M, FIELD_WIDTH_M, GOAL_DEPTH_M, GOAL_HEIGHT_M,
                                      GOAL_WIDTH_M, PENALTY_DEPTH_M)

# REFERENCE §4.2: the index is what monitors use.
PLAY_MODES: tuple[str, ...] = (
    "BeforeKickOff", "KickOff_Left", "KickOff_Right", "PlayOn", "KickIn_Left", "KickIn_Right",
    "corner_kick_left", "corner_kick_right", "goal_kick_left", "goal_kick_right", "offside_left",
    "offside_right", "GameOver", "Goal_Left", "Goal_Right", "free_kick_left", "free_kick_right",
    "direct_free_kick_left", "direct_free_kick_right", "pass_left", "pass_right",
)
PLAY_MODE_INDEX: dict[str, int] = {name: index for index, name in enumerate(PLAY_MODES)}

LEFT = "left"
RIGHT = "right"
SIDES = (LEFT, RIGHT)


def opponent(side: str) -> str:
    """The other side: "left" <-> "right"."""
    return RIGHT if side == LEFT else LEFT


def side_suffix(side: str) -> str:
    """Play-mode suffix of a side as the server spells it in CamelCase modes ("Left"/"Right")."""
    return "Left" if side == LEFT else "Right"


def team_number(side: str) -> int:
    """Team index on the monitor wire: 1 = left, 2 = right (REFERENCE §4.5 foul report)."""
    return 1 if side == LEFT else 2


class FoulType(enum.IntEnum):
    """Foul type numbers of REFERENCE §4.5 (the server's EFoulType)."""

    CROWDING = 0
    TOUCHING = 1
    ILLEGAL_DEFENCE = 2
    ILLEGAL_ATTACK = 3
    INCAPABLE = 4
    KICK_OFF = 5
    CHARGING = 6
    SELF_COLLISION = 7


@dataclass(frozen=True)
class RefereeConfig:
    """Server parameters the referee uses (names follow naosoccersim.rb; units in the names).

    Field geometry [m]: field_length_m, field_width_m, goal_width_m, goal_height_m, goal_depth_m,
    penalty_length_m (area depth), penalty_width_m (area width minus the goal width, as the server adds them),
    ball_radius_m, agent_radius_m, free_kick_distance_m (centre circle / set-piece clearance),
    free_kick_move_dist_m (how far cleared players are put), kick_repel_dist_m (kickers near the placed ball),
    goal_kick_dist_m (goal-kick spot from the goal line).
    Timing [s]: cycle_s, half_time_s, goal_pause_time_s, kick_in_pause_time_s, drop_ball_time_s,
    wait_before_kick_off_s (automatic kick-off), foul_hold_time_s (lifted before the outside placement).
    Fouls: not_standing_max_time_s, ground_max_time_s and the goalie versions, max_players_inside_own_area,
    max_touch_group_size, charging_* (REFERENCE §4.5), self_collision_* (tolerance [m], frozen/thaw [s]).
    Switches: automatic_kick_off, coin_toss_for_kick_off, use_charging, foul_on_self_collisions,
    start_any_field_position.
    """

    field_length_m: float = FIELD_LENGTH_M
    field_width_m: float = FIELD_WIDTH_M
    field_height_m: float = 40.0
    goal_width_m: float = GOAL_WIDTH_M
    goal_depth_m: float = GOAL_DEPTH_M
    goal_height_m: float = GOAL_HEIGHT_M
    border_size_m: float = 0.0
    penalty_length_m: float = PENALTY_DEPTH_M
    penalty_width_m: float = 3.9
    ball_radius_m: float = BALL_RADIUS_M
    ball_mass_kg: float = BALL_MASS_KG
    agent_radius_m: float = AGENT_RADIUS_M
    free_kick_distance_m: float = CENTRE_CIRCLE_RADIUS_M
    free_kick_move_dist_m: float = 2.5
    kick_repel_dist_m: float = 0.5
    goal_kick_dist_m: float = 1.0

    cycle_s: float = CYCLE_S
    half_time_s: float = 300.0
    goal_pause_time_s: float = 3.0
    kick_in_pause_time_s: float = 1.0
    drop_ball_time_s: float = DROP_BALL_TIME_S
    wait_before_kick_off_s: float = 30.0
    foul_hold_time_s: float = 0.5

    automatic_kick_off: bool = False
    coin_toss_for_kick_off: bool = False
    start_any_field_position: bool = False

    not_standing_max_time_s: float = 30.0
    goalie_not_standing_max_time_s: float = 60.0
    ground_max_time_s: float = 15.0
    goalie_ground_max_time_s: float = 30.0
    not_standing_z_m: float = 0.25
    on_ground_z_m: float = 0.15
    max_players_inside_own_area: int = 3
    max_touch_group_size: int = 2

    use_charging: bool = True
    charging_min_speed_m_s: float = 0.4
    charging_min_ball_speed_angle_deg: float = 30.0
    charging_min_delta_dist_m: float = 0.05
    charging_min_delta_ang_deg: float = 15.0
    charging_immunity_time_s: float = 1.0
    charging_collision_min_time_s: float = 0.2
    charging_max_ball_rules_dist_m: float = 1.0
    charging_min_coll_ball_dist_m: float = 0.1
    charging_min_collision_speed_m_s: float = 0.2
    charging_velocity_samples: int = 3
    moved_immunity_time_s: float = 1.0

    foul_on_self_collisions: bool = True
    self_collision_tolerance_m: float = 0.04
    self_collision_joint_frozen_time_s: float = 1.0
    self_collision_joint_thaw_time_s: float = 2.0

    max_safe_reposition_attempts: int = 100

    pass_mode_max_ball_speed_m_s: float = 0.05
    pass_mode_max_ball_dist_m: float = 0.5
    pass_mode_min_opp_ball_dist_m: float = 1.0
    pass_mode_duration_s: float = 4.0
    pass_mode_score_wait_time_s: float = 10.0
    pass_mode_retry_wait_time_s: float = 3.0

    # Width of a standing robot's footprint around the torso centre, used where the server intersects the
    # agent's bounding rectangle (derived: shoulders at x +-0.133, stretched arms and feet reach 0.2 forward).
    agent_half_extent_m: float = 0.15

    @property
    def half_length_m(self) -> float:
        return self.field_length_m / 2.0

    @property
    def half_width_m(self) -> float:
        return self.field_width_m / 2.0

    @property
    def goal_ball_line_x_m(self) -> float:
        """|x| beyond which the whole ball is behind the goal line (15.042)."""
        return self.half_length_m + self.ball_radius_m

    def penalty_area(self, side: str) -> tuple[float, float, float, float]:
        """(x_min, x_max, y_min, y_max) of ``side``'s own penalty area [m]."""
        half_y = (self.penalty_width_m + self.goal_width_m) / 2.0
        if side == LEFT:
            return (-self.half_length_m, -self.half_length_m + self.penalty_length_m, -half_y, half_y)
        return (self.half_length_m - self.penalty_length_m, self.half_length_m, -half_y, half_y)

    def corner_kick_y_m(self) -> float:
        """|y| of the corner spot: (FieldWidth + GoalWidth)/4 - BallRadius = 5.483 (a 2012 value, REFERENCE §4.4)."""
        return (self.field_width_m + self.goal_width_m) / 4.0 - self.ball_radius_m


def default_config(**overrides: object) -> RefereeConfig:
    """The rcssserver3d 0.7.3 defaults, with named overrides (a TypeError names an unknown field)."""
    return dataclasses.replace(RefereeConfig(), **overrides)


def in_box(x: float, y: float, box: tuple[float, float, float, float]) -> bool:
    """Point inside an (x_min, x_max, y_min, y_max) box, edges included (salt::AABB2::Contains)."""
    return box[0] <= x <= box[1] and box[2] <= y <= box[3]
