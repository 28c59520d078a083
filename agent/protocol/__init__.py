"""agent.protocol: the project's one definition of the rcssserver3d wire language.

Framing (4-byte big-endian length prefix), the S-expression reader and writer, typed sense messages
(parse on the agent, format byte-exact on our server), effector commands (format on the agent, parse on our
server) and monitor messages. No I/O beyond the two blocking socket helpers in :mod:`.framing`.
"""

from agent.protocol.effectors import (
    Action,
    Beam,
    Init,
    InvalidAction,
    JointVelocity,
    ParsedAction,
    PassMode,
    Say,
    Scene,
    Syn,
    UnknownAction,
    check_say_message,
    format_actions,
    format_joint_velocities,
    parse_actions,
)
from agent.protocol.errors import ProtocolError
from agent.protocol.framing import FrameDecoder, frame, read_frame, write_frame
from agent.protocol.monitor import MonitorMessage, format_game_state, format_monitor, parse_monitor
from agent.protocol.perceptors import (
    Accelerometer,
    AgentState,
    ForceResistance,
    GameState,
    Gyro,
    Hear,
    HingeJoint,
    Polar,
    See,
    Sense,
    TimePerceptor,
    VisibleLine,
    VisibleObject,
    VisiblePlayer,
)
from agent.protocol.sense import format_sense, parse_sense
from agent.protocol.sexpr import format_sexpr, parse_sexpr

__all__ = [
    "Accelerometer",
    "Action",
    "AgentState",
    "Beam",
    "ForceResistance",
    "FrameDecoder",
    "GameState",
    "Gyro",
    "Hear",
    "HingeJoint",
    "Init",
    "InvalidAction",
    "JointVelocity",
    "MonitorMessage",
    "ParsedAction",
    "PassMode",
    "Polar",
    "ProtocolError",
    "Say",
    "Scene",
    "See",
    "Sense",
    "Syn",
    "TimePerceptor",
    "UnknownAction",
    "VisibleLine",
    "VisibleObject",
    "VisiblePlayer",
    "check_say_message",
    "format_actions",
    "format_game_state",
    "format_joint_velocities",
    "format_monitor",
    "format_sense",
    "format_sexpr",
    "frame",
    "parse_actions",
    "parse_monitor",
    "parse_sense",
    "parse_sexpr",
    "read_frame",
    "write_frame",
]
