"""The agent's core: ``Agent.step(sense: bytes) -> bytes``, pure (no sockets, clocks, files or prints).

Transports wrap it: :mod:`agent.runner` over TCP, sim/'s in-process host directly. The connection sequence
of REFERENCE §3.2 lives here as data: :meth:`Agent.connect_message` is the ``scene`` command, the first
answer carries ``init``, beams follow the formation (once per beam-allowed play mode or when the target
changes: beaming every cycle crashes the real server, §3.7), and every answer ends with ``(syn)``.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

from agent.communication import messages, slots
from agent.errors import ConfigError
from agent.formation import DEFAULT_FORMATION, BeamSpot, beam_spot, kick_off_spot
from agent.localization import DEFAULT_LOCALIZER, LOCALIZERS
from agent.protocol.constants import HALF_LENGTH_M, HALF_WIDTH_M
from agent.protocol.effectors import Action, Beam, Init, Say, Scene, Syn, format_actions
from agent.protocol.sense import parse_sense
from agent.world_model import WorldModel
from kinematics.spec import ROBOT_TYPES

#: A behaviour: the updated world model -> this cycle's actions (joint velocities, pass...). The motion
#: controller and skills plug in here; the default does nothing, so the robot keeps its joint velocities.
Behavior = Callable[[WorldModel], list[Action]]
#: The ball counts as known for team messages if seen within this time [s].
BALL_FRESH_S = 1.0
#: Positions farther outside the field lines than this are not told to teammates [m]: a robot trying to stand up
#: from its side once believed the ball 54 m away, beyond what a message carries (±38.72 m), and the encoder's
#: error ended its step (our simulator, 2026-11-26).
TELL_OUTSIDE_FIELD_M = 3.0
#: ... and a ball farther away than that field's diagonal is not told either [m].
TELL_BALL_WITHIN_M = math.hypot(2.0 * (HALF_LENGTH_M + TELL_OUTSIDE_FIELD_M),
                                2.0 * (HALF_WIDTH_M + TELL_OUTSIDE_FIELD_M))
HETERO_RSG = "rsg/agent/nao/nao_hetero.rsg"
#: After a goal the agent beams to its kick-off spot only this many cycles into the Goal_* mode (it lasts 3 s):
#: the behaviour has stopped the walk into the stance by then. Beamed in the goal's first cycle, players in
#: mid-stride were set down on one foot and fell, on both servers (3 v 3: most of our falls against robots
#: that only stand came at the beam after a goal). The same at half time (BeforeKickOff with the game clock past
#: 0; both servers wait 3 s there before the second half's kick-off): 11 v 11 on ours, a player walking at 300 s
#: fell at its beam.
GOAL_BEAM_DELAY_CYCLES = 50


@dataclass(frozen=True)
class AgentConfig:
    """Who the agent is and which methods it uses.

    Raises:
        ConfigError: unum outside 0-11, unknown robot type, an empty or bad team name, unknown localizer.
    """

    team: str
    """Team name (printable ASCII, no spaces or parentheses; the first team name the server sees is left)."""
    unum: int = 0
    """Requested uniform number, 1-11, or 0 for the next free one."""
    robot_type: int = 0
    """Heterogeneous robot type 0-4 (``nao_hetero.rsg`` with that parameter)."""
    localization: str = DEFAULT_LOCALIZER
    """Localizer name: ``ekf`` (default) or ``seed`` (triangulation + FIFO, REFERENCE §7.5)."""
    formation: str = DEFAULT_FORMATION
    """Beam-spot table (agent.formation.FORMATIONS)."""
    say: bool = True
    """Take part in the time-sliced team communication."""

    def __post_init__(self) -> None:
        if isinstance(self.unum, bool) or not isinstance(self.unum, int) or not 0 <= self.unum <= 11:
            raise ConfigError(f"unum must be 0-11 (0 = next free), got {self.unum!r}", "unum")
        if self.robot_type not in ROBOT_TYPES:
            raise ConfigError(f"robot type must be one of {list(ROBOT_TYPES)}, got {self.robot_type!r}", "type")
        if not self.team or any(not 0x21 <= ord(c) <= 0x7E or c in "()" for c in self.team):
            raise ConfigError(f"team name {self.team!r} must be printable ASCII without spaces or parentheses",
                              "team")
        if self.localization not in LOCALIZERS:
            raise ConfigError(f"unknown localization {self.localization!r}; known: {', '.join(LOCALIZERS)}",
                              "localization")


def _idle(world: WorldModel) -> list[Action]:
    return []


class Agent:
    """One soccer agent as a pure function of the sense messages it has seen.

    Args:
        config: identity and methods.
        behavior: what to do each cycle once the world model is updated (default: nothing).
    """

    def __init__(self, config: AgentConfig, behavior: Behavior | None = None) -> None:
        self.config = config
        self.behavior = behavior or _idle
        self.world = WorldModel(config.team, config.unum, config.robot_type, config.localization)
        self._init_sent = False
        self._beamed_for: tuple[float, float, float, float] | None = None
        self._said_hello = False
        self.said: list[str] = []
        """Team messages said so far (latest last; capped at 100), for tests and logs."""

    def connect_message(self) -> bytes:
        """The first message on a new connection: ``(scene rsg/agent/nao/nao_hetero.rsg T)`` (REFERENCE §3.2)."""
        return format_actions([Scene(HETERO_RSG, self.config.robot_type)])

    def step(self, sense: bytes) -> bytes:
        """One cycle: a sense message in, this cycle's effector message out.

        Raises:
            agent.protocol.errors.ProtocolError: a malformed sense message; nothing in the agent changed
                (the transport logs it, answers ``(syn)`` and goes on).
        """
        parsed = parse_sense(sense)  # first: a bad message must leave the beliefs untouched
        # Beliefs before decisions: init, beam, behaviour and the team message all read this cycle's world.
        self.world.update(parsed)
        actions = self._connection_actions() + self.behavior(self.world)
        # Say after the behaviour so the message reports what the agent now believes; syn last, because it
        # ends this agent's cycle in sync mode.
        actions += self._team_message()
        actions.append(Syn())
        return format_actions(actions)

    # --- connection sequence: init, then beam -------------------------------------------------------------
    def _connection_actions(self) -> list[Action]:
        if not self._init_sent:
            self._init_sent = True
            return [Init(self.config.unum, self.config.team)]
        game = self.world.game
        if not game.beam_allowed or game.unum is None or game.side is None:
            return []
        mid_game = game.play_mode.startswith("Goal_") or (game.play_mode == "BeforeKickOff" and game.game_time_s > 0.0)
        if mid_game and game.play_mode_cycles < GOAL_BEAM_DELAY_CYCLES:
            return []  # the stance first (see GOAL_BEAM_DELAY_CYCLES)
        spot = beam_spot(game.unum, self.config.formation)
        if game.play_mode.lower() == f"goal_{game.side}":
            # We scored: the opponents kick off next, so no spot inside the centre circle or on its line.
            x, y = kick_off_spot(spot.x_m, spot.y_m, game.unum, opponents_kick_off=True)
            spot = BeamSpot(x, y, spot.rot_deg)
        # One beam per beam-allowed play-mode period (keyed by when it began), or when the target changes.
        key = (game.play_mode_since_s, spot.x_m, spot.y_m, spot.rot_deg)
        if key == self._beamed_for:
            return []
        self._beamed_for = key
        return [Beam(spot.x_m, spot.y_m, spot.rot_deg)]

    # --- time-sliced team message (REFERENCE §7.9) ----------------------------------------------------------
    def _team_message(self) -> list[Action]:
        world, game = self.world, self.world.game
        if not self.config.say or game.unum is None or game.side is None:
            return []
        if not slots.may_say(game.unum, game.play_mode_cycles):
            return []
        text = messages.encode(self.compose_message(), self.config.team)
        self.said = self.said[-99:] + [text]
        return [Say(text)]

    def compose_message(self) -> messages.TeamMessage:
        """This slot's message: ``i`` once, then ``c`` (self + ball), ``l`` (self), ``b`` (ball only) or
        ``x`` (fallen or lost), by what the world model knows (REFERENCE §7.9 table)."""
        world = self.world
        unum = world.unum
        if not self._said_hello:
            self._said_hello = True
            return messages.TeamMessage("i", unum)
        if world.body.fallen:
            return messages.TeamMessage("x", unum)
        pose = world.pose if world.localized else None
        ball = world.ball if world.ball is not None and world.ball.age_s(world.now_s) <= BALL_FRESH_S else None
        if ball is not None and ((ball.position is not None and not _on_field(ball.position))
                                 or (ball.distance_m or 0.0) > TELL_BALL_WITHIN_M):
            ball = None
        if pose is not None and _on_field((pose.x_m, pose.y_m)):
            position = (pose.x_m, pose.y_m)
            if ball is not None and ball.position is not None:
                return messages.TeamMessage("c", unum, position=position, ball=ball.position)
            return messages.TeamMessage("l", unum, position=position)
        if ball is not None and ball.distance_m is not None:
            return messages.TeamMessage("b", unum, ball_distance_m=ball.distance_m,
                                        ball_angle_rad=ball.bearing_rad or 0.0)
        return messages.TeamMessage("x", unum)


def _on_field(point: tuple[float, float]) -> bool:
    """Within TELL_OUTSIDE_FIELD_M of the field (team frame) [m]."""
    return (abs(point[0]) <= HALF_LENGTH_M + TELL_OUTSIDE_FIELD_M
            and abs(point[1]) <= HALF_WIDTH_M + TELL_OUTSIDE_FIELD_M)


__all__ = ["Agent", "AgentConfig", "Behavior"]
