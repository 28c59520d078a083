"""The agent's beliefs as RoboViz shapes: self pose, ball, teammates, the target it walks to and its role.

Pure: an `Agent` in, packets out (`agent.drawing.udp` sends them). Everything is drawn where the agent
believes it is, in field coordinates, so RoboViz shows the belief beside the truth: a self circle away from
the robot is a localization error. One set per robot (`set_name`), swapped at the end of each frame.
"""

from __future__ import annotations

import math
from typing import Any

from agent.agent import Agent
from agent.drawing import roboviz
from agent.protocol.constants import BALL_RADIUS_M

#: A teammate or the ball is drawn as current when heard or seen within this time [s], greyed after.
FRESH_S = 1.0
SELF_RADIUS_M = 0.25
HEADING_LENGTH_M = 0.5
TEAMMATE_RADIUS_M = 0.2
BALL_DRAWN_RADIUS_M = 0.06   # a little larger than the ball, so it shows beside RoboViz's own ball
ANNOTATION_HEIGHT_M = 0.9
TEAM_COLOURS = {"left": (40, 110, 255), "right": (255, 60, 40)}
BALL_COLOUR = (255, 140, 0)
TARGET_COLOUR = (255, 0, 255)
STALE_COLOUR = (150, 150, 150)
TEXT_COLOUR = (255, 255, 255)


def set_name(side: str | None, unum: int) -> str:
    """This robot's drawing set, ``nao3d.L03``: two digits, so no robot's name is a prefix of another's
    (RoboViz swaps every set whose name starts with the swapped name, REFERENCE §5.5)."""
    return f"nao3d.{'R' if side == 'right' else 'L'}{unum:02d}"


def intent(behavior: Any) -> tuple[str | None, tuple[float, float] | None]:
    """(role, team-frame target) of a behaviour, for behaviours that have them: ``role`` (SoccerBehavior) and
    the running skill's ``target`` (WalkTo); (None, None) for the others."""
    role = getattr(behavior, "role", None)
    skill = getattr(getattr(behavior, "skills", None), "skill", None)
    target = getattr(skill, "target", None)
    if not (isinstance(target, tuple) and len(target) == 2 and all(isinstance(v, (int, float)) for v in target)):
        target = None
    return (role if isinstance(role, str) else None), target


def belief_packets(agent: Agent) -> list[bytes]:
    """One frame of drawings of ``agent``'s beliefs, ending with the swap of its set; [] before it knows its
    side and number (RoboViz could not tell whose drawings they are)."""
    world = agent.world
    game = world.game
    if game.side is None or game.unum is None:
        return []
    name = set_name(game.side, game.unum)
    colour = TEAM_COLOURS[game.side]
    now = world.now_s
    frame = world.frame
    packets: list[bytes] = []
    pose = world.world_pose()
    if pose is not None:
        x, y = pose.x_m, pose.y_m
        packets.append(roboviz.circle((x, y), SELF_RADIUS_M, 3.0, colour if world.localized else STALE_COLOUR, name))
        tip = (x + HEADING_LENGTH_M * math.cos(pose.heading_rad), y + HEADING_LENGTH_M * math.sin(pose.heading_rad))
        packets.append(roboviz.line((x, y, 0.0), (*tip, 0.0), 3.0, colour, name))
    ball = world.ball
    if ball is not None and ball.position is not None:
        bx, by = frame.point_to_world(*ball.position)
        fresh = ball.age_s(now) <= FRESH_S
        packets.append(roboviz.sphere((bx, by, BALL_RADIUS_M), BALL_DRAWN_RADIUS_M, BALL_COLOUR if fresh else STALE_COLOUR, name))
    for unum, mate in sorted(world.teammates.items()):
        if mate.position is None or unum == game.unum:
            continue
        mx, my = frame.point_to_world(*mate.position)
        fresh = mate.age_s(now) <= FRESH_S
        packets.append(roboviz.circle((mx, my), TEAMMATE_RADIUS_M, 2.0, colour if fresh else STALE_COLOUR, name))
        packets.append(roboviz.annotation(str(unum), (mx, my, 0.3), TEXT_COLOUR, name))
    role, target = intent(agent.behavior)
    if target is not None:
        tx, ty = frame.point_to_world(*target)
        packets.append(roboviz.point((tx, ty, 0.0), 8.0, TARGET_COLOUR, name))
        if pose is not None:
            packets.append(roboviz.line((pose.x_m, pose.y_m, 0.01), (tx, ty, 0.01), 1.5, TARGET_COLOUR, name))
    if role is not None:
        packets.append(roboviz.agent_annotation(game.side, game.unum, f"{game.unum} {role}", colour))
    packets.append(roboviz.swap_buffers(name))
    return packets
