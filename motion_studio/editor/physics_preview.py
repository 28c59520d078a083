"""Physics preview: play a motion on a robot in the MuJoCo world through the agent's own sense/act loop.

The robot is a real ``agent.Agent`` hosted in-process by ``sim.inprocess.InProcessHost`` on a
``sim.engine.SimEngine`` (the bytes are those of a TCP match): it connects, inits and beams, is moved to a
clear spot at the zero pose, stands for ``SETTLE_S``, plays the motion, then holds its last pose for
``HOLD_S``. The joints are driven the only way an agent can, by joint velocities.

Which controller plays the motion: the agent's own (``agent.motion.MotionController`` through
``ControllerPlayer``), so the preview shows what a match shows; ``behavior_factory`` swaps in another.

Fell: the torso's up axis z component below 0.6 (REFERENCE §8.1's criterion), at any time of the run.
"""

from __future__ import annotations

import logging
import math
import threading
import time
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from agent.agent import Agent, AgentConfig, Behavior
from agent.motion import MotionController, MotionLibrary, MotionRequest, load_dynamic_params
from agent.protocol.effectors import Action, JointVelocity
from agent.world_model import WorldModel
from motions import Motion
from sim.engine import FrozenReferee, SimEngine
from sim.inprocess import InProcessHost
from agent.protocol.constants import CYCLE_S

logger = logging.getLogger(__name__)

#: Seconds of standing at the zero pose before the motion starts (the robot lands from its beam height).
SETTLE_S = 0.5
#: Seconds the last pose is held after the motion ends (does it stay up?).
HOLD_S = 1.0
#: Seconds a robot laid on the ground lies still before the motion starts (it drops 0.12 m - its torso's
#: half depth - and comes to rest).
LYING_SETTLE_S = 1.0
#: Starts of a run: standing at the zero pose, or lying (``motion_studio.scenarios.lay_robot_down``) on the
#: back, the front, or the side (on the back turned 90 deg about the long axis: the right side down).
STARTS = ("standing", "back", "front", "side")
#: Torso up-axis z below this counts as fallen (REFERENCE §8.1).
FALLEN_UP_Z = 0.6
#: Where the robot plays, field frame [m]: clear of the ball at the centre spot and of the goals.
FIELD_SPOT_M = (-5.0, 0.0)
#: Cycles for scene, init and beam before the robot is moved to FIELD_SPOT_M.
CONNECT_CYCLES = 8
#: Display-frame position of the simulated robot's start [m] (the kinematic robot stands at the origin).
DISPLAY_OFFSET_M = (0.5, 0.0)


class PreviewCancelled(Exception):
    """The caller's cancel event was set; the run stopped early."""


@dataclass
class PreviewResult:
    """A finished physics run, in the editor's display frame (robot facing +y, start at DISPLAY_OFFSET_M).

    times_s: motion time of each sample (0 = motion start; negative while settling) [s], shape (n,).
    torso_height_m: torso centre height above the ground [m], (n,).
    com_m: whole-robot centre of mass [m], (n, 3).
    up_z: z component of the torso's up axis (1 upright), (n,).
    body_poses: per sample, SimSpark body name -> 4x4 pose [m] (for drawing the simulated robot).
    fell: whether the robot fell (up_z < FALLEN_UP_Z); fall_time_s: first such time, else None. From a lying
    start (``start`` not "standing") the robot is down at first: fell then means down at any time after the
    motion ended (it did not get up, or not for good).
    motion_duration_s: the motion's length; controller: which controller played it.
    cycles: simulated cycles; wall_s: wall time of the run [s].
    """

    times_s: np.ndarray
    torso_height_m: np.ndarray
    com_m: np.ndarray
    up_z: np.ndarray
    body_poses: list[dict[str, np.ndarray]] = field(repr=False)
    fell: bool
    fall_time_s: float | None
    motion_duration_s: float
    controller: str
    cycles: int
    wall_s: float
    start: str = "standing"

    def sample_index(self, t_s: float) -> int:
        """Index of the sample nearest to motion time ``t_s``."""
        index = int(np.searchsorted(self.times_s, t_s))
        if index >= len(self.times_s):
            return len(self.times_s) - 1
        if index > 0 and t_s - self.times_s[index - 1] < self.times_s[index] - t_s:
            return index - 1
        return index

    def summary(self) -> dict[str, object]:
        """Plain numbers for a panel or a report."""
        shown = self.times_s >= 0.0
        return {"start": self.start, "fell": self.fell, "fall_time_s": self.fall_time_s, "controller": self.controller,
                "motion_duration_s": self.motion_duration_s, "cycles": self.cycles, "wall_s": self.wall_s,
                "min_torso_height_m": float(self.torso_height_m[shown].min()) if shown.any() else None,
                "final_torso_height_m": float(self.torso_height_m[-1])}


