"""One kick on our simulator, measured: the real agent stands in the walk stance (``stand``), the ball is put
where the kick motion expects it (its constants ``ball_forward_m`` / ``ball_left_m``, plus a placement
error), then the agent plays the kick (``PlayMotion``); ground truth gives where the ball comes to rest,
whether the robot fell and when the foot touched the ball. Shared by the kick tuner and the kick benchmark.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from agent.motion import MotionController, MotionLibrary, load_dynamic_params
from agent.motion.dynamic import DynamicParams
from agent.skills.base import PlayMotion
from motion_studio.scenarios import Scenario, Truth
from agent.protocol.constants import CYCLE_S

#: Cycles of standing in the stance before the ball is placed (the stance is reached and settled).
SETTLE_CYCLES = 30
#: The ball counts as struck once it moves faster than this [m/s] (a nudge while the robot shifts its
#: weight is no strike).
STRIKE_SPEED_M_S = 0.3
#: The ball rests when slower than this [m/s] (drag makes its speed decay only exponentially).
REST_SPEED_M_S = 0.01
#: A foot moving up faster than this, or the torso faster than TRAP_TORSO_M_S, right at the contact means
#: the ball was trapped under the foot and the stiff contact threw the leg up (see the kick report).
TRAP_FOOT_UP_M_S = 3.0
TRAP_TORSO_UP_M_S = 0.5


@dataclass(frozen=True)
class Placement:
    """Where the ball lies against where the kick expects it, in the robot frame, and the robot's heading
    error: ball ``forward_m`` / ``left_m`` off its spot [m], robot turned ``heading_deg`` (+ = left) away
    from the kick direction."""

    forward_m: float = 0.0
    left_m: float = 0.0
    heading_deg: float = 0.0


@dataclass
class KickRun:
    """A measured kick; positions in the world frame [m], times from the kick request [s]."""

    motion: str
    placement: Placement
    ball_start_m: tuple[float, float]
    ball_rest_m: tuple[float, float]
    kick_heading_deg: float
    """Direction the kick aims at (the robot's heading minus the placement's heading error) [deg]."""
    contact_s: float | None
    """Time from the kick request to the strike (ball faster than STRIKE_SPEED_M_S; None: never struck)."""
    motion_s: float
    """Time from the kick request to the end of the kick motion (or of the run)."""
    fell: bool
    trapped: bool
    """The ball got trapped under the foot (see TRAP_FOOT_UP_M_S)."""
    ball_max_height_m: float
    foot_speed_m_s: float | None = None
    """Horizontal speed of the fastest foot in the cycle before the contact [m/s]."""
    ball_speed_m_s: float | None = None
    """Ball speed 3 cycles after the contact [m/s]."""
    truths: list[Truth] = field(repr=False, default_factory=list)

    @property
    def distance_m(self) -> float:
        return math.dist(self.ball_start_m, self.ball_rest_m)

    @property
    def direction_error_deg(self) -> float:
        """Angle of the ball's travel against the aim [deg] (+ = to the left); 0 when it did not move."""
        dx, dy = (b - a for a, b in zip(self.ball_start_m, self.ball_rest_m))
        if math.hypot(dx, dy) < 1e-6:
            return 0.0
        return (math.degrees(math.atan2(dy, dx)) - self.kick_heading_deg + 180.0) % 360.0 - 180.0

    def figures(self) -> dict[str, float | bool | None]:
        """JSON-friendly figures."""
        return {"distance_m": round(self.distance_m, 3), "direction_error_deg": round(self.direction_error_deg, 2),
                "contact_s": None if self.contact_s is None else round(self.contact_s, 3),
                "motion_s": round(self.motion_s, 2), "fell": self.fell, "trapped": self.trapped,
                "ball_max_height_m": round(self.ball_max_height_m, 3),
                "foot_speed_m_s": None if self.foot_speed_m_s is None else round(self.foot_speed_m_s, 2),
                "ball_speed_m_s": None if self.ball_speed_m_s is None else round(self.ball_speed_m_s, 2),
                "ball_rest_m": [round(v, 3) for v in self.ball_rest_m]}


def ball_spot(truth: Truth, forward_m: float, left_m: float, heading_deg: float | None = None) -> tuple[float, float]:
    """The world point ``forward_m`` ahead and ``left_m`` left of the torso's ground point, along
    ``heading_deg`` (default: the robot's heading)."""
    heading = math.radians(truth.heading_deg if heading_deg is None else heading_deg)
    c, s = math.cos(heading), math.sin(heading)
    x, y = truth.torso_m[0], truth.torso_m[1]
    return (x + c * forward_m - s * left_m, y + s * forward_m + c * left_m)


