"""Walk skills: to a field point (WalkTo), in a body-relative direction (WalkDirection); to the ball in
``agent.skills.walk_ball``. They read only the world model (self pose from localization, the ball estimate) and ask for
the walk motions of the contract (``walk_forward``, ``walk_backward``, ``walk_left``, ``walk_right``,
``turn_left``/``turn_right`` when the library has them, ``stand``).

Steering (REFERENCE §7.2): a heading error within the lean band is walked out with the walk lean; larger
errors turn in place with the turn motions (their gain from the turn-gain curve) or, in a library without
turn motions, with a full lean. Near the target the walk is stopped early by the distance it still covers
while it stops (the walk file's ``measured_stop_m`` constant), and the last few decimetres are corrected
with the backward and sideways walks.

The skills also report the walk's odometry to the world model (the walk files' measured speeds), so the
localizer's prediction follows the walk between vision frames.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from agent.motion import MotionController, MotionRequest
from agent.skills.avoid import AvoidConfig, Avoider
from agent.skills.base import Skill
from agent.world_model import WorldModel
from agent.protocol.constants import CYCLE_S

FORWARD, BACKWARD, LEFT, RIGHT = "walk_forward", "walk_backward", "walk_left", "walk_right"
#: The fast forward walk (``motions/params/gait.toml`` [walk_fast]): 7-cycle steps of 12 cm where ``walk_forward``
#: takes 5-cycle steps of 6.5 cm, but its shortest use covers 0.68 m (``walk_forward`` 0.33 m), so only far targets
#: get it (``WalkConfig.fast_from_m``); everything short or precise keeps ``walk_forward``.
FAST = "walk_fast"
WALKS = (FORWARD, FAST, BACKWARD, LEFT, RIGHT)
#: The walks that go forward and steer with the walk lean.
FORWARD_WALKS = (FORWARD, FAST)
TURN_LEFT, TURN_RIGHT = "turn_left", "turn_right"
#: The orbits: sideways walks that turn as they go, circling a point ahead (``motions/params/gait.toml``: orbit_left
#: steps right and turns left round a ball about 0.45 m ahead).
ORBIT_LEFT, ORBIT_RIGHT = "orbit_left", "orbit_right"
ORBITS = (ORBIT_LEFT, ORBIT_RIGHT)
STAND = "stand"
#: Stopping distance used when a walk file has no ``measured_stop_m`` constant [m].
DEFAULT_STOP_M = 0.12


@dataclass(frozen=True)
class WalkConfig:
    """Thresholds of the walk skills (numbers chosen on our simulator; see the walk benchmark)."""

    lean_band_deg: float = 7.0
    """Heading error steered with the walk lean alone (REFERENCE §7.2: 7°); a standing robot turns first
    when its error is larger and turn motions exist."""
    lean_full_deg: float = 15.0
    """Heading error that asks for a full lean (smaller errors lean proportionally)."""
    turn_band_deg: float = 45.0
    """A walking robot stops to turn in place once its error exceeds this (with turn motions)."""
    arrive_m: float = 0.15
    """Target reached within this distance [m]."""
    near_m: float = 0.5
    """Within this distance the robot corrects with the short walks (backward, sideways) instead of turning
    toward the target [m]."""
    head_deg: tuple[float, float] = (0.0, 0.0)
    """Head (yaw, pitch) while walking [deg, SimSpark signs] (level: landmarks in view for localization)."""
    corrected_arrive_m: float = 0.25
    """After at least one short correcting walk the target counts as reached within this distance [m]."""
    max_corrections: int = 6
    """Short correcting walks near the target before WalkTo gives up (``done`` with ``reached`` False)."""
    lean_rate_per_s: float = 2.5
    """Largest change of the lean request per second (a sudden full lean can topple the walk); the lean
    starts from 0 whenever the walk is not in its cycle phases."""
    chain_turn_deg: float = 15.0
    """A turn motion that leaves more than this of the asked turn is played again at once, without the
    stance and the settle between [deg] (0 = never). Why: a turn motion turns about ``turn_motion_deg``; with
    the stance (0.4 s) and the settle after each, a dribbler turning 180 deg beside the ball spent 7 s on it;
    chained, 3.5 s. A striker alone before 15 starts around the ball (2 seeds, 60 s each, our simulator):
    the ball's first 1 m push came after 20.5 s on average instead of 23.6 s, no falls either way."""
    chain_stale_deg: float = 45.0
    """A chained turn is cut to the skill's fresh bearing when that lies this much short of the rest of the
    planned turn [deg] (the target moved since the plan: see ``_Steer.turn_step``). Smaller differences keep the
    plan: the pose lags a turn motion. Measured (2026-11-27): the real dribble's 10 m (``motion-studio real skills
    dribble``) took a median of 28 s over 8 runs with the plan alone (one not done in 45 s), 34 s over 6 with every
    chain cut to the bearing (0 here), 31 s over 6 with 45 (one not done): within the real runs' spread, 21-41 s;
    3 v 3 against robots that only stand on ours, seeds 0-31: 41, 47 and 44 goals."""
    turn_motion_deg: float = 38.0
    """What one turn motion turns at full gain [deg] (transfer: 38.0 real, 39.7 ours)."""
    settle_after_turn_s: float = 0.06
    """Standing still after a turn motion (and the stance after it) before walking on [s]. A dribbler turned 15
    times per 120 s match on the real server, 2.1 s a turn. 3 v 3 against robots that only stand, 120 s, seeds
    1-24 on the real server: 0.3 s here (with the open-play shot, before the goal-mouth play-through) 22 goals,
    falls 3; 0.06 s (no shot, play-through) 28 goals, 7 matches with two (1 before), falls 6. Ours, seeds 1-16:
    24 -> 25 goals, falls 3 -> 0. The three changes were measured together."""
    fast_from_m: float = math.inf
    """WalkTo walks with ``FAST`` (where the library has it) toward a target farther than this [m], and once under
    way goes on with it until its stop near the target (a switch between the two forward walks stops and starts
    again); the walk itself is measured in ``motions/params/gait.toml`` [walk_fast]. Off by default (inf): with 2.5
    for every WalkTo of the team (support spots, restarts, the kick's far approach), 3 v 3 against robots that only
    stand, 120 s, gave on the real server 11 goals in seeds 1-8 (10 without), 1 fall (0), and on ours 49 goals in
    seeds 0-31 (54 without) with 19 falls (8): its walkers ran into others and type 4 fell in its cycle. The dribble
    pushing with it lost the ball (ours, seeds 0-15: 19 goals against 27). (Measured with the walk_fast of
    2026-11-28; the one of 2026-11-29 is 9 % faster over 20 m on the real server.)"""
    lean_release: float = 0.15
    """A walk leaning more than this is straightened at ``lean_rate_per_s`` before it is stopped or left
    for another motion: dropped at once (a full lean to 0 mid-stride, then the stop), it toppled a
    type-1 robot in a match."""
    avoid: AvoidConfig | None = AvoidConfig()
    """Obstacle avoidance while walking toward a far target (``agent.skills.avoid``); None = walk straight."""


