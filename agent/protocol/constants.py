"""The simulated world's shared facts, defined once: the cycle length and the field, goal and ball geometry.

Why here: the agent and sim/ must agree on them to the last digit (the agent localises against the landmarks
sim/ draws, counts cycles sim/ steps), and agent.protocol is the one room both import (DESIGN.md,
Conventions). Values are rcssserver3d 0.7.3's (REFERENCE §1 and §4.1); frame: the field frame, origin at
the centre spot, x toward the right team's goal, y left, z up, metres.
"""

from __future__ import annotations

#: One server cycle: simulated time per step, perceptor period, effector period [s] (REFERENCE §1).
CYCLE_S = 0.02

FIELD_LENGTH_M = 30.0
FIELD_WIDTH_M = 20.0
HALF_LENGTH_M = FIELD_LENGTH_M / 2.0
HALF_WIDTH_M = FIELD_WIDTH_M / 2.0
#: Goal: width between the posts, crossbar height, depth behind the goal line [m].
GOAL_WIDTH_M = 2.1
GOAL_HALF_WIDTH_M = GOAL_WIDTH_M / 2.0
GOAL_HEIGHT_M = 0.8
GOAL_DEPTH_M = 0.6
#: Penalty area: depth from the goal line, half width [m]; its front line is at |x| = PENALTY_AREA_X_M.
PENALTY_DEPTH_M = 1.8
PENALTY_HALF_WIDTH_M = 3.0
PENALTY_AREA_X_M = HALF_LENGTH_M - PENALTY_DEPTH_M
CENTRE_CIRCLE_RADIUS_M = 2.0
#: The centre circle is drawn (and seen) as this many straight chords.
CENTRE_CIRCLE_CHORDS = 10
BALL_RADIUS_M = 0.042
BALL_MASS_KG = 0.026
#: Radius of the cylinder the referee treats a player as (crowding, set-piece clearance) [m].
AGENT_RADIUS_M = 0.4
#: A kick-off, kick-in, free kick, goal kick or corner kick nobody takes within this ends in a drop ball [s]
#: (REFERENCE §4.3; the server's DropBallTime).
DROP_BALL_TIME_S = 15.0

#: Vision landmarks -> (x, y, z) [m], in the order the server lists them in ``See`` (goal posts seen at
#: their top). Measured order: G1L G2L G2R G1R, then the flags (tests/sim/test_vision.py, recorded samples).
LANDMARKS: dict[str, tuple[float, float, float]] = {
    "G1L": (-HALF_LENGTH_M, GOAL_HALF_WIDTH_M, GOAL_HEIGHT_M),
    "G2L": (-HALF_LENGTH_M, -GOAL_HALF_WIDTH_M, GOAL_HEIGHT_M),
    "G2R": (HALF_LENGTH_M, -GOAL_HALF_WIDTH_M, GOAL_HEIGHT_M),
    "G1R": (HALF_LENGTH_M, GOAL_HALF_WIDTH_M, GOAL_HEIGHT_M),
    "F1L": (-HALF_LENGTH_M, HALF_WIDTH_M, 0.0),
    "F2L": (-HALF_LENGTH_M, -HALF_WIDTH_M, 0.0),
    "F1R": (HALF_LENGTH_M, HALF_WIDTH_M, 0.0),
    "F2R": (HALF_LENGTH_M, -HALF_WIDTH_M, 0.0),
}
