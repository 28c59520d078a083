"""The motion controller: plays XML phase and Webots motions as joint velocities, one call per cycle.

Interface: a behaviour posts a :class:`MotionRequest` (:meth:`MotionController.request`) each cycle, then
:meth:`MotionController.update` turns the measured joint angles into this cycle's joint velocities
(effector -> rad/s). Pure: no clock, no files (the library is loaded beforehand).

Playback (REFERENCE §6, thesis controller):

* A keyframe (XML phase or Webots pose) lasts a whole number of cycles; each cycle every commanded joint
  gets ω = (target − current) / (time left in the keyframe), so the target is reached at the keyframe's end
  (the thesis computes it once per phase; recomputing each cycle corrects for load and rounding).
* XML phases: every unlisted joint gets ω = 0 (an empty phase holds the whole body); ``next`` is followed
  while the same motion is requested; when another motion is requested, the phase's ``finalize`` follows,
  or, without one, the motion ends after an ``isFinal`` phase, else ``next`` goes on; ``skipIfFlag`` skips
  a phase whose flag is set, ``setFlagTrue``/``setFlagFalse`` set or clear a flag (shared by all motions)
  when the phase starts; ``computed`` targets come from the dynamic elements (walk lean) or from
  :attr:`MotionController.computed_deg`, else their ``end`` fallback.
* Webots poses: ``Duration`` cycles per pose and ``PoseStep`` poses per step as the seed agent
  (:class:`~agent.motion.library.WebotsTiming`), or the file's own times; ``*`` leaves the joint
  uncommanded. A Webots motion runs to its end.
* Action delay (REFERENCE §3.9): the answer to sense message k acts during the step after the one already
  running, so the angle it starts from is the measured one moved by the previous command for one cycle;
  the controller predicts that angle (``delay_compensation``).
* Blending: a motion's first keyframe lasts at least as long as its largest joint move takes at
  ``blend_speed_rad_s``, so a motion started from a far pose gets there without a jolt; a motion with a
  ``blend_speed_rad_s`` constant uses its own bound (the stand-ups, which start lying still). Head joints
  that the request steers (``head_deg``) do not count.
* Turn gain (REFERENCE §7.3): a gain g scales a motion's targets as base + g·(target − base), where base
  is the library's gain base motion (same keyframe count) or the motion's first keyframe.
* Slowdown (REFERENCE §7.2): after a stop request, the phases of a walk (a motion with a ``speed_m_s``
  constant) are stretched by the slowdown curve.
* Kick distance: a request with ``distance_m`` stretches the strike phases of the kicks the kick-distance
  table names (a slower swing, a shorter kick).

Joint targets are kept ``joint_margin_deg`` inside the joint limits: at a stop the server ignores new
commands (REFERENCE §2.2), so a joint driven into its stop could never leave it.
"""

from __future__ import annotations

import math
from collections import Counter
from collections.abc import Mapping
from dataclasses import dataclass, field

from agent.motion.dynamic import DynamicParams
from agent.motion.library import MotionLibrary, WebotsTiming
from kinematics.spec import robot_spec
from motions import XML, Keyframe, Motion
from motions.model import BLEND_SPEED_CONSTANT
from agent.protocol.constants import CYCLE_S

#: Head joints (driven by ``MotionRequest.head_deg`` when set, as the seed agent drives the head apart).
HEAD_JOINTS = ("hj1", "hj2")
#: Guard against a loop of skipped phases (every phase of a cycle skipped).
_MAX_SKIPS = 64


@dataclass(frozen=True)
class ControllerConfig:
    """Settings of the controller that are not tuned curves."""

    delay_compensation: bool = True
    """Predict the angle the next command starts from (measured + previous command x one cycle)."""
    blend_speed_rad_s: float = 3.0
    """Joint speed bound of the move into a motion's first keyframe [rad/s]."""
    joint_margin_deg: float = 0.5
    """Targets are kept this far inside the joint limits [deg]."""
    head_time_constant_s: float = 0.1
    """Time constant of the head tracking ``head_deg`` [s]."""


@dataclass(frozen=True)
class MotionRequest:
    """What a behaviour asks the controller for in one cycle.

    motion: motion name in the library; None = no motion (the body holds still once the current motion
        has finished).
    lean: walk lean request in [-1, 1], + = curve to the left (REFERENCE §7.2).
    turn_deg: requested turn for a gain-scaled motion; the turn-gain curve gives the gain.
    gain: explicit gain (overrides ``turn_deg``); None and no ``turn_deg``: gain 1.
    head_deg: (yaw, pitch) targets of the head joints in SimSpark degrees, or None to let the motion
        drive them.
    interrupt: drop the current motion at once (no finalize), e.g. for a stand-up after a fall.
    distance_m: the ball distance a kick should reach [m] (the kick-distance table gives its strike's
        stretch); None = the kick as authored (its full distance).
    """

    motion: str | None = None
    lean: float = 0.0
    turn_deg: float | None = None
    gain: float | None = None
    head_deg: tuple[float, float] | None = None
    interrupt: bool = False
    distance_m: float | None = None


