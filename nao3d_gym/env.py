"""`Nao3DEnv`: one Nao on the in-process SimSpark world as a Gymnasium environment, one step per 20 ms cycle.

The environment is the agent: each step it sends the 22 joint velocities as effector bytes and reads the
sense message back through the same parser a real agent uses (agent.protocol), so a policy trained here
sees what it would see on rcssserver3d, with the same one-cycle action delay (REFERENCE §3.9). Resets use
trainer commands (REFERENCE §5.2) to put the robot and the ball back, and the world's joint reset (no
trainer command sets joint angles), so no server restarts between episodes.
"""

from __future__ import annotations

import math
from typing import Any

import gymnasium
import numpy as np
from gymnasium import spaces

from agent.protocol.constants import BALL_RADIUS_M, CYCLE_S
from agent.protocol.effectors import Init, Scene, format_actions, joint_velocity_template
from agent.protocol.numbers import AGENT_FLOAT_DECIMALS
from agent.protocol.sense import parse_sense
from kinematics.spec import ROBOT_TYPES, robot_spec
from nao3d_gym.observation import ObservationReader, PerceptorRowReader, fixed_floats
from nao3d_gym.tasks import TASKS, StepState, fallen
from sim.engine import SimEngine
from sim.rules.trainer import apply_trainer_message
from sim.vision import VisionConfig

TEAM = "Nao3DGym"
#: Where an episode starts: the torso above the field point (x, y) [m] facing +x, the ball off the path.
START_XY_M = (-5.0, 0.0)
BALL_START_M = (0.0, 5.0, BALL_RADIUS_M)
#: Gap [m] between the soles and the grass when the robot is put down (it lands within the settle cycles).
DROP_GAP_M = 0.005


