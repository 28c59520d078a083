"""The world model: everything the agent believes, updated once per sense message, in the team frame.

Positions are in the agent's team frame (own goal at −x; :class:`~agent.world.frames.TeamFrame` converts to
and from the world frame), angles in radians, times in server seconds. Each tracked object keeps its last
sighting; ``age_s(now)`` says how stale it is.
"""

from __future__ import annotations

import logging
import math

import numpy as np

from agent.communication.messages import TeamMessage, decode
from agent.communication.slots import cycles_elapsed
from agent.errors import MessageError
from agent.localization import DEFAULT_LOCALIZER, Localizer, make_localizer
from agent.protocol.perceptors import Sense
from agent.world import mat3
from agent.world.field import FIELD_LINES, LANDMARKS, goal_kick_drop_m
from agent.world.frames import Pose2D, TeamFrame, wrap_angle_rad
from agent.world.ball_track import BallTrack
from agent.world.objects import TeammateReport, Tracked
from agent.world.orientation import OrientationFilter
from agent.world.state import BodyState, GameInfo
from agent.world.vision import VisionFrame, vision_frame
from kinematics.fk import NaoKinematics
from kinematics.spec import robot_spec
from agent.protocol.constants import CYCLE_S, DROP_BALL_TIME_S

logger = logging.getLogger(__name__)