@dataclass
class _Keyframe:
    """One keyframe as it will be played: its cycles and resolved targets (wire -> rad, None = uncommanded)."""

    name: str
    cycles: int
    targets: dict[str, float | None]
    hold_unlisted: bool


@dataclass
class _Playback:
    """State of the motion being played."""

    name: str
    motion: Motion
    gain: float
    base: Motion | None
    timing: WebotsTiming
    keyframe: Keyframe | None = None
    index: int = 0
    current: _Keyframe | None = None
    cycles_done: int = 0
    stopping: bool = False
    phases_since_stop: int = 0
    first: bool = True
    time_s: float = 0.0
    cycle_phases: tuple[str, ...] = ()


@dataclass
class MotionEvent:
    """Something that happened during an update: ``kind`` = "start", "phase" or "end", with names and time."""

    kind: str
    motion: str
    phase: str | None
    time_s: float


class MotionController:
    """Plays motions from a library as joint velocities; see the module docstring.

    Args:
        library: the motions (name -> Motion) and their playback settings.
        dynamic: the dynamic elements (walk lean, slowdown, turn gain).
        robot_type: 0-4 (which joints exist, their limits and speeds).
        config: controller settings.
    """

    def __init__(self, library: MotionLibrary, dynamic: DynamicParams | None = None, robot_type: int = 0,
                 config: ControllerConfig | None = None) -> None:
        self.library = library
        self.dynamic = dynamic or DynamicParams()
        self.config = config or ControllerConfig()
        self.robot_type = robot_type
        spec = robot_spec(robot_type)
        self.joints = spec.joints
        self._effector = {j.perceptor: j.effector for j in self.joints}
        margin = math.radians(self.config.joint_margin_deg)
        self._bounds = {j.perceptor: (j.min_rad + margin, j.max_rad - margin) for j in self.joints}
        # Commands are capped at type 0's joint speeds too [rad/s]: the motions were authored and tuned on
        # type 0, where the walk's ankle pitch saturates at 6.14 rad/s in a quarter of its cycles. Type 2's
        # ankle pitch goes to 8.81 rad/s (REFERENCE 2.5), so uncapped it played a harder walk than the tuned
        # one: it curved 38 deg left in 3 s and walked 0.6 m where type 0 walks 1.3 m (a WalkTo of 8 m not
        # done after 30 s; capped, 14.8 s as on type 0). Slower joints (type 2's ankle roll) keep their own.
        type0 = {j.perceptor: j.max_speed_rad_s for j in robot_spec(0).joints}
        self._max_speed = {j.perceptor: min(j.max_speed_rad_s, type0.get(j.perceptor, j.max_speed_rad_s))
                           for j in self.joints}
        self.flags: dict[str, bool] = {}
        """Flags shared by all motions (``skipIfFlag`` / ``setFlagTrue`` / ``setFlagFalse``)."""
        self.computed_deg: dict[str, float] = {}
        """Run-time values by ``computed`` name [deg] that are not dynamic elements (e.g. ``headAngle1``)."""
        self.completed: Counter[str] = Counter()
        """Motion name -> times it has played to its end."""
        self.events: list[MotionEvent] = []
        """Events of the last update."""
        self._request = MotionRequest()
        self._playback: _Playback | None = None
        self._last_command: dict[str, float] = {j.perceptor: 0.0 for j in self.joints}
        self._last_time_s: float | None = None
        self._sent_phase: str | None = None
        self._gyro_deg_s: tuple[float, float, float] | None = None
        self.time_s = 0.0

    # ---- state --------------------------------------------------------------------------------------
    @property
    def motion_name(self) -> str | None:
        """The motion playing now (None when idle)."""
        return self._playback.name if self._playback else None

    @property
    def phase_name(self) -> str | None:
        """The keyframe whose command the last update sent (None when it sent none, idle)."""
        return self._sent_phase

    @property
    def stopping(self) -> bool:
        """The current motion is leaving (another motion was requested)."""
        return bool(self._playback and self._playback.stopping)

    @property
    def idle(self) -> bool:
        return self._playback is None

    @property
    def last_request(self) -> MotionRequest:
        """The request posted last (what the motion plays with now, e.g. its walk lean)."""
        return self._request

    def request(self, request: MotionRequest | str | None) -> None:
        """Post this cycle's request (a name is ``MotionRequest(name)``); the latest one before ``update``
        counts.

        Raises:
            KeyError: an unknown motion name (the message lists the known ones).
        """
        if not isinstance(request, MotionRequest):
            request = MotionRequest(request)
        if request.motion is not None and request.motion not in self.library:
            self.library.get(request.motion)  # raises with the known names
        self._request = request
        if request.interrupt and self._playback is not None and self._playback.name != request.motion:
            self._finish(self._playback, completed=False)

    # ---- the cycle ----------------------------------------------------------------------------------
    def update(self, joint_angles_deg: Mapping[str, float], time_s: float | None = None,
               gyro_deg_s: tuple[float, float, float] | None = None) -> dict[str, float]:
        """One cycle: measured joint angles in, joint velocities out.

        Args:
            joint_angles_deg: wire name (``llj3``) -> measured angle [deg] (the HJ perceptors).
            time_s: server time of the sense message [s]; if cycles were missed, the motion time and the
                delay compensation follow the real gap. None = one cycle after the last call.
            gyro_deg_s: the torso's angular rate (GYR perceptor, x/y/z) [deg/s] for the walk balance;
                None = no feedback this cycle.

        Returns:
            effector name (``lle3``) -> target angular velocity [rad/s], clamped to the joint's max speed.
            Joints missing from ``joint_angles_deg`` and Webots ``*`` joints are left out.
        """
        self.events = []
        elapsed = CYCLE_S
        if time_s is not None and self._last_time_s is not None:
            elapsed = min(max(time_s - self._last_time_s, CYCLE_S), 10 * CYCLE_S)
        if time_s is not None:
            self._last_time_s = time_s
        self.time_s += elapsed
        self._gyro_deg_s = gyro_deg_s
        current = self._predicted_angles(joint_angles_deg, elapsed)
        self._advance_motion(current)
        velocities = self._joint_velocities(current)
        self._head_velocities(current, velocities)
        out = {}
        for wire, omega in velocities.items():
            if omega is None:
                continue
            limit = self._max_speed[wire]
            omega = max(-limit, min(limit, omega))
            self._last_command[wire] = omega
            out[self._effector[wire]] = omega
        return out

    def _predicted_angles(self, measured_deg: Mapping[str, float], elapsed_s: float) -> dict[str, float]:
        """Angle each joint will have when this cycle's command starts to act [rad]."""
        lead = CYCLE_S if self.config.delay_compensation else 0.0
        angles = {}
        for wire in self._effector:
            value = measured_deg.get(wire)
            if value is not None:
                angles[wire] = math.radians(value) + self._last_command[wire] * lead
        return angles

    # ---- motion sequencing --------------------------------------------------------------------------
    def _advance_motion(self, current: Mapping[str, float]) -> None:
        """Make ``self._playback.current`` the keyframe this cycle's command belongs to (or None when idle)."""
        request = self._request
        playback = self._playback
        if playback is not None and request.motion != playback.name and not playback.stopping:
            playback.stopping = True
        if playback is not None and playback.current is not None and playback.cycles_done >= playback.current.cycles:
            self._next_keyframe(playback, current)
        if self._playback is None and request.motion is not None:
            self._start(request, current)

    def _start(self, request: MotionRequest, current: Mapping[str, float]) -> None:
        name = request.motion
        assert name is not None
        motion = self.library.get(name)
        gain = 1.0
        if request.gain is not None:
            gain = request.gain
        elif request.turn_deg is not None:
            gain = self.dynamic.turn_gain.gain(request.turn_deg)
        base_name = self.library.gain_bases.get(name)
        base = self.library.get(base_name) if base_name else None
        playback = _Playback(name, motion, gain, base, self.library.timing(name))
        if motion.source_format == XML:
            playback.cycle_phases = _cycle_phases(motion)
        self._playback = playback
        self.events.append(MotionEvent("start", name, None, self.time_s))
        if motion.source_format == XML:
            self._enter_phase(playback, motion.start_phase(), current)
        else:
            self._enter_pose(playback, 0, current)

    def _next_keyframe(self, playback: _Playback, current: Mapping[str, float]) -> None:
        if playback.motion.source_format == XML:
            following = self._successor(playback, playback.keyframe)
            if following is None:
                self._finish(playback, completed=True)
            else:
                self._enter_phase(playback, following, current)
        else:
            index = playback.index + playback.timing.pose_step
            last = len(playback.motion.keyframes) - 1
            if playback.index < last and index > last:
                index = last  # PoseStep never skips the final pose
            if index > last:
                self._finish(playback, completed=True)
            else:
                self._enter_pose(playback, index, current)

    def _successor(self, playback: _Playback, phase: Keyframe | None) -> Keyframe | None:
        if phase is None:
            return None
        same = playback.name == self._request.motion and not playback.stopping
        if not same and phase.finalize is None and phase.is_final:
            return None
        return playback.motion.successor(phase, requested_same_motion=same)

    def _finish(self, playback: _Playback, completed: bool) -> None:
        if completed:
            self.completed[playback.name] += 1
        self.events.append(MotionEvent("end", playback.name, playback.current.name if playback.current else None,
                                       self.time_s))
        self._playback = None

    def _enter_phase(self, playback: _Playback, phase: Keyframe, current: Mapping[str, float]) -> None:
        for _ in range(_MAX_SKIPS):
            if phase.skip_if_flag is None or not self.flags.get(phase.skip_if_flag, False):
                break
            following = self._successor(playback, phase)
            if following is None:
                playback.keyframe = phase
                self._finish(playback, completed=True)
                return
            phase = following
        else:
            playback.keyframe = phase
            self._finish(playback, completed=True)
            return
        if phase.set_flag_true is not None:
            self.flags[phase.set_flag_true] = True
        if phase.set_flag_false is not None:
            self.flags[phase.set_flag_false] = False
        playback.keyframe = phase
        duration_s = phase.duration_s
        if playback.stopping and "speed_m_s" in playback.motion.constants:
            duration_s *= self.dynamic.slowdown.factor(playback.phases_since_stop)
            playback.phases_since_stop += 1
        distance = self._request.distance_m
        if distance is not None and self.dynamic.kick_distance.applies(playback.name, phase.name):
            duration_s *= self.dynamic.kick_distance.stretch_for(distance)
        targets = {wire: self._phase_target(playback, phase, wire, t.angle_rad, t.computed)
                   for wire, t in phase.targets.items() if wire in self._effector}
        self._begin(playback, _Keyframe(phase.name, 0, targets, hold_unlisted=True), duration_s, current)

    def _phase_target(self, playback: _Playback, phase: Keyframe, wire: str, fallback: float | None,
                      computed: str | None) -> float | None:
        if computed is None or fallback is None:
            return fallback
        motion = playback.motion
        position = (playback.cycle_phases.index(phase.name) / len(playback.cycle_phases)
                    if phase.name in playback.cycle_phases else 0.0)
        offset = self.dynamic.walk_lean.offset_deg(computed, self._request.lean,
                                                   motion.constants.get("speed_m_s", 0.0), position)
        if offset is not None:
            return fallback + math.radians(offset)
        value = self.computed_deg.get(computed)
        return fallback if value is None else math.radians(value)

    def _enter_pose(self, playback: _Playback, index: int, current: Mapping[str, float]) -> None:
        motion, timing = playback.motion, playback.timing
        pose = motion.keyframes[index]
        playback.index, playback.keyframe = index, pose
        if timing.use_file_times:
            times = motion.keyframe_times_s()
            previous = times[index - timing.pose_step] if index - timing.pose_step >= 0 else 0.0
            duration_s = max(times[index] - previous, CYCLE_S)
        else:
            duration_s = timing.duration_cycles * CYCLE_S
        base = playback.base.keyframes[min(index, len(playback.base.keyframes) - 1)] if playback.base else \
            motion.keyframes[0]
        targets: dict[str, float | None] = {}
        for wire, target in pose.targets.items():
            if wire not in self._effector:
                continue
            angle = target.angle_rad
            if angle is not None and playback.gain != 1.0:
                reference = base.angle_rad(wire)
                if reference is not None:
                    angle = reference + playback.gain * (angle - reference)
            targets[wire] = angle
        self._begin(playback, _Keyframe(pose.name, 0, targets, hold_unlisted=False), duration_s, current)

    def _within_bounds(self, wire: str, angle_rad: float) -> float:
        """``angle_rad`` kept ``joint_margin_deg`` inside the joint's limits (a joint at its stop ignores
        commands, see the module docstring) [rad]."""
        low, high = self._bounds[wire]
        return min(max(angle_rad, low), high)

    def _begin(self, playback: _Playback, keyframe: _Keyframe, duration_s: float,
               current: Mapping[str, float]) -> None:
        """Start a keyframe: clip its targets, quantise its duration to cycles (carrying the rounding so
        the motion keeps its total time), stretch a first keyframe for blending."""
        for wire, angle in keyframe.targets.items():
            if angle is not None:
                keyframe.targets[wire] = self._within_bounds(wire, angle)
        start = playback.time_s
        playback.time_s += duration_s
        cycles = max(1, round(playback.time_s / CYCLE_S) - round(start / CYCLE_S))
        if playback.first:
            playback.first = False
            # The head follows the request's ``head_deg`` when it has one, whatever the keyframe says: it does
            # not stretch the blend then. Why: turn motions list the head at 0 deg; a dribbler looking 60 deg
            # aside at the ball spent 0.36 s of each 0.78 s turn motion blending a head it never moved there.
            steered = HEAD_JOINTS if self._request.head_deg is not None else ()
            largest = max((abs(a - current[w]) for w, a in keyframe.targets.items()
                           if a is not None and w in current and w not in steered), default=0.0)
            speed = float(playback.motion.constants.get(BLEND_SPEED_CONSTANT, self.config.blend_speed_rad_s))
            blend_cycles = math.ceil(largest / speed / CYCLE_S - 1e-9)
            if blend_cycles > cycles:
                playback.time_s += (blend_cycles - cycles) * CYCLE_S
                cycles = blend_cycles
        keyframe.cycles = cycles
        playback.current = keyframe
        playback.cycles_done = 0
        self.events.append(MotionEvent("phase", playback.name, keyframe.name, self.time_s))

    # ---- velocities ---------------------------------------------------------------------------------
    def _joint_velocities(self, current: Mapping[str, float]) -> dict[str, float | None]:
        playback = self._playback
        if playback is None or playback.current is None:
            self._sent_phase = None
            return {wire: 0.0 for wire in current}  # idle: hold every joint
        keyframe = playback.current
        self._sent_phase = keyframe.name
        remaining_s = (keyframe.cycles - playback.cycles_done) * CYCLE_S
        playback.cycles_done += 1
        balance = self._balance_offsets(playback)
        velocities: dict[str, float | None] = {}
        for wire, angle in current.items():
            target = keyframe.targets.get(wire)
            if target is not None and wire in balance:
                target = self._within_bounds(wire, target + balance[wire])
            if target is None:
                if wire in keyframe.targets or not keyframe.hold_unlisted:
                    velocities[wire] = None  # Webots '*': not commanded
                else:
                    velocities[wire] = 0.0  # XML: an unlisted joint holds still
            else:
                velocities[wire] = (target - angle) / remaining_s
        if playback.cycles_done >= keyframe.cycles:
            # Decided now, so that the behaviour sees the end in the cycle after the last command.
            self._next_keyframe_if_done(playback, current)
        return velocities

    def _balance_offsets(self, playback: _Playback) -> dict[str, float]:
        """Wire name -> the walk balance's target offset this cycle [rad] (empty outside the walks)."""
        balance = self.dynamic.walk_balance
        gyro = self._gyro_deg_s
        if gyro is None or not balance.applies(playback.name, "speed_m_s" in playback.motion.constants):
            return {}
        offsets = {}
        for wire, effector in self._effector.items():
            offset = balance.offset_deg(effector[1:], gyro)
            if offset:
                offsets[wire] = math.radians(offset)
        return offsets

    def _next_keyframe_if_done(self, playback: _Playback, current: Mapping[str, float]) -> None:
        """A non-cyclic motion whose last keyframe has just been commanded ends now (not a cycle later)."""
        if playback.motion.source_format == XML:
            if self._successor(playback, playback.keyframe) is None:
                self._finish(playback, completed=True)
        elif playback.index >= len(playback.motion.keyframes) - 1:
            self._finish(playback, completed=True)

    def _head_velocities(self, current: Mapping[str, float], velocities: dict[str, float | None]) -> None:
        head = self._request.head_deg
        if head is None:
            return
        for wire, target_deg in zip(HEAD_JOINTS, head):
            if wire not in current:
                continue
            target = self._within_bounds(wire, math.radians(target_deg))
            velocities[wire] = (target - current[wire]) / max(self.config.head_time_constant_s, CYCLE_S)


def _cycle_phases(motion: Motion) -> tuple[str, ...]:
    """Names of the phases of the motion's ``next`` cycle (empty if the chain does not loop)."""
    chain: list[str] = []
    current = motion.start_phase()
    while current is not None and current.name not in chain:
        chain.append(current.name)
        current = motion.find_phase(current.next)
    if current is None:
        return ()
    return tuple(chain[chain.index(current.name):])


__all__ = ["ControllerConfig", "MotionController", "MotionEvent", "MotionRequest"]