class ControllerPlayer:
    """A Behavior that plays one motion once with the agent's own motion controller (``agent.motion``).

    Why the agent's controller: the preview must show what a match will show, with the same playback
    (phase durations in cycles, action-delay compensation, blending from the start pose, dynamic
    elements of ``motions/params/dynamic_elements.toml``). The motion is requested for its authored
    length; a cyclic motion (a walk looping on ``next``) then gets its stop request and ends through its
    ``finalize`` phases, as in a match when the behaviour stops walking.

    Args:
        motion: the motion (played under its own name in a one-motion library).
        robot_type: 0-4 (the joints commanded).
    """

    name = "agent.motion.MotionController"
    #: A cyclic motion that has not ended this long after its stop request is cut off [s].
    STOP_LIMIT_S = 5.0

    def __init__(self, motion: Motion, robot_type: int = 0) -> None:
        self.motion = motion
        self.controller = MotionController(MotionLibrary({motion.name: motion}), load_dynamic_params(),
                                           robot_type=robot_type)
        self.cycle_s = CYCLE_S
        self.started = False
        self.calls_since_start = 0

    def start(self) -> None:
        """Begin playing at the next cycle."""
        self.started = True
        self.calls_since_start = 0

    @property
    def time_s(self) -> float:
        """Motion time of the last command sent [s]."""
        return self.calls_since_start * self.cycle_s

    @property
    def finished(self) -> bool:
        """The motion has ended (or was cut off ``STOP_LIMIT_S`` after its stop request)."""
        if not self.started or self.calls_since_start == 0:
            return False
        return self.controller.idle or self.time_s > self.motion.duration_s + self.STOP_LIMIT_S

    def __call__(self, world: WorldModel) -> list[Action]:
        if not self.started or not world.body.joints_rad:
            return []
        self.calls_since_start += 1
        playing = self.time_s <= self.motion.duration_s + 1e-9 and self.controller.completed[self.motion.name] == 0
        self.controller.request(MotionRequest(self.motion.name if playing else None))
        angles_deg = {name: math.degrees(value) for name, value in world.body.joints_rad.items()}
        velocities = self.controller.update(angles_deg, world.now_s, world.body.gyro_deg_s)
        return [JointVelocity(effector, value) for effector, value in velocities.items()]


def _finished(player: Behavior, motion: Motion) -> bool:
    """Whether ``player`` is done: its own ``finished`` if it has one, else the motion's length has passed."""
    finished = getattr(player, "finished", None)
    return bool(finished) if finished is not None else getattr(player, "time_s", 0.0) >= motion.duration_s


def _display_transform(position_m: np.ndarray, heading_deg: float) -> np.ndarray:
    """4x4 map from the field frame to the display frame: the robot at ``position_m`` facing ``heading_deg``
    ends up at DISPLAY_OFFSET_M facing +y (the kinematic robot's forward)."""
    turn = math.radians(90.0 - heading_deg)
    rotation = np.array([[math.cos(turn), -math.sin(turn), 0.0], [math.sin(turn), math.cos(turn), 0.0],
                         [0.0, 0.0, 1.0]])
    transform = np.eye(4)
    transform[:3, :3] = rotation
    start = rotation @ np.array([position_m[0], position_m[1], 0.0])
    transform[:3, 3] = [DISPLAY_OFFSET_M[0] - start[0], DISPLAY_OFFSET_M[1] - start[1], 0.0]
    return transform