class WorldModel:
    """Beliefs of one agent.

    Args:
        team: own team name (to tell teammates from opponents in vision and hear).
        unum: requested uniform number (replaced by the server's answer once it comes).
        robot_type: 0-4, for the camera-height kinematics.
        localization: localizer name (``ekf`` default, ``seed``).
        localization_options: parameters for the localizer, by name.
    """

    def __init__(self, team: str, unum: int, robot_type: int = 0, localization: str = DEFAULT_LOCALIZER,
                 **localization_options: float) -> None:
        self.team = team
        self.requested_unum = unum
        self.robot_type = robot_type
        self.game = GameInfo()
        self.body = BodyState()
        self.orientation = OrientationFilter()
        self.kinematics = NaoKinematics(robot_type)
        self._joint_order = robot_spec(robot_type).joint_names
        self._localization = (localization, localization_options)
        self.frame = TeamFrame("left")
        self.localizer: Localizer = self._new_localizer()
        self.last_vision: VisionFrame | None = None
        self.ball: Tracked | None = None
        self.ball_track = BallTrack()
        """The ball's recent team-frame sightings: its velocity and where it will stop (``agent.world.ball_track``)."""
        self.teammates: dict[int, Tracked] = {}
        """Unum -> last sighting (vision) or report (say), whichever is newer."""
        self.opponents: dict[int, Tracked] = {}
        """Unum (0 when the server sent none) -> last sighting."""
        self.landmarks: dict[str, Tracked] = {}
        """Flag/goal-post name -> last sighting."""
        self.reports: dict[int, TeammateReport] = {}
        """Unum -> the teammate's last decoded message."""
        self.own_report: TeammateReport | None = None
        """The own last team message as the server echoed it (what the teammates know about us)."""
        self.ignored_messages = 0
        """Heard messages dropped: the other team's, or ours that failed to decode (garbled, foreign)."""
        self._clock_seen = False
        self._last_yaw: float | None = None
        self._odometry: tuple[float, float] | None = None

    def report_odometry(self, forward_m: float, left_m: float) -> None:
        """Torso displacement the motion controller made since the last sense message, ego frame [m].

        Summed until the next :meth:`update`, where the localizer's prediction uses it (without it the
        localizer assumes unknown motion, REFERENCE §7.5 has no odometry).
        """
        f, l = self._odometry or (0.0, 0.0)
        self._odometry = (f + forward_m, l + left_m)

    # --- update: one sense message ----------------------------------------------------------------------
    def update(self, sense: Sense) -> None:
        """Fold one parsed sense message into the beliefs.

        The order matters: time first (everything is stamped with it); then the body, because projecting
        vision needs this cycle's head angles and torso tilt; then the localizer's prediction to now
        before its correction from vision; objects after localization, since their team-frame positions go
        through the corrected pose; hear last, since it refers to the side and the own unum.
        """
        self._update_game(sense)
        self._update_body(sense)
        yaw = self.orientation.yaw_rad
        odometry, self._odometry = self._odometry, None
        self.localizer.predict(0.0 if self._last_yaw is None else wrap_angle_rad(yaw - self._last_yaw), odometry)
        self._last_yaw = yaw
        if sense.see is not None:
            frame = self._project(sense)
            self.last_vision = frame
            if not self.body.fallen:  # lying down, "height above the soles" is no camera height
                self.localizer.correct(frame)
            self._update_objects(frame)
        for hear in sense.hears:
            self._hear(hear.team, hear.direction_deg is None, hear.game_time_s, hear.message)

    def _update_game(self, sense: Sense) -> None:
        game = self.game
        game.cycles += 1
        if sense.time is not None:
            if self._clock_seen:
                game.play_mode_cycles += cycles_elapsed(game.server_time_s, sense.time.now_s)
            else:
                game.play_mode_cycles = round(sense.time.now_s / CYCLE_S)
                self._clock_seen = True
            game.server_time_s = sense.time.now_s
        gs = sense.game_state
        if gs is None:
            return
        game.game_time_s = gs.game_time_s
        if gs.play_mode != game.play_mode:
            # How long the ending mode lasted, when its start was seen (not for the mode an agent connected into).
            lasted_s = game.server_time_s - game.play_mode_since_s if game.play_mode_since_s > 0.0 else 0.0
            ended = game.play_mode
            if game.play_mode != "unknown":
                game.play_mode_since_s = game.server_time_s
                game.play_mode_cycles = 0
            game.play_mode = gs.play_mode
            if gs.play_mode == "PlayOn" and ended.startswith("goal_kick_") and lasted_s >= DROP_BALL_TIME_S - CYCLE_S:
                self._ball_dropped(goal_kick_drop_m(ended.removeprefix("goal_kick_")))
        if gs.score_left is not None:
            game.score_left, game.score_right = gs.score_left, gs.score_right or 0
        if gs.unum is not None:
            game.unum = gs.unum
        if gs.team in ("left", "right") and gs.team != game.side:
            game.side = gs.team
            self.frame = TeamFrame(gs.team)
            self.localizer = self._new_localizer()  # landmark positions change frame
            self.ball, self.teammates, self.opponents = None, {}, {}
            self.ball_track.clear()

    def _ball_dropped(self, world_m: tuple[float, float]) -> None:
        """The referee dropped the ball at ``world_m`` (world frame) [m]: believe it there at once. The drop
        after an untaken goal kick moves the ball 3 m aside (``goal_kick_drop_m``), usually out of the camera's
        view, and the last sighting then kept the players walking to the empty goal-kick spot for 4-5 s (real
        server, 3 v 3 against robots that only stand)."""
        x, y = self.frame.point_from_world(*world_m)
        pose = self.localizer.pose
        forward, left = pose.to_ego(x, y) if pose is not None else (None, None)
        self.ball = Tracked(forward, left, x, y, self.game.server_time_s, source="referee")
        self.ball_track.clear()

    def _update_body(self, sense: Sense) -> None:
        body = self.body
        if sense.joints:
            body.joints_rad.update({name: math.radians(deg) for name, deg in sense.joints.items()})
        if sense.gyro is not None:
            body.gyro_deg_s = sense.gyro.rate_deg_s
        if sense.acc is not None:
            body.acc_m_s2 = sense.acc.acc_m_s2
        body.set_feet(sense.frp)
        self.orientation.update(sense.gyro.rate_deg_s if sense.gyro else None,
                                sense.acc.acc_m_s2 if sense.acc else None)
        tilt = self.orientation.tilt
        body.pitch_forward_rad, body.roll_right_rad = tilt.pitch_forward_rad, tilt.roll_right_rad
        body.up_z = self.orientation.up_z

    def _project(self, sense: Sense) -> VisionFrame:
        joints = self.body.joints_rad
        q = np.fromiter((joints.get(name, 0.0) for name in self._joint_order), float, len(self._joint_order))
        tilt = self.orientation.tilt_rotation
        self.body.camera_height_m = self.kinematics.camera_height_m(q, np.array(tilt))
        camera = self.kinematics.frame_pose("camera", q)
        rotation: mat3.Matrix = tuple(map(tuple, camera.rotation.tolist()))  # type: ignore[assignment]
        position: mat3.Vector = tuple(camera.position_m.tolist())  # type: ignore[assignment]
        return vision_frame(sense.see, self.game.server_time_s, tilt, rotation, position,  # type: ignore[arg-type]
                            self.body.camera_height_m, self.team, self.unum)

    def _update_objects(self, frame: VisionFrame) -> None:
        now = frame.time_s
        pose = self.localizer.pose

        def tracked(forward: float, left: float) -> Tracked:
            x, y = pose.to_team(forward, left) if pose is not None else (None, None)
            return Tracked(forward, left, x, y, now)

        for name, obs in frame.landmarks.items():
            self.landmarks[name] = tracked(obs.forward_m, obs.left_m)
        if frame.ball is not None:
            self.ball = tracked(frame.ball.forward_m, frame.ball.left_m)
            if self.ball.x_m is not None and self.ball.y_m is not None:
                self.ball_track.add(now, self.ball.x_m, self.ball.y_m)
        for player in frame.players:
            if player.team == self.team:
                if player.unum is not None:
                    self.teammates[player.unum] = tracked(player.forward_m, player.left_m)
            else:
                self.opponents[player.unum or 0] = tracked(player.forward_m, player.left_m)

    def _hear(self, team: str | None, is_self: bool, game_time_s: float, text: str) -> None:
        if is_self:
            self._hear_self(game_time_s, text)
            return
        if team is not None and team != self.team:
            self.ignored_messages += 1
            return
        try:
            message = decode(text, self.team)
        except MessageError as error:
            self.ignored_messages += 1
            logger.debug("ignored team message: %s", error)
            return
        self.apply_message(message, game_time_s)

    def _hear_self(self, game_time_s: float, text: str) -> None:
        """Keep the own message as the server echoed it: what every teammate heard about us, at the same
        cycle. Team decisions take the own position from it, so that every player decides on the same data
        (the own pose is fresher than what the others know, and that asymmetry made two players both
        believe they played the ball)."""
        try:
            message = decode(text, self.team)
        except MessageError:
            return
        self.own_report = TeammateReport(message.unum, message.kind, self.game.server_time_s, game_time_s,
                                         message.position, message.ball, None, active=message.kind != "x")

    def apply_message(self, message: TeamMessage, game_time_s: float) -> None:
        """Fold a teammate's decoded message in (its position becomes a ``say`` sighting of that teammate)."""
        now = self.game.server_time_s
        if message.kind == "a" or message.unum == self.unum:
            return  # actions are for the team layer; a message about ourselves tells us nothing
        report = TeammateReport(message.unum, message.kind, now, game_time_s, message.position, message.ball,
                                None if message.ball_distance_m is None
                                else (message.ball_distance_m, message.ball_angle_rad or 0.0),
                                active=message.kind != "x")
        self.reports[message.unum] = report
        if message.position is not None:
            self.teammates[message.unum] = Tracked(None, None, message.position[0], message.position[1], now, "say")

    def _new_localizer(self) -> Localizer:
        name, options = self._localization
        landmarks = {n: self.frame.point_from_world(p[0], p[1]) for n, p in LANDMARKS.items()}
        lines = tuple((self.frame.point_from_world(*a), self.frame.point_from_world(*b)) for a, b in FIELD_LINES)
        return make_localizer(name, landmarks, lines, **options)

    # --- beliefs -----------------------------------------------------------------------------------------
    @property
    def unum(self) -> int:
        """Own uniform number (the server's once known, else the requested one)."""
        return self.game.unum if self.game.unum is not None else self.requested_unum

    @property
    def now_s(self) -> float:
        """Server time of the latest sense message [s]."""
        return self.game.server_time_s

    @property
    def pose(self) -> Pose2D | None:
        """Self pose in the team frame, or None until localized once."""
        return self.localizer.pose

    @property
    def localized(self) -> bool:
        """The localizer is confident of the pose."""
        return self.localizer.localized

    def world_pose(self) -> Pose2D | None:
        """Self pose in the world (field) frame."""
        pose = self.pose
        return None if pose is None else self.frame.pose_to_world(pose)