def run_kick(library: MotionLibrary, motion: str, placement: Placement = Placement(), seed: int = 0,
             position_m: tuple[float, float] = (0.0, 0.0), heading_deg: float = 0.0, max_s: float = 12.0,
             dynamic: DynamicParams | None = None, stance_motion: str = "stand", robot_type: int = 0,
             distance_m: float | None = None) -> KickRun:
    """Play ``motion`` once from the stance with the ball at its spot (moved by ``placement``).

    Args:
        library: must hold ``motion`` and ``stance_motion``; ``motion`` must have the constants
            ``ball_forward_m`` and ``ball_left_m``.
        max_s: the run stops this long after the kick request at the latest (else when the ball rests
            after the motion ended).
        robot_type: the robot (0-4) that plays the motions of ``library``.
        dynamic: the controller's dynamic elements (default: the shipped ones, whose kick-distance table serves
            ``distance_m``).
        distance_m: the ball distance requested from the kick (``MotionRequest.distance_m``; None: the kick
            as authored).

    Raises:
        KeyError: an unknown motion. ValueError: the motion lacks the ball constants.
    """
    kick = library.get(motion)
    try:
        forward, left = kick.constants["ball_forward_m"], kick.constants["ball_left_m"]
    except KeyError:
        raise ValueError(f"motion {motion!r} has no ball_forward_m / ball_left_m constants") from None
    controller = MotionController(library, dynamic or load_dynamic_params(), robot_type)
    scenario = Scenario(PlayMotion(stance_motion), position_m, heading_deg + placement.heading_deg,
                        robot_type=robot_type, seed=seed, controller=controller, recover_falls=False)
    scenario.run(SETTLE_CYCLES)
    start = scenario.truth()
    # The ball lies where a robot facing the aim would expect it; the robot itself is turned by the error.
    aim_deg = start.heading_deg - placement.heading_deg
    spot = ball_spot(start, forward + placement.forward_m, left + placement.left_m, aim_deg)
    scenario.place_ball(spot)
    scenario.set_skill(PlayMotion(motion, distance_m=distance_m))
    world, robot = scenario.world, scenario.world.by_key[scenario.key]
    feet = list(robot.foot_bodies.values())
    previous_feet = np.array([world.body_position(b) for b in feet])
    foot_speed = 0.0
    foot_speed_at_contact = ball_speed = None
    previous_torso_z = start.torso_m[2]
    t0 = start.time_s
    contact_s = motion_s = None
    fell = trapped = False
    max_height = 0.0
    truths: list[Truth] = []
    for _ in range(int(round(max_s / CYCLE_S))):
        truth = scenario.run(1)[0]
        truths.append(truth)
        elapsed = truth.time_s - t0
        feet_now = np.array([world.body_position(b) for b in feet])
        foot_up = float(np.max(feet_now[:, 2] - previous_feet[:, 2])) / CYCLE_S
        speed_before, foot_speed = foot_speed, float(np.max(np.linalg.norm(feet_now[:, :2] - previous_feet[:, :2],
                                                                           axis=1))) / CYCLE_S
        torso_up = (truth.torso_m[2] - previous_torso_z) / CYCLE_S
        previous_feet, previous_torso_z = feet_now, truth.torso_m[2]
        if contact_s is None and float(np.linalg.norm(world.ball_velocity())) > STRIKE_SPEED_M_S:
            contact_s, foot_speed_at_contact = elapsed, max(speed_before, foot_speed)
        if contact_s is not None and ball_speed is None and elapsed - contact_s >= 3 * CYCLE_S - 1e-9:
            ball_speed = float(np.linalg.norm(world.ball_velocity()))
        if contact_s is not None and elapsed - contact_s <= 3 * CYCLE_S:
            trapped = trapped or foot_up > TRAP_FOOT_UP_M_S or torso_up > TRAP_TORSO_UP_M_S
        fell = fell or truth.fallen
        max_height = max(max_height, truth.ball_m[2] - 0.042)
        if motion_s is None and scenario.behavior.skill is not None and scenario.behavior.skill.done:
            motion_s = elapsed
        speed_now = float(np.linalg.norm(world.ball_velocity()))
        if motion_s is not None and (contact_s is not None or elapsed > 2 * motion_s) and speed_now < REST_SPEED_M_S:
            break
    end = truths[-1]
    return KickRun(motion, placement, spot, (end.ball_m[0], end.ball_m[1]), aim_deg, contact_s, motion_s if motion_s is not None else truths[-1].time_s - t0, fell, trapped,
                   max_height, foot_speed_at_contact, ball_speed, truths)


__all__ = ["KickRun", "Placement", "ball_spot", "run_kick"]