class Nao3DEnv(gymnasium.Env):
    """A Nao of one robot type on the SimSpark field, alone (the referee in PlayOn, the ball aside).

    Observation: float32 vector of `nao3d_gym.observation.observation_names` (joint angles [rad], gyro
    [rad/s], accelerometer [m/s²], foot contact points [m] and forces [N]). Action: one target velocity
    [rad/s] per hinge in spec order (22 for types 0-3, 24 for type 4), clipped to each joint's speed limit
    (6.1395 rad/s, REFERENCE §2.2). Reward and termination: `nao3d_gym.tasks`.

    Args:
        task: "stand" or "walk" (`nao3d_gym.tasks.TASKS`).
        robot_type: 0-4 (REFERENCE §2.5).
        settle_cycles: zero-velocity cycles after a reset, so the robot has landed and the first observation
            reflects the new episode (the sense message of a cycle is made at its end).
        init_noise_rad: joint angles at reset are drawn uniformly within this of the zero pose (seeded).
        vision: compute vision (``See`` every third message, in `last_sense` only: the observation has none).
            Off by default, which saves a third of a step's cost. Implies ``text_sense``.
        text_sense: send each action as effector text and read each observation from the parsed sense
            message (`last_sense` then holds it). Off by default: the env hands the engine the joint
            velocities the text would spell and reads the perceptor values the message would be written
            from, each through the text's rounding (``%.4f``, ``%.2f``), which gives the same physics and
            the same observations bit for bit (tests/nao3d_gym/test_fast_path.py) at a fifth less cost.
    """

    metadata = {"render_modes": [], "render_fps": 50}

    def __init__(self, task: str = "stand", robot_type: int = 0, settle_cycles: int = 25,
                 init_noise_rad: float = 0.02, vision: bool = False, text_sense: bool = False) -> None:
        if task not in TASKS:
            raise ValueError(f"task must be one of {sorted(TASKS)}, got {task!r}")
        if robot_type not in ROBOT_TYPES:
            raise ValueError(f"robot_type must be one of {list(ROBOT_TYPES)}, got {robot_type!r}")
        if settle_cycles < 2:
            raise ValueError(f"settle_cycles must be >= 2 (the first message after a reset is stale), "
                             f"got {settle_cycles}")
        if not 0.0 <= init_noise_rad <= 0.5:
            raise ValueError(f"init_noise_rad must be within 0..0.5, got {init_noise_rad}")
        self.task = task
        self.robot_type = robot_type
        self.settle_cycles = settle_cycles
        self.init_noise_rad = init_noise_rad
        self.vision = vision
        self.text_sense = text_sense or vision
        self._reward = TASKS[task]
        spec = robot_spec(robot_type)
        self.joints = spec.joints
        self._stand_z_m = -spec.sole_z_m + DROP_GAP_M
        self._min_rad = np.array([j.min_rad for j in self.joints])
        self._max_rad = np.array([j.max_rad for j in self.joints])
        self._reader = ObservationReader(self.joints)
        self.observation_space = spaces.Box(self._reader.low, self._reader.high, dtype=np.float32)
        speed = np.array([j.max_speed_rad_s for j in self.joints], dtype=np.float32)
        self.action_space = spaces.Box(-speed, speed, dtype=np.float32)
        self._speed = speed.astype(np.float64)
        self._low_speed = -self._speed
        self._command = joint_velocity_template([j.effector for j in self.joints]) + b"(syn)"
        self._rest = self._command % ((0.0,) * len(self.joints))
        # The fast path (see text_sense): effector names and the one printf format of all velocities.
        self._effectors = tuple(j.effector for j in self.joints)
        self._rest_values = [0.0] * len(self.joints)
        from sim.perceptors import wire_joint_order
        feet = tuple(s.name for s in spec.sensors if s.kind == "force")
        self._row_reader = PerceptorRowReader(self.joints, wire_joint_order(robot_type)[0], feet)
        self._next_observation = np.zeros(self._reader.size, dtype=np.float32)
        self._engine: SimEngine | None = None
        self._agent_id = 0
        self._torso_m = np.zeros(3)
        self._steps = 0
        self.last_sense = b""
        """The last raw sense message (vision and hearing included, for users who want more than the
        observation); with ``text_sense`` (or ``vision``) only, else it stays empty."""

    # ---- gymnasium API ---------------------------------------------------------------------------------
    def reset(self, *, seed: int | None = None, options: dict[str, Any] | None = None) -> tuple[np.ndarray, dict]:
        """Start an episode: robot upright at `START_XY_M` facing +x, joints near zero, ball aside.

        Trainer commands put the robot and the ball back and restart the game clock; the engine's noise
        generator is reseeded from the environment's, so a seed fixes the whole episode.
        """
        super().reset(seed=seed)
        engine = self._engine or self._connect()
        engine.rng = np.random.default_rng(int(self.np_random.integers(2**63)))
        x, y = START_XY_M
        bx, by, bz = BALL_START_M
        # (move x y z angle): SimSpark's angle 0 faces +y, so -90 faces +x.
        trainer = (f"(playMode PlayOn)(time 0)(agent (unum 1)(team Left)(move {x} {y} {self._stand_z_m:.4f} -90))"
                   f"(ball (pos {bx} {by} {bz})(vel 0 0 0))")
        apply_trainer_message(trainer, engine.referee, engine.world)
        noise = self.np_random.uniform(-self.init_noise_rad, self.init_noise_rad, len(self.joints))
        engine.world.reset_joints(self._agent_id, np.clip(noise, self._min_rad, self._max_rad))
        observation = self._next_observation
        for _ in range(self.settle_cycles):
            observation = self._cycle(self._rest, self._rest_values)
        self._torso_m = engine.world.torso_position(self._agent_id)
        self._steps = 0
        return observation, self._info()

    def step(self, action: np.ndarray) -> tuple[np.ndarray, float, bool, bool, dict]:
        """One 20 ms cycle with these joint velocities [rad/s] (clipped to the speed limits)."""
        engine = self._engine
        if engine is None:
            raise gymnasium.error.ResetNeeded("call reset() before step()")
        # minimum/maximum: np.clip's values at a third of its call overhead.
        velocity = np.minimum(np.maximum(np.asarray(action, dtype=np.float64), self._low_speed), self._speed)
        if not np.isfinite(velocity).all():
            raise ValueError(f"action must be finite, got {action!r}")
        if self.text_sense:
            values = velocity.tolist()
            observation = self._cycle(self._command % tuple(values), values)
        else:   # the floats the "%.4f" text would be read back as
            observation = self._cycle(b"", fixed_floats(velocity, AGENT_FLOAT_DECIMALS).tolist())
        self._steps += 1
        world = engine.world
        before, self._torso_m = self._torso_m, world.torso_position(self._agent_id)
        state = StepState(before, self._torso_m, float(world.torso_rotation(self._agent_id)[2, 2]),
                          world.params.cycle_s, velocity / self._speed)
        return observation, float(self._reward(state)), fallen(state), False, self._info()

    def close(self) -> None:
        self._engine = None

    # ---- helpers -----------------------------------------------------------------------------------------
    def _connect(self) -> SimEngine:
        """A new engine with this robot connected and on the left team (REFERENCE §3.2: scene, then init)."""
        engine = SimEngine(seed=0, vision=VisionConfig(enabled=self.vision))
        engine.sense_text = self.text_sense
        self._agent_id = engine.connect()
        engine.receive(self._agent_id, format_actions([Scene("rsg/agent/nao/nao_hetero.rsg", self.robot_type)]))
        engine.step()
        engine.receive(self._agent_id, format_actions([Init(1, TEAM)]) + b"(syn)")
        engine.step()
        self._engine = engine
        return engine

    def _cycle(self, command: bytes, velocities: list[float]) -> np.ndarray:
        """Send one action and step one cycle; the observation of the sense message that step hands back.

        Text path: ``command`` as bytes, the message parsed. Fast path: ``velocities`` straight into the
        engine, and the observation the engine's message of the last step would have given, which was
        read from the perceptor values at that step's end (the message of a cycle is handed back by the
        next step: REFERENCE §3.9's one-cycle delay, kept).
        """
        engine = self._engine
        assert engine is not None
        if self.text_sense:
            engine.receive(self._agent_id, command)
            return self._observe(engine.step()[self._agent_id])
        engine.receive_joint_velocities(self._agent_id, self._effectors, velocities)
        engine.step()
        observation = self._next_observation
        world = engine.world
        values, masks = world.perceptor_rows()
        row = world.row[self._agent_id]
        self._next_observation = self._row_reader.read(values[row], masks[row])
        return observation

    def _observe(self, sense: bytes) -> np.ndarray:
        self.last_sense = sense
        return self._reader.read(parse_sense(sense))

    def _info(self) -> dict[str, Any]:
        """Torso centre [m] (field frame) and the episode's simulated time [s] (steps x 20 ms)."""
        return {"torso_position_m": self._torso_m.copy(), "episode_time_s": round(self._steps * CYCLE_S, 6)}


__all__ = ["Nao3DEnv"]
