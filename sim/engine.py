"""The simulation engine without transport: agents in, bytes out, one 20 ms cycle per `SimEngine.step`.

Hosts (sim.tcp_server over TCP, sim.inprocess without sockets) call `connect`, pass every received frame
payload to `receive`, and send what `step` returns. Bad input is logged with the agent id and counted in
`SimEngine.errors`; it never raises.

The per-cycle order is rcssserver3d's (REFERENCE §3.9), written once in `SimEngine.step`:
1. apply the actions received since the last step (init moves the robot now; says are delivered now);
2. sample the accelerometers, then apply beams (SimSpark's beam acts after that sample);
3. hand back the sense messages made at the end of the previous step;
4. physics step; the referee's update; body poses refreshed;
5. make this step's sense messages, to be handed back by the next `step`.
Because the host sends step k's output after step k returns and the agent's reply is applied in step k+1,
an action sent in reply to sense message k first shows in message k+2, as measured on the real server.
"""

from __future__ import annotations

import logging
from collections import Counter
from dataclasses import dataclass, field
from typing import Any, NamedTuple

import numpy as np

from agent.protocol.effectors import (Beam, Init, InvalidAction, JointVelocity, PassMode, Say, Scene, Syn,
                                      UnknownAction, parse_actions, split_joint_commands)
from agent.protocol.errors import ProtocolError
from agent.protocol.perceptors import GameState, Hear
from agent.protocol.sense_template import (PRINTF_NUMBER, SPELLED_NUMBER, SenseTemplate, game_state_bytes,
                                           hear_bytes, time_bytes)
from sim.fixed2 import SPELL_MIN_VALUES, spell_fixed2
from sim.hearing import Hearing, Listener, Speaker
from sim.perceptors import wire_joint_order
from sim.physics_params import PhysicsParams
from sim.rules.self_collision import BodyPoseArrays
from sim.vision import CALIBRATION_ERROR_M, Observer, PlayerParts, SeeWriter, VisionConfig, observe, see
from sim.rows import row_index
from sim.world import VISIBLE_PARTS, World

logger = logging.getLogger(__name__)

#: REFERENCE §3.7: beam noise and the allowed area (team frame, StartAnyFieldPosition false).
BEAM_NOISE_M = 0.05
BEAM_NOISE_DEG = 10.0
BEAM_X_RANGE_M = (-15.0, 0.0)
BEAM_Y_RANGE_M = (-10.0, 10.0)
BEAM_HEIGHT_M = 0.4
#: Vision every third perceptor cycle (REFERENCE §3.5).
VISION_INTERVAL = 3
#: Errors logged per agent at WARNING before the rest go to DEBUG (a broken agent must not flood the log).
LOGGED_ERRORS_PER_AGENT = 20
_SCENES = {"rsg/agent/nao/nao.rsg": False, "rsg/agent/nao/nao_hetero.rsg": True}


class _JointCommands(NamedTuple):
    """The joint commands of one usual message (see `SimEngine.receive`): names and velocities [rad/s]."""

    names: tuple[str, ...]
    values: list[float]


_MISSING = object()
#: Head-body tuples whose pose-row indices are kept (see `SimEngine._head_rows`); the cache is cleared past this.
_HEAD_ROWS_KEPT = 64
#: Name orders whose motor-bank positions are kept (agents send one order; the cache is cleared past this).
_USUAL_POSITIONS_KEPT = 256


@dataclass
class AgentLink:
    """One connection: its robot (once scene arrived), team, and what it sent since the last step.

    key: agent id (also the robot's key in the world); team: team name after a successful init; side /
    unum: "left"/"right" and 1-11 then; perceptor_cycles: sense messages made so far (vision phase).
    """

    key: int
    robot_type: int | None = None
    team: str | None = None
    side: str | None = None
    unum: int | None = None
    calibration_m: np.ndarray = field(default_factory=lambda: np.zeros(3))
    pending: list[Any] = field(default_factory=list)
    synced: bool = False
    announce_identity: bool = False
    perceptor_cycles: int = 0
    created_cycle: int = -1
    errors: int = 0


