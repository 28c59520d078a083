"""The automatic referee's foul checks (REFERENCE §4.5): incapable, illegal defence, touching, charging.

Counters are kept per (team, unum) in cycles, as the server does. `FoulTracker.update` runs once per cycle
while the game is not paused; it decides fouls and calls the `Placer` to enforce them, and returns the fouls
to report. Crowding is disabled in 0.7.3 (all distances 0) and is not checked.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import NamedTuple

from sim.rules.params import LEFT, SIDES, FoulType, RefereeConfig, in_box
from sim.rules.placement import Key, Placer, illegal_defence_position, outside_position
from sim.world_api import RobotState


class FoulRecord(NamedTuple):
    """One record of a foul, as the server lists it to monitors: a lifted foul has one a cycle of its lift,
    ``first`` only on the record that opens it (one referee event per foul, every record to the monitor)."""

    foul: FoulType
    side: str
    unum: int
    first: bool = True


@dataclass
class PlayerCounters:
    """Per-player counters of the automatic referee; times are in cycles."""

    ground: int = 0
    not_standing: int = 0
    standing: int = 0
    inside_own_area: bool = False
    prev_inside_own_area: bool = False
    foul_time: int = 0
    last_foul: FoulType | None = None
    since_ball_touch: int = 0
    charging_time: int = 0
    since_moved: int = 10 ** 6
    touch_group_size_prev: int = 1
    velocities: list[tuple[float, float, float]] = field(default_factory=list)


class FoulTracker:
    """Counters and decisions of the automatic referee.

    Args:
        config: rule parameters.
    """

    def __init__(self, config: RefereeConfig) -> None:
        self.config = config
        self.players: dict[Key, PlayerCounters] = {}
        # Only `update` changes the counters `reset_player` sets, so while the game stays paused one reset
        # holds: `reset_all` then skips the work (it runs every paused cycle).
        self._all_reset = False

    def counters(self, key: Key) -> PlayerCounters:
        if key not in self.players:
            self.players[key] = PlayerCounters()
            self.reset_player(key)
        return self.players[key]

    def forget(self, key: Key) -> None:
        """Drop a player that left the game."""
        self.players.pop(key, None)

    def reset_player(self, key: Key) -> None:
        """The server's ResetFoulCounterPlayer: after an enforcement and whenever the game is paused."""
        c = self.config
        p = self.players[key]
        p.ground = p.not_standing = 0
        p.standing = round(5.0 / c.cycle_s)  # "considers the player has been standing for some time"
        p.inside_own_area = p.prev_inside_own_area = False
        p.foul_time = 0
        p.last_foul = None
        p.since_ball_touch = round(c.charging_immunity_time_s / c.cycle_s)
        p.charging_time = round(c.charging_collision_min_time_s / c.cycle_s)

    def reset_all(self) -> None:
        if self._all_reset:
            return
        for key in self.players:
            self.reset_player(key)
        self._all_reset = True

    def note_moved(self, team: str, unum: int) -> None:
        self.counters((team, unum)).since_moved = 0

    def record_velocities(self, robots: list[RobotState]) -> None:
        """Keep the last few torso velocities for the charging rule (server: every cycle, paused or not)."""
        n = self.config.charging_velocity_samples
        for robot in robots:
            history = self.counters((robot.team, robot.unum)).velocities
            history.insert(0, robot.torso_vel_m_s)
            del history[n:]

    def enforceable(self, key: Key) -> bool:
        """The server's HaveEnforceableFoul (MaxFoulTime 0: any counted foul is enforceable)."""
        p = self.counters(key)
        return p.last_foul is not None and (p.foul_time > 0 or p.last_foul in (
            FoulType.CHARGING, FoulType.TOUCHING, FoulType.SELF_COLLISION))

    # ---- the cycle -----------------------------------------------------------------------------------
    def update(self, robots: list[RobotState], ball_pos: tuple[float, float, float],
               ball_touchers: list[Key], touching_pairs: list[tuple[Key, Key]], placer: Placer) -> list[
                   FoulRecord]:
        """One cycle of the automatic referee; returns the record of each enforced foul."""
        self._all_reset = False
        states = {(r.team, r.unum): r for r in robots}
        for key, robot in states.items():
            self._process_state(key, robot)
        for key in ball_touchers:
            if key in states:
                self.counters(key).since_ball_touch = 0
        groups = _touch_groups(list(states), touching_pairs)
        if self.config.use_charging:
            self._analyse_charging(states, ball_pos, touching_pairs)
        for side in SIDES:
            self._analyse_team(side, states, placer)
        sides = list(SIDES)
        placer.rng.shuffle(sides)
        for side in sides:
            self._analyse_touch_groups(side, states, groups, placer, only_new=True)
        placer.rng.shuffle(sides)
        reported: list[FoulRecord] = []
        for side in sides:
            reported.extend(self._enforce(side, states, ball_pos, placer))
        for key in states:
            self.counters(key).touch_group_size_prev = len(groups.get(key, {key}))
        return reported

    def _process_state(self, key: Key, robot: RobotState) -> None:
        c = self.config
        p = self.counters(key)
        x, y, z = robot.torso_pos_m
        p.prev_inside_own_area = p.inside_own_area
        p.inside_own_area = in_box(x, y, c.penalty_area(key[0]))
        on_field = abs(y) < c.half_width_m + 0.1
        if z < c.not_standing_z_m and on_field:
            p.not_standing += 1
            p.standing = 0
        if z < c.on_ground_z_m and on_field:
            p.ground += 1
        if z >= c.not_standing_z_m:
            p.standing += 1
            p.ground = 0
        if p.standing > 0.5 / c.cycle_s:
            p.not_standing = 0
        p.since_ball_touch += 1
        p.charging_time += 1
        p.since_moved += 1

    def _analyse_team(self, side: str, states: dict[Key, RobotState], placer: Placer) -> None:
        """Illegal defence and incapable (the server's AnalyseFouls; crowding is disabled)."""
        c = self.config
        cycles = c.cycle_s
        team = [key for key in states if key[0] == side]
        placer.rng.shuffle(team)
        inside = [key for key in team if self.counters(key).inside_own_area]
        goal_x = -c.half_length_m if side == LEFT else c.half_length_m
        # Rank by distance to the own goal; a goalie inside its area counts as distance 0.
        def goal_dist(key: Key) -> float:
            if key[1] == 1 and self.counters(key).inside_own_area:
                return 0.0
            x, y = placer.pos[key]
            return math.hypot(x - goal_x, y)
        ranked = sorted(team, key=goal_dist)
        goalie = self.players.get((side, 1))
        goalie_entered = goalie is not None and (side, 1) in states and goalie.inside_own_area and \
            not goalie.prev_inside_own_area
        count_inside = len(inside)
        for key in team:
            p = self.counters(key)
            if self.enforceable(key):
                continue
            unum = key[1]
            if (count_inside > c.max_players_inside_own_area and unum != 1 and p.inside_own_area
                    and (not p.prev_inside_own_area
                         or (goalie_entered and ranked.index(key) + 1 == c.max_players_inside_own_area + 1))):
                p.foul_time += 1
                p.last_foul = FoulType.ILLEGAL_DEFENCE
                count_inside -= 1
                x, y = placer.pos[key]
                placer.move(key, *illegal_defence_position(side, x, y, c))
            elif unum != 1 and p.ground > c.ground_max_time_s / cycles:
                p.foul_time += 1
                p.last_foul = FoulType.INCAPABLE
            elif unum != 1 and p.not_standing > c.not_standing_max_time_s / cycles:
                p.foul_time += 1
                p.last_foul = FoulType.INCAPABLE
            elif unum == 1 and p.ground > c.goalie_ground_max_time_s / cycles:
                p.foul_time += 1
                p.last_foul = FoulType.INCAPABLE
            elif unum == 1 and p.not_standing > c.goalie_not_standing_max_time_s / cycles:
                p.foul_time += 1
                p.last_foul = FoulType.INCAPABLE
            else:
                p.foul_time = 0
                p.last_foul = None

    def _analyse_touch_groups(self, side: str, states: dict[Key, RobotState], groups: dict[Key, set[Key]],
                              placer: Placer, only_new: bool) -> None:
        """Touching: a group of more than MaxTouchGroupSize robots in contact loses its latest member."""
        c = self.config
        team = [key for key in states if key[0] == side]
        placer.rng.shuffle(team)
        for key in team:
            group = groups.setdefault(key, {key})
            if self.enforceable(key):
                group.discard(key)
                continue
            newly_joined = self.counters(key).touch_group_size_prev == 1
            if not ((newly_joined or not only_new) and len(group) > c.max_touch_group_size):
                continue
            members = sorted(group)  # a set's order follows PYTHONHASHSEED: sorted, the seed decides the shuffle
            placer.rng.shuffle(members)
            fouled = 0
            count = {s: 0 for s in SIDES}
            sum_x = sum_y = 0.0
            last_opp: Key | None = None
            last_mate: Key | None = None
            for member in members:
                if self.enforceable(member):
                    fouled += 1
                    continue
                x, y = placer.pos[member]
                sum_x += x
                sum_y += y
                count[member[0]] += 1
                if member[1] != 1 or c.max_touch_group_size < 2:
                    if member[0] != side:
                        last_opp = member
                    else:
                        last_mate = member
            if len(group) - fouled <= c.max_touch_group_size:
                continue
            centre = (sum_x / (len(group) - fouled), sum_y / (len(group) - fouled))
            if count[side] >= len(group) - count[side]:
                victim = last_mate if (key[1] == 1 and c.max_touch_group_size > 1) else key
            else:
                victim = last_opp
            if victim is None:
                continue
            self._penalize_touching(victim, centre, placer)
            group.discard(victim)
        if only_new and any(len(groups.get(key, ())) > c.max_touch_group_size for key in team):
            self._analyse_touch_groups(side, states, groups, placer, only_new=False)

    def _penalize_touching(self, key: Key, centre: tuple[float, float], placer: Placer) -> None:
        p = self.counters(key)
        p.foul_time += 1
        p.last_foul = FoulType.TOUCHING
        x, y = placer.pos[key]
        dx, dy = x - centre[0], y - centre[1]
        norm = math.hypot(dx, dy) or 1.0
        radius = self.config.agent_radius_m
        placer.move(key, x + dx / norm * radius, y + dy / norm * radius)

    def _analyse_charging(self, states: dict[Key, RobotState], ball_pos: tuple[float, float, float],
                          pairs: list[tuple[Key, Key]]) -> None:
        """Charging between two opponents in contact (server AnalyseChargingFouls).

        The contact point is not in WorldView, so the midpoint of the two torsos stands in for it.
        """
        c = self.config
        cyc = c.cycle_s
        new_touch = {key: self.counters(key).since_ball_touch for key in states}
        new_charge = {key: self.counters(key).charging_time for key in states}
        fouls: list[Key] = []
        for a, b in pairs:
            if a not in states or b not in states or a[0] == b[0]:
                continue
            pair = (a, b) if a[0] == LEFT else (b, a)
            info = [self._motion(key, states[key], ball_pos) for key in pair]
            pa, pb = (self.counters(k) for k in pair)
            if (pa.not_standing or pb.not_standing or pa.since_moved < c.moved_immunity_time_s / cyc
                    or pb.since_moved < c.moved_immunity_time_s / cyc
                    or self.enforceable(pair[0]) or self.enforceable(pair[1])):
                continue
            goalie_in_area = [self._goalie_in_own_area(key, states[key]) for key in pair]
            pos = [states[k].torso_pos_m for k in pair]
            avo = [_angle_diff_deg(info[i][3], math.atan2(pos[1 - i][1] - pos[i][1], pos[1 - i][0] - pos[i][0]))
                   for i in range(2)]
            speed = [info[i][1] for i in range(2)]
            dist = [info[i][0] for i in range(2)]
            avb = [info[i][2] for i in range(2)]
            charging = [True, True]
            if dist[0] < c.charging_max_ball_rules_dist_m or dist[1] < c.charging_max_ball_rules_dist_m:
                charging = [avb[i] >= avo[i] and avb[i] >= c.charging_min_ball_speed_angle_deg
                            and speed[i] >= c.charging_min_speed_m_s for i in range(2)]
                if not charging[0] and not charging[1]:
                    delta_d = abs(dist[0] - dist[1])
                    delta_a = abs(avo[0] - avo[1])
                    if delta_d > c.charging_min_delta_dist_m:
                        charging = [dist[0] > dist[1] and (delta_a > c.charging_min_delta_ang_deg
                                                           or speed[1] < c.charging_min_speed_m_s),
                                    dist[1] > dist[0] and (delta_a > c.charging_min_delta_ang_deg
                                                           or speed[0] < c.charging_min_speed_m_s)]
            coll = ((pos[0][0] + pos[1][0]) / 2.0, (pos[0][1] + pos[1][1]) / 2.0)
            for i in range(2):
                vx, vy = info[i][4]
                tx, ty = (coll[0] + pos[1 - i][0]) / 2.0 - pos[i][0], (coll[1] + pos[1 - i][1]) / 2.0 - pos[i][1]
                norm = math.hypot(tx, ty) or 1.0
                coll_speed = (vx * tx + vy * ty) / norm
                charging[i] = charging[i] and speed[i] >= c.charging_min_speed_m_s and \
                    coll_speed >= c.charging_min_collision_speed_m_s
            counters = [pa, pb]
            for i in range(2):
                if not charging[i]:
                    continue
                other = pair[1 - i]
                if goalie_in_area[i]:
                    new_touch[other] = 0
                elif counters[i].since_ball_touch < c.charging_immunity_time_s / cyc:
                    new_touch[other] = min(new_touch[other], counters[i].since_ball_touch)
                new_charge[other] = min(new_charge[other], counters[i].charging_time)
            ball_to_coll = math.hypot(coll[0] - ball_pos[0], coll[1] - ball_pos[1])
            if (charging[0] and charging[1]) or ball_to_coll < c.charging_min_coll_ball_dist_m:
                charging = [False, False]
            for i in range(2):
                if (charging[i] and not goalie_in_area[i]
                        and counters[i].charging_time >= c.charging_collision_min_time_s / cyc
                        and counters[i].since_ball_touch >= c.charging_immunity_time_s / cyc):
                    fouls.append(pair[i])
            if not charging[0] and not charging[1]:
                new_charge[pair[0]] = new_charge[pair[1]] = 0
        for key in states:
            self.counters(key).since_ball_touch = new_touch[key]
            self.counters(key).charging_time = new_charge[key]
        for key in fouls:
            p = self.counters(key)
            p.foul_time += 1
            p.last_foul = FoulType.CHARGING

    def _motion(self, key: Key, robot: RobotState, ball_pos: tuple[float, float, float]) -> tuple[
            float, float, float, float, tuple[float, float]]:
        """(ball distance, mean speed, angle velocity-to-ball [deg], velocity heading [rad], mean velocity)."""
        history = self.counters(key).velocities or [robot.torso_vel_m_s]
        n = self.config.charging_velocity_samples
        vx = sum(v[0] for v in history) / n
        vy = sum(v[1] for v in history) / n
        x, y, _ = robot.torso_pos_m
        heading = math.atan2(vy, vx)
        to_ball = math.atan2(ball_pos[1] - y, ball_pos[0] - x)
        return (math.hypot(x - ball_pos[0], y - ball_pos[1]), math.hypot(vx, vy),
                _angle_diff_deg(heading, to_ball), heading, (vx, vy))

    def _goalie_in_own_area(self, key: Key, robot: RobotState) -> bool:
        if key[1] != 1:
            return False
        x, y, _ = robot.torso_pos_m
        area = self.config.penalty_area(key[0])
        if not area[2] <= y <= area[3]:
            return False
        return x <= area[1] if key[0] == LEFT else x >= area[0]

    def _enforce(self, side: str, states: dict[Key, RobotState], ball_pos: tuple[float, float, float],
                 placer: Placer) -> list[FoulRecord]:
        """The server's ClearPlayersAutomatic: lift for FoulHoldTime, then place outside the field.

        Touching and illegal defence have already moved the player; they only reset the counters (one record).
        A lifted foul is reported in every cycle of the lift and in the one that places the player outside, as
        the server records it (a ``Foul`` each cycle ``HaveEnforceableFoul`` holds: 0.5 s / 20 ms + 1 = 26
        records, measured in the real monitor stream), so the monitor's foul list matches the real one.
        """
        c = self.config
        reported: list[FoulRecord] = []
        for key in placer.team(side):
            if key not in states or not self.enforceable(key):
                continue
            p = self.counters(key)
            foul = p.last_foul
            assert foul is not None
            if foul in (FoulType.ILLEGAL_DEFENCE, FoulType.TOUCHING):
                reported.append(FoulRecord(foul, key[0], key[1]))
                self.reset_player(key)
                continue
            reported.append(FoulRecord(foul, key[0], key[1], first=p.foul_time == 1))
            if p.foul_time <= c.foul_hold_time_s / c.cycle_s:
                p.foul_time += 1
                x, y = placer.pos[key]
                placer.move(key, x, y, safe=False, z_m=1.0 + p.foul_time * 0.01)
            else:
                x, y = outside_position(side, key[1], ball_pos[1], c)
                placer.move(key, x, y, z_m=c.agent_radius_m)  # down from its lift, upright
                self.reset_player(key)
        return reported


def _touch_groups(keys: list[Key], pairs: list[tuple[Key, Key]]) -> dict[Key, set[Key]]:
    """Connected components of the contact graph (each robot maps to the shared set of its group)."""
    groups: dict[Key, set[Key]] = {key: {key} for key in keys}
    for a, b in pairs:
        if a not in groups or b not in groups or groups[a] is groups[b]:
            continue
        merged = groups[a] | groups[b]
        for member in merged:
            groups[member] = merged
    return groups


def _angle_diff_deg(a_rad: float, b_rad: float) -> float:
    """|a - b| normalised to [0, 180] degrees."""
    d = (a_rad - b_rad + math.pi) % (2.0 * math.pi) - math.pi
    return abs(math.degrees(d))