def constant(motion: MotionController, name: str, key: str, default: float) -> float:
    """A constant of motion ``name`` from the library (``default`` if the motion or the key is missing)."""
    if name not in motion.library:
        return default
    return float(motion.library.get(name).constants.get(key, default))


def walk_velocity_m_s(motion: MotionController, name: str) -> tuple[float, float]:
    """(forward, left) steady velocity of a walk [m/s]: measured on the simulator if the file says, else
    the nominal ``speed_m_s`` / ``side_speed_m_s``."""
    forward = constant(motion, name, "measured_forward_m_s", constant(motion, name, "speed_m_s", 0.0))
    left = constant(motion, name, "measured_left_m_s", constant(motion, name, "side_speed_m_s", 0.0))
    return forward, left


def report_walk_odometry(world: WorldModel, motion: MotionController) -> None:
    """Tell the localizer how far the walk moved the torso in the last cycle: the walk's steady velocity
    in its cycle phases, half of it in its start and stop ramps, nothing otherwise."""
    name, phase = motion.motion_name, motion.phase_name
    if name not in WALKS or phase is None:
        return
    share = 1.0 if phase.startswith("cycle") else 0.5 if phase.startswith(("start", "stop_0", "stop_1")) else 0.0
    if share:
        forward, left = walk_velocity_m_s(motion, name)
        world.report_odometry(forward * share * CYCLE_S, left * share * CYCLE_S)