class FrozenReferee:
    """A stand-in referee: BeforeKickOff forever, time frozen, beam allowed, REFERENCE §3.2 init spots.

    Used by tests that need no rules; `SimEngine` uses `sim.referee.Referee` unless told otherwise.
    """

    play_mode = "BeforeKickOff"
    game_time_s = 0.0
    score_left = 0
    score_right = 0

    def __init__(self) -> None:
        self._teams: dict[str, str] = {}
        self._unums: dict[str, set[int]] = {"left": set(), "right": set()}
        self._next_y = {"left": 9.2, "right": 9.2}

    def allows_beam(self) -> bool:
        return True

    def update(self, world: Any) -> None:
        return None

    def on_init(self, team: str, unum: int, robot_type: int = 0) -> Any:
        from sim.referee import Assignment
        side = self._teams.get(team)
        if side is None:
            if len(self._teams) == 2:
                return None
            side = "left" if not self._teams else "right"
            self._teams[team] = side
        if unum == 0:
            unum = next((n for n in range(1, 12) if n not in self._unums[side]), 0)
        if not 1 <= unum <= 11 or unum in self._unums[side]:
            return None
        self._unums[side].add(unum)
        y = self._next_y[side]
        self._next_y[side] -= 1.2
        x = -14.2 if side == "left" else 14.2
        return Assignment(side, unum, (x, y, 0.4), 0.0 if side == "left" else 180.0)

    def on_leave(self, side: str, unum: int, robot_type: int = 0) -> None:
        self._unums[side].discard(unum)

    def request_pass(self, side: str, unum: int) -> bool:
        return False


