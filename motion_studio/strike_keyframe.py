"""The kick's strike keyframe optimised on the symbolic Nao (``kinematics.symbolic``) with IPOPT: the leg
angles and angular velocities at ball contact that give the fastest toe along the kick line, under the
joint speed limit (``JointSpec.max_speed_rad_s``, 6.14 rad/s), with the CoM over the support sole, the toe at
the ball's height and the swing foot clear of the ground.

Why a keyframe NLP: the kick tuner's CMA-ES searches 35 keyframe parameters through rollouts, most of which
fall or miss; the kinematic part of a strike (how fast can the toe go, which pose gets it there while the
robot stays balanced) has exact derivatives and needs no rollout. Its answer is a start for the rollout
search (``motion-studio tune kick``), not a shipped motion. Frame: the support (right) sole's, y forward,
x right, z up; the left foot kicks.
"""

from __future__ import annotations

from dataclasses import dataclass

import casadi
import numpy as np

from sim.field import BALL_RADIUS_M
from kinematics.spec import robot_spec
from kinematics.symbolic import symbolic_nao

#: Margin of the CoM inside the support sole [m], toe height window [m] (around the ball's centre height).
COM_MARGIN_M = 0.015
TOE_HEIGHT_M = (0.5 * BALL_RADIUS_M, 1.5 * BALL_RADIUS_M)
#: Where the toe meets the ball: ahead of the support sole's centre [m], beside it [m] (left: negative x).
TOE_AHEAD_M = (0.08, 0.16)
TOE_BESIDE_M = (-0.16, -0.06)
#: Toe speed across the kick line and up allowed [m/s] (a straight, flat kick).
SIDE_SPEED_M_S = 0.15
UP_SPEED_M_S = 0.3
#: Torso tilt from upright over the support sole, at most [deg].
TILT_DEG = 15.0
LEGS = ("llj1", "llj2", "llj3", "llj4", "llj5", "llj6", "rlj1", "rlj2", "rlj3", "rlj4", "rlj5", "rlj6")
#: The kicking leg: only its joints move at the contact (the support leg holds the robot still).
SWING = LEGS[:6]


@dataclass(frozen=True)
class Strike:
    """The optimised contact keyframe: leg angles [deg] and the swing leg's angular velocities [rad/s] by wire
    name; the toe's velocity and position and the CoM in the support sole's frame [m/s, m]."""

    angles_deg: dict[str, float]
    speeds_rad_s: dict[str, float]
    toe_velocity_m_s: tuple[float, float, float]
    toe_position_m: tuple[float, float, float]
    com_m: tuple[float, float]
    solver_status: str

    @property
    def toe_speed_m_s(self) -> float:
        return self.toe_velocity_m_s[1]


def optimise_strike(robot_type: int = 0) -> Strike:
    """Solve the strike NLP (see the module docstring).

    Raises:
        RuntimeError: IPOPT did not solve it (the message gives its return status).
    """
    spec = robot_spec(robot_type)
    nao = symbolic_nao(robot_type)
    index = [nao.joint_names.index(name) for name in LEGS]
    legs = casadi.SX.sym("legs", len(LEGS))
    speeds = casadi.SX.sym("speeds", len(SWING))
    q = casadi.SX.zeros(len(nao.joint_names))
    for i, j in enumerate(index):
        q[j] = legs[i]
    sole_p, sole_r = nao.pose("rsole")(q)
    foot_p, foot_r = nao.pose("lfoot")(q)
    length, height = spec.body("lfoot").shape.size[1], spec.body("lfoot").shape.size[2]
    toe = foot_p + foot_r @ casadi.DM([0.0, length / 2, -height / 2])
    lsole, _ = nao.pose("lsole")(q)
    to_sole = sole_r.T
    toe_rel = to_sole @ (toe - sole_p)
    com_rel = to_sole @ (nao.com(q) - sole_p)
    lsole_rel = to_sole @ (lsole - sole_p)
    # the support sole stands (its frame is the world's) and the support leg holds: the swing leg moves the toe
    toe_velocity = casadi.jacobian(toe_rel, legs[:len(SWING)]) @ speeds
    half_x, half_y = spec.body("rfoot").shape.size[0] / 2, spec.body("rfoot").shape.size[1] / 2
    rows = [
        (com_rel[0], -half_x + COM_MARGIN_M, half_x - COM_MARGIN_M),
        (com_rel[1], -half_y + COM_MARGIN_M, half_y - COM_MARGIN_M),
        (toe_rel[2], *TOE_HEIGHT_M), (toe_rel[1], *TOE_AHEAD_M), (toe_rel[0], *TOE_BESIDE_M),
        (lsole_rel[2], 0.005, casadi.inf),
        (toe_velocity[0], -SIDE_SPEED_M_S, SIDE_SPEED_M_S), (toe_velocity[2], -UP_SPEED_M_S, UP_SPEED_M_S),
        (to_sole[2, 2], float(np.cos(np.radians(TILT_DEG))), 1.0),  # torso upright over the sole
    ]
    x = casadi.vertcat(legs, speeds)
    objective = -toe_velocity[1] + 1e-3 * casadi.sumsqr(speeds)
    limits = [spec.joint(name) for name in LEGS]
    swing = limits[:len(SWING)]
    lbx = [j.min_rad for j in limits] + [-j.max_speed_rad_s for j in swing]
    ubx = [j.max_rad for j in limits] + [j.max_speed_rad_s for j in swing]
    start = np.radians([0, 0, 20, -40, 20, 0, 0, 0, 20, -40, 20, 0]).tolist() + [0.0] * len(SWING)
    solver = casadi.nlpsol("strike", "ipopt", {"x": x, "f": objective, "g": casadi.vertcat(*[r[0] for r in rows])},
                           {"ipopt.print_level": 0, "print_time": False, "ipopt.sb": "yes", "ipopt.max_iter": 500})
    solution = solver(x0=start, lbx=lbx, ubx=ubx, lbg=[r[1] for r in rows], ubg=[r[2] for r in rows])
    status = solver.stats()["return_status"]
    if not solver.stats()["success"]:
        raise RuntimeError(f"IPOPT did not solve the strike: {status}")
    values = np.array(solution["x"]).ravel()
    figures = casadi.Function("figures", [x], [toe_velocity, toe_rel, com_rel], ["x"],
                              ["toe_velocity_m_s", "toe_m", "com_m"])
    velocity, position, com = (np.array(v).ravel() for v in figures(values))
    n = len(LEGS)
    return Strike({name: round(float(np.degrees(v)), 3) for name, v in zip(LEGS, values[:n])},
                  {name: round(float(v), 4) for name, v in zip(SWING, values[n:])},
                  tuple(float(v) for v in velocity), tuple(float(v) for v in position),
                  (float(com[0]), float(com[1])), status)


__all__ = ["LEGS", "SWING", "Strike", "optimise_strike"]