def stop_distance_m(motion: MotionController, name: str) -> float:
    """Distance a walk still covers after a stop request [m] (file constant ``measured_stop_m``)."""
    return constant(motion, name, "measured_stop_m", DEFAULT_STOP_M)


def _lean(bearing_deg: float, config: WalkConfig) -> float:
    return max(-1.0, min(1.0, bearing_deg / config.lean_full_deg))


def _walking(motion: MotionController) -> bool:
    return motion.motion_name in WALKS and not motion.stopping


class _Steer:
    """Shared mechanics: turn motions played to their end, odometry, head, the last choice (hysteresis)."""

    def __init__(self, config: WalkConfig) -> None:
        self.config = config
        self.turning: str | None = None
        self.lean: float | None = None
        """The lean request sent last (slew-rate limited); None until this skill first steers a walk."""
        self._settle_cycles = 0
        self._stands_before = 0
        self.just_turned = False
        """A turn has ended and no walk has started since: the lean, not another turn, takes the rest
        (a turn motion's smallest turn may exceed the lean band, so turning again could oscillate)."""
        self._turn_deg = 0.0
        self._turns_before = 0

    def request(self, name: str | None, **fields: object) -> MotionRequest:
        return MotionRequest(name, head_deg=fields.pop("head_deg", self.config.head_deg), **fields)  # type: ignore[arg-type]

    def turn(self, motion: MotionController, bearing_deg: float) -> MotionRequest:
        """Start a turn toward ``bearing_deg`` (one turn motion, gain from the turn-gain curve)."""
        self.turning = TURN_LEFT if bearing_deg > 0 else TURN_RIGHT
        self._turn_deg = abs(bearing_deg)
        self._turns_before = motion.completed[self.turning]
        return self.request(self.turning, turn_deg=self._turn_deg)

    def turn_step(self, motion: MotionController, bearing_deg: float | None = None) -> MotionRequest | None:
        """The request while a turn and the return to the stance after it are under way, else None.

        ``bearing_deg``: the skill's bearing to its target now [deg, + = left], if it has one. A chained turn
        goes on by what its start planned minus the turns played, unless the target now lies
        ``chain_stale_deg`` or more short of that: then only as far as the bearing (and not at all when the
        target lies the other way). Why not the bearing alone: right after a turn motion the pose may not show
        all of it yet, which would turn again; why not the plan alone: a plan made on a stale sighting kept
        turning away from the ball (at our kick-off the second attacker planned 150 deg toward the ball's old
        place at the centre, saw it rolling 2.8 m ahead one cycle later, and turned on for 3.5 s, then back)."""
        if self.turning is None and not self._settle_cycles:
            return None
        if self.turning is not None and motion.completed[self.turning] > self._turns_before:
            left = max(0.0, self._turn_deg - self.config.turn_motion_deg)   # still to turn, as planned [deg]
            if bearing_deg is not None:   # ... unless the target moved well away from where it was planned
                toward = bearing_deg if self.turning == TURN_LEFT else -bearing_deg
                if toward < left - self.config.chain_stale_deg:
                    left = max(0.0, toward)
            if self.config.chain_turn_deg > 0.0 and left > self.config.chain_turn_deg:
                return self.turn(motion, left if self.turning == TURN_LEFT else -left)
            self.turning = None
            self.just_turned = True
            self._settle_cycles = round(self.config.settle_after_turn_s / CYCLE_S)
            self._stands_before = motion.completed[STAND]
        if self.turning is None:
            # Back into the walk stance (the turn may end in another pose, and the walk skips its own
            # stance phase while the stance flag is still set), then stand still a moment.
            if STAND in motion.library and motion.completed[STAND] <= self._stands_before:
                return self.request(STAND)
            if self._settle_cycles > 0:
                self._settle_cycles -= 1
                return self.request(None)
            return None
        return self.request(self.turning, turn_deg=self._turn_deg)

    def smooth_lean(self, motion: MotionController, wanted: float) -> float:
        """``wanted`` lean, approached at ``lean_rate_per_s`` once the walk cycles, from the lean the walk
        plays with now (another skill may have started it)."""
        cycling = motion.motion_name in FORWARD_WALKS and (motion.phase_name or "").startswith("cycle")
        if not cycling:
            self.lean = 0.0
            return 0.0
        if self.lean is None:
            self.lean = motion.last_request.lean if motion.last_request.motion in FORWARD_WALKS else 0.0
        step = self.config.lean_rate_per_s * CYCLE_S
        self.lean += max(-step, min(step, wanted - self.lean))
        return self.lean

    def guard(self, motion: MotionController, request: MotionRequest) -> MotionRequest:
        """``request``, unless it leaves a forward walk that still leans more than ``lean_release``: then
        the walk goes on straightening first (the turn or stop follows a few cycles later)."""
        walk = motion.motion_name
        leaving = request.motion != walk and walk in FORWARD_WALKS and not motion.stopping
        if leaving:
            lean = self.smooth_lean(motion, 0.0)
            if abs(lean) > self.config.lean_release:
                return MotionRequest(walk, lean=lean, head_deg=request.head_deg)
        return request

    def can_turn(self, motion: MotionController) -> bool:
        return TURN_LEFT in motion.library and TURN_RIGHT in motion.library

    def heading(self, motion: MotionController, bearing_deg: float, fast: bool = False) -> MotionRequest:
        """Walk forward toward ``bearing_deg``: lean within the bands, else turn (or a full lean); with ``fast``
        the fast walk where the library has it."""
        error = abs(bearing_deg)
        walking = _walking(motion)
        band = self.config.turn_band_deg if walking or self.just_turned else self.config.lean_band_deg
        if error > band and self.can_turn(motion):
            return self.turn(motion, bearing_deg)
        if walking:
            self.just_turned = False
        name = FAST if fast and FAST in motion.library else FORWARD
        return self.request(name, lean=self.smooth_lean(motion, _lean(bearing_deg, self.config)))