class SimEngine:
    """The rcssserver3d-compatible simulation, one `step` per 20 ms cycle.

    Args:
        seed: seed of every random draw (calibration, beam and vision noise): same seed, same bytes.
        sync: sync mode (the host waits for every agent's ``(syn)`` before stepping; see `ready`).
        referee: the rules (default `sim.referee.Referee(seed=seed)`); `FrozenReferee` for no rules.
        physics: MuJoCo settings (`sim.physics_params.default_physics_params()` if None).
        vision: vision switches (noise, calibration, lines).
    """

    def __init__(self, seed: int = 0, sync: bool = True, referee: Any = None, physics: PhysicsParams | None = None,
                 vision: VisionConfig | None = None) -> None:
        if referee is None:
            from sim.referee import Referee
            referee = Referee(seed=seed)
        if getattr(referee, "body_pose_source", False) is None:
            # The self-collision rule reads every robot's body poses each cycle: hand it views of MuJoCo's
            # pose arrays (no copies), so the rule is on in-process as under the TCP server.
            referee.body_pose_source = self.robot_body_poses
        self.seed = seed
        self.sync = sync
        self.referee = referee
        self.world = World(physics)
        self.vision = vision or VisionConfig()
        self.rng = np.random.default_rng(seed)
        self.hearing = Hearing()
        self.agents: dict[int, AgentLink] = {}
        self.errors: Counter[int] = Counter()
        self.cycle = 0
        self._next_id = 1
        self.sense_text = True
        """False: `step` makes no sense messages (it returns none) while the perceptor cycles still count;
        for a host that reads the same values from `World.perceptor_rows` itself (nao3d_gym's fast path).
        Physics and rules do not depend on it."""
        self._outbox: dict[int, bytes] = {}
        self._hears: dict[int, list[Hear]] = {}
        self._bank_positions: dict[tuple[int, int], dict[str, int]] = {}
        self._usual_bank_positions: dict[tuple[int, int, tuple[str, ...]], tuple[np.ndarray, bool] | None] = {}
        self._see_writer = SeeWriter(VISIBLE_PARTS)
        # The plain (GS ...) of the last cycle and what it was written from (it rarely changes).
        self._game_state: tuple[tuple[Any, ...], bytes] = ((), b"")
        # Visible-part bodies of the robots with a team, for vision: (their keys, world layout, flat xpos indices).
        self._part_bodies: tuple[tuple[int, ...], int, np.ndarray] = ((), -1, np.zeros(0, dtype=np.intp))
        self._head_row_cache: dict[tuple[int, ...], tuple[np.ndarray, np.ndarray]] = {}

    # ---- connections ---------------------------------------------------------------------------------
    def connect(self) -> int:
        """A new agent connection; returns its id (its robot appears with its ``scene`` command)."""
        key = self._next_id
        self._next_id += 1
        self.agents[key] = AgentLink(key)
        return key

    def disconnect(self, agent_id: int) -> None:
        """Drop an agent and its robot; its uniform number is free again. Unknown ids are ignored."""
        link = self.agents.pop(agent_id, None)
        if link is None:
            return
        self._outbox.pop(agent_id, None)
        self.hearing.forget(agent_id)
        if link.side is not None and link.unum is not None and hasattr(self.referee, "on_leave"):
            self.referee.on_leave(link.side, link.unum, link.robot_type or 0)
        if agent_id in self.world.by_key:
            self.world.remove_robot(agent_id)

    def receive(self, agent_id: int, payload: bytes) -> None:
        """Queue one frame payload of an agent; applied at the start of the next `step`. Never raises."""
        link = self.agents.get(agent_id)
        if link is None:
            self._error(None, f"message from unknown agent id {agent_id}")
            return
        # The usual message (joint commands and (syn)) skips the action objects; its pattern admits only
        # ASCII, so latin-1 decoding cannot hide a bad byte from it.
        joints = split_joint_commands(payload.decode("latin-1") if isinstance(payload, bytes) else payload)
        if joints is not None:
            names, values, syn = joints
            if names:
                link.pending.append(_JointCommands(tuple(names), values))
            link.synced = link.synced or syn
            return
        try:
            actions = parse_actions(payload)
        except ProtocolError as error:
            self._error(link, f"malformed message dropped: {error}")
            return
        for action in actions:
            if isinstance(action, Syn):
                link.synced = True
            elif isinstance(action, UnknownAction):
                self._error(link, f"unknown effector {action.name!r} at byte {action.offset}")
            elif isinstance(action, InvalidAction):
                self._error(link, f"invalid {action.name!r} at byte {action.offset}: {action.reason}")
            else:
                link.pending.append(action)

    def receive_joint_velocities(self, agent_id: int, names: tuple[str, ...], values: list[float]) -> None:
        """What `receive` does with a usual message ``(EFF F)...(syn)`` whose text was already split into
        ``names`` and the floats its numbers spell: the in-process env skips writing and re-reading the
        text (the values must be those the text would give, e.g. ``float("%.4f" % v)``)."""
        link = self.agents.get(agent_id)
        if link is None:
            self._error(None, f"message from unknown agent id {agent_id}")
            return
        if names:
            link.pending.append(_JointCommands(names, values))
        link.synced = True

    def ready(self) -> bool:
        """Sync mode: True when every agent with a robot has sent ``(syn)`` since the last step (or is in its
        first 4 perceptor cycles, which count as synced, REFERENCE §3.9)."""
        return all(link.synced or link.perceptor_cycles < 4 for link in self.agents.values()
                   if link.key in self.world.by_key)

    @property
    def time_s(self) -> float:
        """Server time [s]: cycles so far x 20 ms."""
        return round(self.cycle * self.world.params.cycle_s, 9)

    # ---- the cycle -----------------------------------------------------------------------------------
    def step(self) -> dict[int, bytes]:
        """One 20 ms cycle (order in the module docstring); returns agent id -> sense payload (unframed),
        the messages made at the end of the previous step."""
        out = self.begin_step()
        self.finish_step()
        return out

    def begin_step(self) -> dict[int, bytes]:
        """The first half of `step` (its points 1-3): actions applied, beams done; returns what `step` returns.

        The messages are final here, before the physics step: a host may hand them to its agents now and run
        `finish_step` while they think (sim.agent_processes), as long as it passes their replies to `receive`
        only after `finish_step` returned (that one clears every agent's ``(syn)``). ``begin_step`` then
        ``finish_step`` is `step`, byte for byte.
        """
        beams = self._apply_actions()
        self.world.begin_cycle()
        for link, beam in beams:
            self._beam(link, beam)
        out, self._outbox = self._outbox, {}
        return out   # made for connected agents only (`disconnect` drops a leaving agent's message)

    def finish_step(self) -> dict[int, bytes]:
        """The second half of `step` (its points 4-5): physics, referee, poses, this step's sense messages.

        Returns:
            the messages just made, the dict the next `begin_step` hands back (the same object; `disconnect`
            drops a leaving agent's message from it): final now, so a host may pass them on at once
            (sim.agent_processes does, so its agents think while the engine waits for the previous cycle's
            replies and applies them).
        """
        self.world.step()
        self.cycle += 1
        self.referee.update(self.world)
        self.world.end_cycle()
        self._outbox = self._percepts()
        for link in self.agents.values():
            link.synced = False
        return self._outbox

    def _apply_actions(self) -> list[tuple[AgentLink, Beam]]:
        beams: list[tuple[AgentLink, Beam]] = []
        speakers: list[Speaker] = []
        motor_index: list[int] = []        # bank positions and velocities of the general path
        motor_value: list[float] = []
        index_arrays: list[np.ndarray] = []   # the usual path: one cached position array per message
        value_lists: list[float] = []
        whole_blocks = 0                      # of those, arrays that command every joint of their robot
        for link in list(self.agents.values()):
            pending = link.pending
            if not pending:
                continue
            link.pending = []
            if len(pending) == 1 and type(pending[0]) is _JointCommands:   # the usual cycle: one joint message
                usual = self._usual_positions(link, pending[0].names)
                if usual is not None:
                    index_arrays.append(usual[0])
                    whole_blocks += usual[1]
                    value_lists += pending[0].values
                    continue
            joints: dict[str, float] = {}
            for action in pending:
                if type(action) is _JointCommands:   # joint commands of a usual message (see `receive`)
                    joints.update(zip(action.names, action.values))
                elif isinstance(action, JointVelocity):
                    if not action.finite:
                        self._error(link, f"non-finite value for {action.effector} ignored")
                    else:
                        joints[action.effector] = action.velocity_rad_s
                elif isinstance(action, Scene):
                    self._scene(link, action)
                elif isinstance(action, Init):
                    self._init(link, action)
                elif isinstance(action, Beam):
                    if not action.finite:
                        self._error(link, "non-finite beam ignored")
                    else:
                        beams.append((link, action))
                elif isinstance(action, Say):
                    if link.team is None or link.key not in self.world.by_key:
                        self._error(link, "say before a successful init ignored")
                    else:
                        speakers.append(Speaker(link.key, link.team, link.side or "left",
                                                tuple(self.world.torso_position(link.key)), action.message))
                elif isinstance(action, PassMode):
                    if link.side is not None and hasattr(self.referee, "request_pass"):
                        self.referee.request_pass(link.side, link.unum)
            if joints:
                self._joints(link, joints, motor_index, motor_value)
        motors = self.world.motors
        if whole_blocks == len(index_arrays) and not motor_index and len(value_lists) == motors.target.size > 0:
            # Every robot commanded every joint once (one robot per link, so the blocks cover the bank).
            bank = np.empty(len(value_lists))
            bank[index_arrays[0] if len(index_arrays) == 1 else np.concatenate(index_arrays)] = value_lists
            motors.command_all(bank, self.world.data.qpos, self.world.time_s)
        else:
            if motor_index:
                index_arrays.append(np.array(motor_index, dtype=np.intp))
                value_lists += motor_value
            if index_arrays:
                motors.command_many(index_arrays[0] if len(index_arrays) == 1 else np.concatenate(index_arrays),
                                    np.array(value_lists), self.world.data.qpos, self.world.time_s)
        if speakers:
            listeners = [Listener(link.key, link.team or "", link.side or "",
                                  tuple(self.world.torso_position(link.key)))
                         for link in self.agents.values() if link.key in self.world.by_key]
            self._hears = self.hearing.deliver(speakers, listeners, self.referee.game_time_s)
        else:
            self.hearing.refill(list(self.world.by_key))
            self._hears = {}
        return beams

    def _scene(self, link: AgentLink, scene: Scene) -> None:
        if link.key in self.world.by_key:
            self._error(link, "second scene command ignored")
            return
        hetero = _SCENES.get(scene.path)
        if hetero is None:
            self._error(link, f"unknown scene {scene.path!r}; expected one of {sorted(_SCENES)}")
            return
        robot_type = scene.robot_type if hetero and scene.robot_type is not None else 0
        if not 0 <= robot_type <= 4:
            self._error(link, f"unknown robot type {robot_type} in scene")
            return
        try:
            self.world.add_robot(link.key, robot_type)
        except ValueError as error:
            self._error(link, f"robot not created: {error}")
            return
        link.robot_type = robot_type
        link.created_cycle = self.cycle + 1
        link.calibration_m = self.rng.uniform(-CALIBRATION_ERROR_M, CALIBRATION_ERROR_M, 3)

    def _init(self, link: AgentLink, init: Init) -> None:
        if link.key not in self.world.by_key:
            self._error(link, "init before scene ignored")
            return
        if link.team is not None:
            self._error(link, "second init ignored")
            return
        assignment = self.referee.on_init(init.team, init.unum, link.robot_type or 0)
        if assignment is None:
            self._error(link, f"init refused (team {init.team!r}, unum {init.unum})")
            return
        link.team, link.side, link.unum = init.team, assignment.side, assignment.unum
        link.announce_identity = True
        self.world.set_team(link.key, assignment.side, assignment.unum)
        x, y, z = assignment.position_m
        self.world.place_robot(link.key, x, y, assignment.heading_deg, z)

    def _usual_positions(self, link: AgentLink, names: tuple[str, ...]) -> tuple[np.ndarray, bool] | None:
        """Motor-bank positions of a usual message's joints and whether they are all the robot's joints (cached
        per robot type, bank block and name order), or None when `_joints` must take it: no robot yet, a
        name twice, or an effector the robot type lacks."""
        robot = self.world.by_key.get(link.key)
        if robot is None:
            return None
        start = self.world.motors.blocks[link.key].start
        key = (robot.robot_type, start, names)
        usual = self._usual_bank_positions.get(key, _MISSING)
        if usual is _MISSING:
            effectors = _effector_index(robot.robot_type)
            usual = None
            if len(set(names)) == len(names) and all(name in effectors for name in names):
                usual = (np.array([start + effectors[name] for name in names], dtype=np.intp),
                         len(names) == len(effectors))
            if len(self._usual_bank_positions) >= _USUAL_POSITIONS_KEPT:   # odd agents vary the order
                self._usual_bank_positions.clear()
            self._usual_bank_positions[key] = usual
        return usual

    def _joints(self, link: AgentLink, values: dict[str, float], index: list[int], velocity: list[float]) -> None:
        """Collect one agent's joint commands as motor-bank positions (applied together afterwards)."""
        if link.key not in self.world.by_key:
            self._error(link, "joint command before scene ignored")
            return
        robot_type = link.robot_type or 0
        start = self.world.motors.blocks[link.key].start
        positions = self._bank_positions.get((robot_type, start))
        if positions is None:
            positions = self._bank_positions[(robot_type, start)] = {
                effector: start + i for effector, i in _effector_index(robot_type).items()}
        try:
            index.extend(list(map(positions.__getitem__, values)))   # all or nothing
            velocity.extend(values.values())
        except KeyError:   # an effector this robot type lacks: take the known ones, report the others
            for effector, value in values.items():
                position = positions.get(effector)
                if position is None:
                    self._error(link, f"robot type {link.robot_type} has no joint effector {effector!r}")
                    continue
                index.append(position)
                velocity.append(value)

    def _beam(self, link: AgentLink, beam: Beam) -> None:
        """REFERENCE §3.7: allowed play modes, clamp, noise, team frame, upright at z 0.4, velocities zeroed."""
        if link.side is None or link.key not in self.world.by_key:
            self._error(link, "beam before a successful init ignored")
            return
        if not self.referee.allows_beam():
            return
        x = min(max(beam.x_m, BEAM_X_RANGE_M[0]), BEAM_X_RANGE_M[1])
        y = min(max(beam.y_m, BEAM_Y_RANGE_M[0]), BEAM_Y_RANGE_M[1])
        dx, dy, drot = self.rng.uniform(-1.0, 1.0, 3) * (BEAM_NOISE_M, BEAM_NOISE_M, BEAM_NOISE_DEG)
        x, y, rot = x + dx, y + dy, beam.rot_deg + drot
        if link.side == "right":
            x, y, rot = -x, -y, rot + 180.0
        self.world.place_robot(link.key, x, y, rot, BEAM_HEIGHT_M)

    # ---- perceptors ----------------------------------------------------------------------------------
    def _percepts(self) -> dict[int, bytes]:
        world = self.world
        # A new robot's perceptors start one cycle after the step that built it: measured, its first message
        # shows two steps of free fall (vision height, and ACC 29.42 = 2 g + g when init stops the fall).
        links = [link for link in self.agents.values()
                 if link.key in world.by_key and self.cycle > link.created_cycle]
        if not links:
            return {}
        if not self.sense_text:
            for link in links:
                link.perceptor_cycles += 1
            return {}
        values, frp_masks = world.perceptor_rows()
        spelled = values.size >= SPELL_MIN_VALUES
        # Every float of every robot spelled at once, or (few robots) handed to printf templates as floats.
        values = spell_fixed2(values).tolist() if spelled else values.tolist()
        sees = self._vision_bytes(links)
        referee = self.referee
        out = {}
        try:
            now = time_bytes(self.time_s)
            state_key = (referee.score_left, referee.score_right, referee.game_time_s, referee.play_mode)
            if state_key != self._game_state[0]:
                self._game_state = (state_key, game_state_bytes(GameState(None, None, *state_key)))
            plain_state = self._game_state[1]
        except ProtocolError as error:   # e.g. a play mode that is no atom: never crash the cycle
            for link in links:
                link.perceptor_cycles += 1
                self._error(link, f"sense message not formatted: {error}")
            return out
        for link in links:
            row = world.row[link.key]
            link.perceptor_cycles += 1
            try:
                game_state = plain_state
                if link.announce_identity:
                    link.announce_identity = False
                    game_state = game_state_bytes(GameState(link.unum, link.side, referee.score_left,
                                                            referee.score_right, referee.game_time_s,
                                                            referee.play_mode))
                hears = self._hears.get(link.key)
                out[link.key] = _sense_template(link.robot_type or 0, spelled).format(
                    values[row], now, game_state, frp_masks[row], sees.get(link.key),
                    [hear_bytes(hear) for hear in hears] if hears else ())
            except ProtocolError as error:   # e.g. a team name that is no atom: never crash the cycle
                self._error(link, f"sense message not formatted: {error}")
        return out

    def _vision_bytes(self, links: list[AgentLink]) -> dict[int, bytes]:
        """The See predicate of every robot that sees this cycle, written straight from the vision arrays."""
        if not self.vision.enabled:
            return {}
        seeing = [link for link in links if link.perceptor_cycles % VISION_INTERVAL == 0]
        if not seeing:
            return {}
        world = self.world
        data = world.data
        players = [link for link in self.agents.values() if link.team is not None and link.key in world.by_key]
        keys = tuple(link.key for link in players)
        if keys != self._part_bodies[0] or world.layout_version != self._part_bodies[1]:
            bodies = [world.by_key[key].part_bodies for key in keys]
            self._part_bodies = (keys, world.layout_version,
                                 row_index(np.concatenate(bodies) if bodies else np.zeros(0, dtype=np.intp), 3))
        xpos_index, xmat_index = self._head_rows(tuple(world.by_key[link.key].head_body for link in seeing))
        a = world.ball_qadr
        sighting = observe(world.xpos_flat[xpos_index].reshape(-1, 3), world.xmat_flat[xmat_index].reshape(-1, 3, 3),
                           np.array([link.calibration_m for link in seeing]), data.qpos[a:a + 3],
                           world.xpos_flat[self._part_bodies[2]].reshape(-1, 3), self.rng, self.vision)
        frames = self._see_writer.frames(sighting, tuple((link.team, link.unum or 0) for link in players))
        return {link.key: frame for link, frame in zip(seeing, frames)}

    def _head_rows(self, heads: tuple[int, ...]) -> tuple[np.ndarray, np.ndarray]:
        """Flat indices (`sim.world.row_index`) of these head bodies' rows of xpos and xmat, kept per tuple of
        body ids (which robots see in a cycle follows a few fixed patterns)."""
        rows = self._head_row_cache.get(heads)
        if rows is None:
            if len(self._head_row_cache) >= _HEAD_ROWS_KEPT:
                self._head_row_cache.clear()
            bodies = np.array(heads, dtype=np.intp)
            rows = self._head_row_cache[heads] = (row_index(bodies, 3), row_index(bodies, 9))
        return rows

    def _vision(self, links: list[AgentLink]) -> dict[int, Any]:
        world = self.world
        seeing = [link for link in links if link.perceptor_cycles % VISION_INTERVAL == 0]
        if not seeing:
            return {}
        data = world.data
        players = []
        for link in self.agents.values():
            robot = world.by_key.get(link.key)
            if robot is not None and link.team is not None:
                players.append(PlayerParts(link.team, link.unum or 0, data.xpos[robot.part_bodies], VISIBLE_PARTS))
        observers = []
        for link in seeing:
            robot = world.by_key[link.key]
            observers.append(Observer(data.xpos[robot.head_body], data.xmat[robot.head_body].reshape(3, 3),
                                      link.calibration_m, link.team or "", link.unum or 0))
        frames = see(observers, np.array(world.ball_position()), players, self.rng, self.vision)
        return {link.key: frame for link, frame in zip(seeing, frames)}

    def robot_body_poses(self) -> list[tuple[str | None, int, int, BodyPoseArrays]]:
        """Per robot in connection order: (side or None, unum or 0, robot type, body name -> (centre [m],
        row-major 3x3 rotation)), as `sim.world.World.robot_body_poses` but over the world's whole pose arrays
        (the centres with ODE's joint drift), which the self-collision rule gathers for all robots at once."""
        positions, rotations = self.world.body_centres(), self.world.data.xmat   # shared by every robot
        return [(robot.side, robot.unum or 0, robot.robot_type, BodyPoseArrays(robot.body_rows, positions, rotations))
                for robot in self.world.by_key.values()]

    # ---- errors --------------------------------------------------------------------------------------
    def _error(self, link: AgentLink | None, text: str) -> None:
        key = link.key if link is not None else -1
        self.errors[key] += 1
        if link is not None:
            link.errors += 1
        level = logging.WARNING if self.errors[key] <= LOGGED_ERRORS_PER_AGENT else logging.DEBUG
        logger.log(level, "agent %d: %s", key, text)


