"""The referee: play modes, kick-off, goals, set pieces, halves and the automatic fouls of REFERENCE §4.

It follows rcssserver3d 0.7.3's GameStateAspect, BallStateAspect and SoccerRuleAspect, and acts on the world
only through `sim.world_api.WorldView`. The engine calls `update(world)` once per 20 ms cycle, after the
physics step; `on_init`, `on_leave`, `allows_beam` and `request_pass` serve the agents' effectors;
`kick_off`, `set_play_mode`, `drop_ball`, `set_game_time` and `set_score` serve the trainer commands.
"""

from __future__ import annotations

import logging
import math
import random
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass

from sim.rules.ball import ball_on_field, goal_of
from sim.rules.fouls import FoulRecord, FoulTracker
from sim.rules.params import (LEFT, PLAY_MODE_INDEX, PLAY_MODES, RIGHT, SIDES, FoulType, RefereeConfig,
                              default_config, in_box, opponent, side_suffix, team_number)
from sim.rules.pass_mode import PassModeTracker
from sim.rules.placement import Key, Placer, in_opponent_half
from sim.rules.roster import Assignment, Roster
from sim.rules.self_collision import SelfCollisionRule
from sim.world_api import RobotState, WorldView
from sim.errors import RuleError

logger = logging.getLogger(__name__)

# Modes where a set piece waits for the first touch, with (side, is_indirect) per mode.
_SET_PIECES: dict[str, tuple[str, str, bool]] = {
    "KickIn_Left": ("kick_in", LEFT, True), "KickIn_Right": ("kick_in", RIGHT, True),
    "free_kick_left": ("free_kick", LEFT, True), "free_kick_right": ("free_kick", RIGHT, True),
    "offside_left": ("free_kick", LEFT, True), "offside_right": ("free_kick", RIGHT, True),
    "direct_free_kick_left": ("free_kick", LEFT, False), "direct_free_kick_right": ("free_kick", RIGHT, False),
    "goal_kick_left": ("goal_kick", LEFT, False), "goal_kick_right": ("goal_kick", RIGHT, False),
    "corner_kick_left": ("corner_kick", LEFT, False), "corner_kick_right": ("corner_kick", RIGHT, False),
}
# A set-piece kick is one touch; a second touch by the taker within this window is the same kick [s].
_KICK_DURATION_S = 0.1
# A touch must come this long after the set-piece pause to count (server: pause + 0.03) [s].
_TOUCH_DELAY_PAD_S = 0.03

@dataclass(frozen=True)
class Foul:
    """A foul as monitors see it: ``(foul index type team unum)`` with team 1 = left, 2 = right.

    index: 1-based running number; type: REFERENCE §4.5 foul type; team: "left"/"right"; unum: 1-11;
    game_time_s: game time of the call.
    """

    index: int
    type: FoulType
    team: str
    unum: int
    game_time_s: float

    def monitor_tuple(self) -> tuple[int, int, int, int]:
        return (self.index, int(self.type), team_number(self.team), self.unum)


@dataclass(frozen=True)
class RefereeEvent:
    """Something the referee decided: kind "play_mode" (play_mode is the new mode), "goal" (team scored)
    or "foul" (foul set). game_time_s: game time of the decision."""

    kind: str
    game_time_s: float
    play_mode: str
    team: str | None = None
    foul: Foul | None = None


@dataclass
class _Touch:
    key: Key
    game_time_s: float