class WalkTo(Skill):
    """Walk to a team-frame point (x, y) [m]; ``done`` when within ``arrive_m`` (``reached``) or after
    ``max_corrections`` short corrections near it (``reached`` False).

    Args:
        x_m, y_m: the target in the team frame (own goal at -x).
        config: thresholds.
    """

    def __init__(self, x_m: float, y_m: float, config: WalkConfig | None = None) -> None:
        super().__init__()
        self.target = (float(x_m), float(y_m))
        self.config = config or WalkConfig()
        self.name = f"walk to ({x_m:.2f}, {y_m:.2f})"
        self.reset()

    def reset(self) -> None:
        super().reset()
        self.reached = False
        self.corrections = 0
        self._steer = _Steer(self.config)
        self._avoider = Avoider(self.config.avoid) if self.config.avoid else None
        self._correction: str | None = None

    def step(self, world: WorldModel, motion: MotionController) -> MotionRequest:
        return self._steer.guard(motion, self._step(world, motion))

    def _step(self, world: WorldModel, motion: MotionController) -> MotionRequest:
        report_walk_odometry(world, motion)
        steer = self._steer
        pose = world.pose
        if self.done or pose is None or not world.localized:
            return steer.request(None)  # no trusted pose yet (e.g. just after a beam): stand and look
        under_way = steer.turn_step(motion)
        if under_way is not None:
            return under_way
        forward, left = pose.to_ego(*self.target)
        distance = math.hypot(forward, left)
        bearing_deg = math.degrees(math.atan2(left, forward))
        if distance <= self.config.arrive_m:
            return self._arrive(motion, reached=True)
        if self._correction is not None:
            return self._correct(motion, forward, left)
        if distance <= self.config.near_m:
            walk = motion.motion_name
            if walk in FORWARD_WALKS and not motion.stopping and forward > 0:
                # Still walking in: stop once the remaining distance is what the stop covers.
                if forward > stop_distance_m(motion, walk) + self.config.arrive_m / 2 and abs(bearing_deg) < 45:
                    return steer.request(walk, lean=steer.smooth_lean(motion, _lean(bearing_deg, self.config)))
            return self._correct(motion, forward, left)
        if self._avoider is not None:
            escape = self._avoider.bearing_deg(world, (forward, left))
            if escape is None:
                return steer.request(None)  # surrounded: let the others pass
            bearing_deg = escape
        fast = distance > self.config.fast_from_m or (motion.motion_name == FAST and not motion.stopping)
        return steer.heading(motion, bearing_deg, fast=fast)

    def _arrive(self, motion: MotionController, reached: bool) -> MotionRequest:
        if motion.idle or motion.motion_name not in WALKS:
            self.done, self.reached = True, reached
        return self._steer.request(None)

    def _correct(self, motion: MotionController, forward: float, left: float) -> MotionRequest:
        """Near the target: one short walk along the larger error component (a walk already stopping is let
        finish first); each finished correction counts."""
        if self._correction is not None:
            if motion.motion_name == self._correction and not motion.stopping:
                if self._correction_left(motion, forward, left) > stop_distance_m(motion, self._correction):
                    return self._steer.request(self._correction)
                return self._steer.request(None)
            if not motion.idle:
                return self._steer.request(None)
            self._correction = None
            self.corrections += 1
            if math.hypot(forward, left) <= self.config.corrected_arrive_m:
                # Close enough after a correction: the short walks move more than this error (a side walk
                # about 0.25 m), so another one only swings past the target to the other side (seen: six
                # side walks swinging between +-0.13 m until the skill gave up).
                return self._arrive(motion, reached=True)
            if self.corrections >= self.config.max_corrections:
                return self._arrive(motion, reached=False)
        if not motion.idle and motion.motion_name in WALKS:
            return self._steer.request(None)
        if abs(forward) >= abs(left):
            name = FORWARD if forward > 0 else BACKWARD
        else:
            name = LEFT if left > 0 else RIGHT
        if name not in motion.library:
            name = FORWARD
        self._correction = name
        return self._steer.request(name)

    @staticmethod
    def _correction_left(motion: MotionController, forward: float, left: float) -> float:
        """Remaining error along the correcting walk's direction [m]."""
        return {FORWARD: forward, BACKWARD: -forward, LEFT: left, RIGHT: -left}.get(motion.motion_name or "", 0.0)