_EFFECTOR_INDEX: dict[int, dict[str, int]] = {}
_SENSE_TEMPLATES: dict[tuple[int, bool], SenseTemplate] = {}


def _sense_template(robot_type: int, spelled: bool = True) -> SenseTemplate:
    """The sense-message writer of a robot type: its joints in wire order, its foot sensors in spec order
    (the order of `World.perceptor_rows`), numbers spelled beforehand (`sim.fixed2`) or, not ``spelled``,
    floats for printf."""
    template = _SENSE_TEMPLATES.get((robot_type, spelled))
    if template is None:
        from kinematics.spec import robot_spec
        feet = [sensor.name for sensor in robot_spec(robot_type).sensors if sensor.kind == "force"]
        template = _SENSE_TEMPLATES[(robot_type, spelled)] = SenseTemplate(
            wire_joint_order(robot_type)[0], feet, number=SPELLED_NUMBER if spelled else PRINTF_NUMBER)
    return template


def _effector_index(robot_type: int) -> dict[str, int]:
    if robot_type not in _EFFECTOR_INDEX:
        from kinematics.spec import robot_spec
        _EFFECTOR_INDEX[robot_type] = {j.effector: i for i, j in enumerate(robot_spec(robot_type).joints)}
    return _EFFECTOR_INDEX[robot_type]