class Referee:
    """Game state and rules; see the module docstring.

    Args:
        config: rule parameters (`sim.rules.params.default_config()` if None).
        seed: seed of the referee's random choices (coin toss, player order); None = nondeterministic.
    """

    def __init__(self, config: RefereeConfig | None = None, seed: int | None = None) -> None:
        self.config = config or default_config()
        self.rng = random.Random(seed)
        self.play_mode_index = PLAY_MODE_INDEX["BeforeKickOff"]
        self.game_time_s = 0.0
        self.half = 1
        self.score_left = 0
        self.score_right = 0
        self.events: list[RefereeEvent] = []
        self.fouls: list[Foul] = []
        self.paused = True
        self.cycle = 0

        self._lead_time_s = 0.0
        self._fup_time_s = 0.0
        self._last_mode_change_s = 0.0
        self._last_kick_off_half: int | None = None
        self._next_half_kick_off: str | None = None if self.config.coin_toss_for_kick_off else LEFT

        r = self.config.ball_radius_m
        self._ball_pos: tuple[float, float, float] = (0.0, 0.0, r)
        self._ball_vel: tuple[float, float, float] = (0.0, 0.0, 0.0)
        self._ball_on_field = True
        self._last_valid_ball: tuple[float, float, float] = (0.0, 0.0, r)
        self._free_kick_pos: tuple[float, float, float] = (0.0, 0.0, r)
        self._last_touch: _Touch | None = None
        self._touching: list[Key] = []
        self._robots: list[RobotState] = []
        self._repel_for_kick = False

        self._allow_kick_off_team_to_score = True
        self._kick_off_taker: Key | None = None
        self._check_taker_foul = False
        self._free_kick_time_s = 0.0
        self._free_kick_taker: Key | None = None
        self._indirect_kick = False

        self.roster = Roster(self.config)
        self.pass_mode = PassModeTracker(self.config)
        self.fouls_tracker = FoulTracker(self.config)
        # Body poses for the self-collision rule (sim.engine.SimEngine sets its cheap array views here); when
        # None, the world's own ``robot_body_poses()`` if it has one, else the rule is off.
        self.body_pose_source: Callable[[], Sequence[tuple[str | None, int, int, Mapping[str, object]]]] | None = None
        self.self_collisions = SelfCollisionRule(self.config.self_collision_tolerance_m,
                                                 self.config.self_collision_joint_frozen_time_s,
                                                 self.config.self_collision_joint_thaw_time_s)

    # ---- public state --------------------------------------------------------------------------------
    @property
    def play_mode(self) -> str:
        """The REFERENCE §4.2 string of the current play mode."""
        return PLAY_MODES[self.play_mode_index]

    @property
    def mode_time_s(self) -> float:
        """Time in the current mode [s] (lead time before kick-off, follow-up time after the game)."""
        if self.play_mode == "BeforeKickOff":
            return self._lead_time_s
        if self.play_mode == "GameOver":
            return self._fup_time_s
        return self.game_time_s - self._last_mode_change_s

    @property
    def team_names(self) -> dict[str, str | None]:
        """Team name per side ("left"/"right"), None until a team's first init."""
        return self.roster.team_names

    def allows_beam(self) -> bool:
        """Beam is accepted only in BeforeKickOff, Goal_Left and Goal_Right (REFERENCE §3.7)."""
        return self.play_mode in ("BeforeKickOff", "Goal_Left", "Goal_Right")

    def score(self, side: str) -> int:
        return self.score_left if side == LEFT else self.score_right

    # ---- agents --------------------------------------------------------------------------------------
    def on_init(self, team: str, unum: int, robot_type: int = 0) -> Assignment | None:
        """Hand out a uniform (REFERENCE §3.2): the first team name seen plays left, the second right.

        Args:
            team: the agent's team name; unum: requested number, 0 = next free; robot_type: 0-4.
        Returns:
            the side, number and init spot, or None when the team, number or robot type is refused
            (logged; the agent then plays without team and number, as on the real server).
        """
        return self.roster.assign(team, unum, robot_type)

    def on_leave(self, side: str, unum: int, robot_type: int = 0) -> None:
        """Return a uniform when its agent disconnects."""
        self.roster.release(side, unum, robot_type)
        self.fouls_tracker.forget((side, unum))

    # ---- trainer commands ----------------------------------------------------------------------------
    def kick_off(self, side: str | None) -> None:
        """Start play: "Left"/"left", "Right"/"right", or None/"None" (coin toss or half alternation)."""
        chosen = _parse_side(side)
        if chosen is None:
            chosen = self.rng.choice(SIDES)
            if self.half != self._last_kick_off_half:
                if self._next_half_kick_off is not None:
                    chosen = self._next_half_kick_off
                self._next_half_kick_off = opponent(chosen)
        self._set_mode(f"KickOff_{side_suffix(chosen)}")
        self._last_kick_off_half = self.half

    def set_play_mode(self, name: str) -> None:
        """Set a play mode by its §4.2 name (trainer ``(playMode ...)``).

        Raises:
            ValueError: unknown name (the message lists the known ones).
        """
        if name not in PLAY_MODE_INDEX:
            raise RuleError(f"unknown play mode {name!r}; known: {', '.join(PLAY_MODES)}", cycle=self.cycle)
        self._set_mode(name)

    def set_game_time(self, time_s: float) -> None:
        """Trainer ``(time t)``."""
        self.game_time_s = float(time_s)

    def set_score(self, left: int | None = None, right: int | None = None) -> None:
        """Trainer ``(score (left n)(right n))``."""
        if left is not None:
            self.score_left = int(left)
        if right is not None:
            self.score_right = int(right)

    def drop_ball(self, world: WorldView, position: tuple[float, float, float] | None = None) -> None:
        """Drop the ball (trainer ``(dropBall)`` or the 15 s rule): not in a penalty area nor outside the
        field, both teams cleared from the free-kick circle, PlayOn."""
        c = self.config
        x, y, z = position if position is not None else world.ball_position()
        for side in SIDES:
            area = c.penalty_area(side)
            if in_box(x, y, area):
                x = area[1] if side == LEFT else area[0]
                y = area[2] if y < 0 else area[3]
        if y <= -c.half_width_m:
            y = -c.half_width_m + c.ball_radius_m
        elif y >= c.half_width_m:
            y = c.half_width_m - c.ball_radius_m
        self._move_ball(world, (x, y, z))
        placer = self._placer(world)
        sides = list(SIDES)
        self.rng.shuffle(sides)
        for side in sides:
            placer.clear_circle((x, y), c.free_kick_distance_m, side)
        self._reset_kick_checks()
        self._set_mode("PlayOn")

    def request_pass(self, side: str, unum: int) -> bool:
        """An agent's ``(pass)``: start pass mode when REFERENCE §4.6 allows it; returns whether it did."""
        if self.play_mode != "PlayOn" or not self.pass_mode.may_start(
                side, unum, self.game_time_s, self._touching, self._ball_pos, self._ball_vel, self._robots):
            return False
        self.pass_mode.ball_at_start[side] = self._ball_pos
        self._set_mode(f"pass_{side}")
        return True

    # ---- the cycle -----------------------------------------------------------------------------------
    def update(self, world: WorldView) -> None:
        """Advance one cycle: clock, ball state, halves, the current mode's rules, then the fouls.

        The order is the server's (GameStateAspect, BallStateAspect, SoccerRuleAspect): the clock moves
        first so a touch in this cycle carries this cycle's time and beats the last mode change.
        """
        self.cycle += 1
        self._advance_clock()
        self._robots = world.robots()
        self._ball_pos = tuple(world.ball_position())  # type: ignore[assignment]
        self._ball_vel = tuple(world.ball_velocity())  # type: ignore[assignment]
        self._update_ball_state(world.ball_touchers())
        self._check_halves()
        self._update_kick_off_scoring()
        mode = self.play_mode
        if mode == "BeforeKickOff":
            self._update_before_kick_off(world)
        elif mode == "PlayOn":
            self._update_play_on(world)
        elif mode in ("KickOff_Left", "KickOff_Right"):
            self._update_kick_off(world, LEFT if mode.endswith("Left") else RIGHT)
        elif mode in _SET_PIECES:
            kind, side, indirect = _SET_PIECES[mode]
            self._update_set_piece(world, kind, side, indirect)
        elif mode in ("pass_left", "pass_right"):
            self._update_pass_mode(world, LEFT if mode.endswith("left") else RIGHT)
        elif mode in ("Goal_Left", "Goal_Right"):
            self._update_goal(world, RIGHT if mode == "Goal_Left" else LEFT)
        elif mode == "GameOver":
            self.paused = False
        self.fouls_tracker.record_velocities(self._robots)
        self._automatic_referee(world)

    def _advance_clock(self) -> None:
        dt = self.config.cycle_s
        if self.play_mode == "BeforeKickOff":
            self._lead_time_s += dt
        elif self.play_mode == "GameOver":
            self._fup_time_s += dt
        else:
            # Rounded so 50 cycles make exactly 1.00 s on the wire after thousands of additions.
            self.game_time_s = round(self.game_time_s + dt, 9)

    def _update_ball_state(self, touchers: list[tuple[str, int]]) -> None:
        c = self.config
        self._touching = [(team, unum) for team, unum in touchers]
        if self._touching:
            self._last_touch = _Touch(self._touching[0], self.game_time_s)
        self._ball_on_field = ball_on_field(self._ball_pos, c)
        if self._ball_on_field:
            self._last_valid_ball = self._ball_pos

    def _check_halves(self) -> None:
        if self.half == 1 and self.game_time_s >= self.config.half_time_s:
            self._set_mode("BeforeKickOff")
            self.half = 2
        elif self.half == 2 and self.game_time_s >= 2 * self.config.half_time_s:
            self._set_mode("GameOver")

    def _update_kick_off_scoring(self) -> None:
        """After a kick-off the kicking team may score only once an opponent touched the ball or a kicker
        touched it outside the centre circle (REFERENCE §4.4)."""
        if self._allow_kick_off_team_to_score or self._kick_off_taker is None:
            return
        team = self._kick_off_taker[0]
        by_kickers = any(key[0] == team for key in self._touching)
        by_opponents = any(key[0] != team for key in self._touching)
        outside = math.hypot(self._ball_pos[0], self._ball_pos[1]) > self.config.free_kick_distance_m
        self._allow_kick_off_team_to_score = by_opponents or (by_kickers and outside)

    # ---- per-mode rules ------------------------------------------------------------------------------
    def _update_before_kick_off(self, world: WorldView) -> None:
        if not self._robots:
            return
        c = self.config
        self._move_ball(world, (0.0, 0.0, c.ball_radius_m))
        self.paused = True
        if not c.start_any_field_position and in_opponent_half(self._robots, c):
            placer = self._placer(world)
            sides = list(SIDES)
            self.rng.shuffle(sides)
            for side in sides:
                placer.clear_box(placer.half(opponent(side)), side)
        if c.automatic_kick_off and self._lead_time_s > c.wait_before_kick_off_s:
            self.kick_off(None)

    def _update_kick_off(self, world: WorldView, side: str) -> None:
        self.paused = False
        self._reset_kick_checks()
        self._allow_kick_off_team_to_score = True
        self._placer(world).clear_before_kick_off(side)
        c = self.config
        if c.drop_ball_time_s > 0 and self.mode_time_s > c.drop_ball_time_s:
            self.drop_ball(world, self._ball_pos)
            return
        touch = self._last_touch
        if touch is not None and touch.game_time_s > self._last_mode_change_s:
            # The server skips the kick-off checks with two agents or fewer ("until a penalty mode exists").
            if len(self._robots) > 2:
                self._set_kick_taken(touch, indirect=True)
                self._kick_off_taker = touch.key
                self._allow_kick_off_team_to_score = False
            self._set_mode("PlayOn")

    def _update_set_piece(self, world: WorldView, kind: str, side: str, indirect: bool) -> None:
        """Kick-in, free kick, goal kick and corner kick: pause, clear, hold the ball, wait for a touch."""
        c = self.config
        self.paused = False
        if self.mode_time_s < c.kick_in_pause_time_s:
            self._repel_for_kick = True
            return
        self._reset_kick_checks()
        placer = self._placer(world)
        if kind == "free_kick":
            x, y, z = self._free_kick_pos
            for area_side in SIDES:
                area = c.penalty_area(area_side)
                if in_box(x, y, area):
                    x = area[1] if area_side == LEFT else area[0]
                    y = area[2] if y < 0 else area[3]
            self._free_kick_pos = (x, y, z)
        spot = (self._free_kick_pos[0], self._free_kick_pos[1])
        if kind == "goal_kick":
            placer.clear_box(c.penalty_area(side), opponent(side))
        else:
            placer.clear_circle(spot, c.free_kick_distance_m, opponent(side))
        if c.drop_ball_time_s > 0 and self.mode_time_s > c.drop_ball_time_s:
            self.drop_ball(world, self._free_kick_pos)
            return
        touch = self._last_touch
        touched = (touch is not None and not self._repel_for_kick and touch.game_time_s
                   > self._last_mode_change_s + c.kick_in_pause_time_s + _TOUCH_DELAY_PAD_S)
        if kind == "goal_kick":
            if touched:
                assert touch is not None
                # PlayOn only once the ball has left the penalty area after the touch.
                bx, by, _ = self._ball_pos
                area = c.penalty_area(side)
                beyond = bx > area[1] if side == LEFT else bx < area[0]
                if not in_box(bx, by, area) and (not self._ball_on_field or beyond or not area[2] <= by <= area[3]):
                    self._set_kick_taken(touch, indirect=False)
                    self._set_mode("PlayOn")
                return
        elif touched:
            assert touch is not None
            self._set_kick_taken(touch, indirect=indirect if kind != "corner_kick" else False)
            self._set_mode("PlayOn")
            return
        if self._repel_for_kick:
            placer.repel(spot, c.kick_repel_dist_m, side, pad=0.0)
            self._repel_for_kick = False
        self._move_ball(world, self._free_kick_pos)

    def _update_pass_mode(self, world: WorldView, side: str) -> None:
        """pass_<side>: PlayOn after a touch or PassModeDuration; meanwhile opponents kept 1 m away."""
        c = self.config
        self.paused = False
        self.pass_mode.in_pass_mode(side, self.game_time_s, self._ball_pos)
        touch = self._last_touch
        if self.mode_time_s >= c.pass_mode_duration_s:
            self._set_mode("PlayOn")
        elif touch is not None and touch.game_time_s >= self._last_mode_change_s:
            self._set_mode("PlayOn")
        self._update_play_on(world)
        if self.play_mode == f"pass_{side}":
            self.pass_mode.ball_at_start[side] = self._ball_pos
            self._placer(world).repel((self._ball_pos[0], self._ball_pos[1]), c.pass_mode_min_opp_ball_dist_m,
                                      opponent(side), pad=0.1)

    def _update_goal(self, world: WorldView, conceding: str) -> None:
        self._placer(world).clear_before_kick_off(conceding)
        self.paused = True
        if self.mode_time_s < self.config.goal_pause_time_s:
            return
        self._move_ball(world, (0.0, 0.0, self.config.ball_radius_m))
        self.kick_off(conceding)

    def _update_play_on(self, world: WorldView) -> None:
        self.paused = False
        self.pass_mode.update(self.game_time_s, self._ball_pos, self._touching)
        if self._check_taker_foul_now():
            return
        if self._check_goal():
            return
        self._check_ball_left_field(world)

    # ---- goals and the ball leaving the field --------------------------------------------------------
    def _check_goal(self) -> bool:
        goal = goal_of(self._ball_pos, self._ball_vel, self.config)
        if goal is None:
            return False
        if not self._allow_kick_off_team_to_score and self._kick_off_taker is not None:
            if goal != self._kick_off_taker[0]:
                self._punish_indirect_goal(self._kick_off_taker, goal)
                return True
        kicker = self._last_kick_from_free_kick()
        if kicker is not None and (self._indirect_kick or kicker[0] == goal) and len(self._robots) > 2:
            self._punish_indirect_goal(kicker, goal)
            return True
        scorer = opponent(goal)
        if self.pass_mode.waiting(scorer, self.game_time_s):
            self._award_goal_kick(goal)
            return True
        if scorer == LEFT:
            self.score_left += 1
        else:
            self.score_right += 1
        self._set_mode(f"Goal_{side_suffix(scorer)}")
        self.events.append(RefereeEvent("goal", self.game_time_s, self.play_mode, team=scorer))
        return True

    def _check_ball_left_field(self, world: WorldView) -> bool:
        c = self.config
        if self._ball_on_field:
            self._free_kick_pos = (self._last_valid_ball[0], self._last_valid_ball[1], c.ball_radius_m)
            return False
        if self._last_touch is None:
            # Nobody ever touched the ball: the server leaves it where it is.
            return True
        last_side = self._last_touch.key[0]
        x, y, _ = self._ball_pos
        if abs(x) >= c.half_length_m:
            ball_side = LEFT if x < 0 else RIGHT
            if last_side == ball_side:
                self._award_corner_kick(opponent(ball_side))
            else:
                self._award_goal_kick(ball_side)
        elif abs(y) >= c.half_width_m:
            self._award_kick_in(opponent(last_side))
        else:
            self._move_ball(world, self._last_valid_ball)
            return False
        return True

    # ---- awards --------------------------------------------------------------------------------------
    def _award_goal_kick(self, side: str) -> None:
        c = self.config
        x = -c.half_length_m + c.goal_kick_dist_m if side == LEFT else c.half_length_m - c.goal_kick_dist_m
        self._free_kick_pos = (x, 0.0, c.ball_radius_m)
        self._repel_for_kick = True
        self._set_mode(f"goal_kick_{side}")

    def _award_corner_kick(self, side: str) -> None:
        c = self.config
        x = c.half_length_m - c.ball_radius_m if side == LEFT else -c.half_length_m + c.ball_radius_m
        y = c.corner_kick_y_m() if self._ball_pos[1] > 0 else -c.corner_kick_y_m()
        self._free_kick_pos = (x, y, c.ball_radius_m)
        self._repel_for_kick = True
        self._set_mode(f"corner_kick_{side}")

    def _award_kick_in(self, side: str) -> None:
        c = self.config
        x, y, _ = self._last_valid_ball
        y = c.half_width_m - c.ball_radius_m if y > 0 else -c.half_width_m + c.ball_radius_m
        self._free_kick_pos = (x, y, c.ball_radius_m)
        self._repel_for_kick = True
        self._set_mode(f"KickIn_{side_suffix(side)}")

    def _award_free_kick(self, side: str, indirect: bool) -> None:
        self._repel_for_kick = True
        self._set_mode(f"{'' if indirect else 'direct_'}free_kick_{side}")

    def _punish_indirect_goal(self, kicker: Key, goal_of: str) -> None:
        """A goal that may not count: own goal -> corner for the opponents, else goal kick for the defenders."""
        self._indirect_kick = False
        if kicker[0] == goal_of:
            self._award_corner_kick(opponent(kicker[0]))
        else:
            self._award_goal_kick(goal_of)

    # ---- set-piece taker bookkeeping -----------------------------------------------------------------
    def _set_kick_taken(self, touch: _Touch, indirect: bool) -> None:
        self._check_taker_foul = True
        self._free_kick_time_s = touch.game_time_s
        self._free_kick_taker = touch.key
        self._indirect_kick = indirect

    def _reset_kick_checks(self) -> None:
        self._check_taker_foul = False
        self._indirect_kick = False
        self.pass_mode.forget()

    def _last_kick_from_free_kick(self) -> Key | None:
        """The set-piece taker when the last touch is still its kick (within 0.1 s), else None."""
        touch = self._last_touch
        if self._free_kick_taker is None or touch is None:
            return None
        if touch.game_time_s - self._free_kick_time_s < _KICK_DURATION_S and touch.key == self._free_kick_taker:
            return touch.key
        return None

    def _check_taker_foul_now(self) -> bool:
        """Double touch: the taker touches again before anyone else -> indirect free kick for the opponents."""
        if not self._check_taker_foul or self._free_kick_taker is None:
            return False
        if self._last_kick_from_free_kick() is not None:
            return False
        self._check_taker_foul = False
        self._indirect_kick = False
        if self._last_touch is not None and self._last_touch.key == self._free_kick_taker:
            self._award_free_kick(opponent(self._free_kick_taker[0]), indirect=True)
            return True
        return False

    def pass_mode_score_wait_s(self, side: str) -> float | None:
        """Seconds until ``side`` may score after its pass mode (monitor field, PlayOn only), or None."""
        if self.play_mode != "PlayOn":
            return None
        return self.pass_mode.score_wait_s(side, self.game_time_s)

    # ---- fouls ---------------------------------------------------------------------------------------
    def _automatic_referee(self, world: WorldView) -> None:
        if self.paused:
            self.fouls_tracker.reset_all()
            self.self_collisions.reset()
            return
        enforced = self._check_self_collisions(world)
        placer = self._placer(world)
        enforced += self.fouls_tracker.update(self._robots, self._ball_pos, self._touching,
                                              world.touching_robot_pairs(), placer)
        for foul_type, team, unum, first in enforced:
            foul = Foul(len(self.fouls) + 1, foul_type, team, unum, self.game_time_s)
            self.fouls.append(foul)   # every record, as the monitor sends them (a lifted foul: one a cycle)
            if not first:
                continue   # the same foul's next record: one event and one log line per foul
            self.events.append(RefereeEvent("foul", self.game_time_s, self.play_mode, team=team, foul=foul))
            logger.info("foul %s by %s %d at t=%.2f", foul_type.name, team, unum, self.game_time_s)

    def _check_self_collisions(self, world: WorldView) -> list[FoulRecord]:
        """Self-collision (type 7): needs body poses, from `body_pose_source` or else the world's
        ``robot_body_poses()`` (see sim.monitor.SceneSource); without them the rule is skipped.

        Each call to ``world.freeze_joints`` is one foul: the joints stay frozen for the frozen time by the
        world's motors, and `SelfCollisionRule` names a joint again only after frozen + thaw time.
        """
        poses_of = self.body_pose_source or getattr(world, "robot_body_poses", None)
        if not self.config.foul_on_self_collisions or poses_of is None:
            return []
        robots = [(side, unum, robot_type, poses) for side, unum, robot_type, poses in poses_of()
                  if side is not None and unum]
        fouls: list[FoulRecord] = []
        for side, unum, effectors in self.self_collisions.check_all(robots, self.game_time_s):
            world.freeze_joints(side, unum, effectors)
            fouls.append(FoulRecord(FoulType.SELF_COLLISION, side, unum))
        return fouls

    # ---- helpers -------------------------------------------------------------------------------------
    def _placer(self, world: WorldView) -> Placer:
        return Placer(world, self._robots, (self._ball_pos[0], self._ball_pos[1]), self.config, self.rng,
                      self.fouls_tracker.note_moved)

    def _move_ball(self, world: WorldView, position: tuple[float, float, float]) -> None:
        world.set_ball(position, (0.0, 0.0, 0.0))
        self._ball_pos = (float(position[0]), float(position[1]), float(position[2]))
        self._ball_vel = (0.0, 0.0, 0.0)
        self._free_kick_pos = (self._ball_pos[0], self._ball_pos[1], self.config.ball_radius_m)

    def _set_mode(self, name: str) -> None:
        index = PLAY_MODE_INDEX[name]
        if index == self.play_mode_index:
            return
        logger.info("play mode %s -> %s at t=%.2f", self.play_mode, name, self.game_time_s)
        self.play_mode_index = index
        self._last_mode_change_s = self.game_time_s
        self._lead_time_s = 0.0
        self._fup_time_s = 0.0
        self.events.append(RefereeEvent("play_mode", self.game_time_s, name))


def _parse_side(side: str | None) -> str | None:
    if side is None or side in ("None", "none"):
        return None
    lowered = side.lower()
    if lowered not in SIDES:
        raise RuleError(f"unknown side {side!r}; expected Left, Right or None")
    return lowered
