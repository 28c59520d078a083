"""Pass mode (REFERENCE §4.6): when a team may ask for it, and when it may score again afterwards."""

from __future__ import annotations

import math
from collections.abc import Sequence

from sim.rules.params import LEFT, RIGHT, SIDES, RefereeConfig, opponent
from sim.world_api import RobotState

Vec3 = tuple[float, float, float]
_NEVER_S = -1000.0


class PassModeTracker:
    """Per team: the last game time in pass mode and the "cleared to score" bookkeeping.

    Args:
        config: pass-mode parameters.
    """

    def __init__(self, config: RefereeConfig) -> None:
        self.config = config
        self.last_s: dict[str, float] = {LEFT: _NEVER_S, RIGHT: _NEVER_S}
        self.cleared: dict[str, bool] = {LEFT: False, RIGHT: False}
        self.ball_at_start: dict[str, Vec3] = {}
        self._first_toucher: dict[str, int] = {LEFT: -1, RIGHT: -1}
        self._several_touched: dict[str, bool] = {LEFT: False, RIGHT: False}
        self._ball_left_circle: dict[str, bool] = {LEFT: False, RIGHT: False}

    def forget(self) -> None:
        """A set piece was taken or the ball dropped: no team is in a pass-mode wait any more."""
        self.last_s = {LEFT: _NEVER_S, RIGHT: _NEVER_S}

    def may_start(self, side: str, unum: int, time_s: float, touching: Sequence[tuple[str, int]],
                  ball: Vec3, ball_velocity: Vec3, robots: Sequence[RobotState]) -> bool:
        """The conditions of REFERENCE §4.6 (the play mode, PlayOn, is the caller's)."""
        c = self.config
        if time_s - self.last_s[side] < c.pass_mode_retry_wait_time_s:
            return False
        if any(key[0] == side for key in touching):
            return False
        if math.sqrt(sum(v * v for v in ball_velocity)) > c.pass_mode_max_ball_speed_m_s:
            return False
        me = next((r for r in robots if r.team == side and r.unum == unum), None)
        if me is None or math.hypot(me.torso_pos_m[0] - ball[0], me.torso_pos_m[1] - ball[1]) > \
                c.pass_mode_max_ball_dist_m:
            return False
        return not any(r.team != side and math.hypot(r.torso_pos_m[0] - ball[0], r.torso_pos_m[1] - ball[1])
                       < c.pass_mode_min_opp_ball_dist_m for r in robots)

    def in_pass_mode(self, side: str, time_s: float, ball: Vec3) -> None:
        """Called every cycle of ``pass_<side>``: restart the wait, cancel the opponent's."""
        self.last_s[side] = time_s
        self._first_toucher[side] = -1
        self._several_touched[side] = False
        self._ball_left_circle[side] = False
        self.cleared[side] = False
        self.last_s[opponent(side)] = _NEVER_S
        self.ball_at_start[side] = ball

    def waiting(self, side: str, time_s: float) -> bool:
        """True while ``side`` may not score: within the wait after its pass mode and not yet cleared."""
        return time_s - self.last_s[side] < self.config.pass_mode_score_wait_time_s and not self.cleared[side]

    def update(self, time_s: float, ball: Vec3, touching: Sequence[tuple[str, int]]) -> None:
        """Clear a waiting team once two teammates touched the ball, one after it left the 1 m circle."""
        team = next((s for s in SIDES if self.waiting(s, time_s)), None)
        if team is None:
            return
        if not self._ball_left_circle[team] and team in self.ball_at_start:
            px, py, _ = self.ball_at_start[team]
            if math.hypot(ball[0] - px, ball[1] - py) >= self.config.pass_mode_min_opp_ball_dist_m:
                self._ball_left_circle[team] = True
        for side, unum in touching:
            if side != team:
                continue
            first = self._first_toucher[team]
            if first > 0 and (first != unum or self._several_touched[team]):
                self._several_touched[team] = True
                if self._ball_left_circle[team]:
                    self.cleared[team] = True
                break
            self._first_toucher[team] = unum

    def score_wait_s(self, side: str, time_s: float) -> float | None:
        """Seconds left in ``side``'s wait (the monitor's pass_mode_score_wait), or None."""
        if not self.waiting(side, time_s):
            return None
        return self.config.pass_mode_score_wait_time_s - (time_s - self.last_s[side])