class WalkDirection(Skill):
    """Walk in a direction relative to the body, without turning: 0° = forward, 90° = left, ±180° =
    backward, -90° = right; the nearest of the four walks (sectors of ±45°) plays until the skill is
    replaced (``done`` stays False).

    Args:
        angle_deg: the direction [deg], counter-clockwise from forward.
    """

    def __init__(self, angle_deg: float, config: WalkConfig | None = None) -> None:
        super().__init__()
        if not math.isfinite(angle_deg):
            raise ValueError(f"WalkDirection angle_deg must be finite, got {angle_deg!r}")
        self.angle_deg = (angle_deg + 180.0) % 360.0 - 180.0
        self.config = config or WalkConfig()
        self.name = f"walk direction {self.angle_deg:.0f}°"
        self.motion_name = self.walk_for(self.angle_deg)

    @staticmethod
    def walk_for(angle_deg: float) -> str:
        """The walk motion for a body-relative direction [deg]."""
        angle = (angle_deg + 180.0) % 360.0 - 180.0
        if -45.0 <= angle <= 45.0:
            return FORWARD
        if 45.0 < angle < 135.0:
            return LEFT
        if -135.0 < angle < -45.0:
            return RIGHT
        return BACKWARD

    def step(self, world: WorldModel, motion: MotionController) -> MotionRequest:
        report_walk_odometry(world, motion)
        return MotionRequest(self.motion_name, head_deg=self.config.head_deg)


__all__ = ["WalkConfig", "WalkDirection", "WalkTo", "report_walk_odometry", "stop_distance_m", "walk_velocity_m_s"]