def run_physics_preview(motion: Motion, robot_type: int = 0,
                        progress: Callable[[float], None] | None = None,
                        cancel: threading.Event | None = None,
                        behavior_factory: Callable[[Motion, int], Behavior] | None = None,
                        hold_s: float = HOLD_S, start: str = "standing") -> PreviewResult:
    """Play ``motion`` on a simulated robot and record its torso, CoM and body poses every cycle.

    Args:
        motion: the motion to play (not changed).
        robot_type: 0-4.
        progress: called with the fraction done (0..1) every few cycles.
        cancel: when set, the run stops and raises PreviewCancelled.
        behavior_factory: (motion, robot_type) -> the agent behavior that plays it and has ``start()``;
            default ``ControllerPlayer``.
        hold_s: seconds recorded after the motion ends.
        start: one of STARTS: standing, or lying on the back, front or side (a stand-up's start).

    Returns:
        The recorded run (see PreviewResult).

    Raises:
        PreviewCancelled: ``cancel`` was set.
        ValueError: ``start`` is not one of STARTS.
    """
    if start not in STARTS:
        raise ValueError(f"start must be one of {', '.join(STARTS)}, got {start!r}")
    wall_start = time.perf_counter()
    tracker = (behavior_factory or ControllerPlayer)(motion, robot_type)
    engine = SimEngine(seed=0, referee=FrozenReferee())
    host = InProcessHost(engine)
    agent = Agent(AgentConfig("preview", 1, robot_type, say=False), tracker)
    key = host.add(agent)
    host.run(CONNECT_CYCLES)
    world = engine.world
    world.place_robot(key, FIELD_SPOT_M[0], FIELD_SPOT_M[1], 0.0)
    if start != "standing":
        from motion_studio.scenarios import lay_robot_down

        lay_robot_down(world, key, "front" if start == "front" else "back", twist_deg=90.0 if start == "side" else 0.0)
    robot = world.by_key[key]
    masses = world.model.body_mass[robot.body_ids]
    display = _display_transform(world.torso_position(key), world.heading_deg(key))
    cycle_s = world.params.cycle_s
    settle_cycles = round((SETTLE_S if start == "standing" else LYING_SETTLE_S) / cycle_s)
    hold_cycles = math.ceil(hold_s / cycle_s)
    # Estimated length for the progress bar; the run lasts until the player says the motion ended.
    total = settle_cycles + math.ceil(motion.duration_s / cycle_s) + hold_cycles
    times, heights, coms, ups, poses = [], [], [], [], []
    cycle, ended_at = 0, None
    while ended_at is None or cycle < ended_at + hold_cycles:
        if cancel is not None and cancel.is_set():
            raise PreviewCancelled("physics preview cancelled")
        if cycle == settle_cycles:
            tracker.start()
        host.run(1)
        t_s = tracker.time_s if cycle >= settle_cycles else (cycle - settle_cycles) * cycle_s
        rotation = world.torso_rotation(key)
        torso = world.torso_position(key)
        com = masses @ world.data.xipos[robot.body_ids] / masses.sum()
        times.append(t_s)
        heights.append(float(torso[2]))
        coms.append(display[:3, :3] @ com + display[:3, 3])
        ups.append(float(rotation[2, 2]))
        bodies = {}
        xpos, xmat = world.data.xpos, world.data.xmat
        for name, body in zip(robot.body_names, robot.body_ids):
            pose = np.eye(4)
            pose[:3, :3], pose[:3, 3] = xmat[body].reshape(3, 3), xpos[body]
            bodies[name] = display @ pose
        poses.append(bodies)
        if ended_at is None and cycle >= settle_cycles and _finished(tracker, motion):
            ended_at = cycle
            total = cycle + hold_cycles
        cycle += 1
        if progress is not None and cycle % 10 == 0:
            progress(min(cycle / max(total, 1), 1.0))
    if progress is not None:
        progress(1.0)
    up = np.array(ups)
    times_arr = np.array(times)
    judged = up if start == "standing" else np.where(np.arange(len(up)) >= (ended_at or 0), up, 1.0)
    fallen = np.flatnonzero(judged < FALLEN_UP_Z)
    fall_time = float(times_arr[fallen[0]]) if len(fallen) else None
    result = PreviewResult(times_arr, np.array(heights), np.array(coms), up, poses, bool(len(fallen)), fall_time,
                           motion.duration_s, getattr(tracker, "name", type(tracker).__name__),
                           engine.cycle, time.perf_counter() - wall_start, start)
    logger.info("physics preview of %r: %d cycles in %.2f s, %s", motion.name, result.cycles, result.wall_s,
                "fell" if result.fell else "stayed up")
    return result
