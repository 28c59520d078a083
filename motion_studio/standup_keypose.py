"""Stand-up key poses on the symbolic Nao (``kinematics.symbolic``) solved with IPOPT: the crouch a robot
reaches from the ground, feet flat, the torso at a lean and height within bounds, the CoM over the soles.

Why an NLP next to ``motions.authoring.standup.SagittalSolver``: that solver answers one question (the leg
angles for a *given* lean, height and CoM offset) by damped Gauss-Newton on finite differences; a stand-up
author also wants to ask "which crouch within these bounds is the most stable?" and "which of the stable
crouches is closest to the pose the ground phases end in?". Both are constrained optimisations with exact
derivatives on the symbolic Nao. Two modes:

* **matched** (``com_forward_m`` given): the same equations as ``SagittalSolver.com_over_soles`` (flat foot,
  torso centre ``height_m`` above the sole site, CoM ``com_forward_m`` ahead of the sole centres at lean
  ``pitch_deg``); a test holds both to 0.1 deg and 1 mm;
* **max margin** (``com_forward_m`` None): maximise the CoM's distance inside the support polygon of the two
  flat feet, lean and height within bounds, and among equally stable poses the least joint travel from a
  reference pose (``reference_deg``: e.g. the last ground phase of a stand-up).

The sagittal model is the authoring one: hip yaw, hip roll and ankle roll at zero, legs mirrored, arms held
(``arms_rad``), so the support polygon is the rectangle of the two foot boxes. Frame: gravity-aligned,
torso-centred, x right, y forward, z up; angles SimSpark-signed. This module lives in motion_studio because
motions/ may not import CasADi-heavy code (DESIGN.md room graph).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass

import casadi
import numpy as np

from kinematics.spec import robot_spec
from kinematics.symbolic import symbolic_nao

#: Sagittal leg joints (left; the right mirrors) and their limits [deg], as SagittalSolver's LEG_LIMITS_DEG.
LEG_JOINTS = ("hip", "knee", "ankle")
LEG_LIMITS_DEG = {"hip": (-24.5, 99.5), "knee": (-129.5, 0.5), "ankle": (-44.5, 74.5)}
#: Default bounds of the max-margin crouch: lean [deg] and torso-centre height above the sole site [m],
#: around the shipped crouches (motions/params/standup.toml: 23-30 deg, 0.27-0.30 m).
PITCH_BOUNDS_DEG = (15.0, 35.0)
HEIGHT_BOUNDS_M = (0.26, 0.31)
#: Weight of the joint travel [1/rad^2 of m]: small, so it only breaks ties between equally stable poses.
TRAVEL_WEIGHT = 1e-4
#: SagittalSolver's start, used as the travel reference when none is given [deg].
DEFAULT_REFERENCE_DEG = (60.0, -100.0, 40.0)


@dataclass(frozen=True)
class StandupKeypose:
    """A solved key pose: wire name -> angle [SimSpark deg] for legs and the held arms; lean [deg]; torso
    centre above the sole site [m]; CoM ahead of the sole centres [m]; CoM margin inside the support
    polygon [m] (symbolic model); IPOPT's status."""

    angles_deg: dict[str, float]
    pitch_deg: float
    height_m: float
    com_forward_m: float
    margin_m: float
    solver_status: str

    def angles_rad(self) -> dict[str, float]:
        """Wire name -> angle [rad] (what ``SagittalSolver.com_margin_m`` and Pinocchio take)."""
        return {name: math.radians(value) for name, value in self.angles_deg.items()}


def _check_bounds(name: str, bounds: tuple[float, float]) -> None:
    low, high = bounds
    if not (math.isfinite(low) and math.isfinite(high)) or low > high:
        raise ValueError(f"{name}: bounds ({low}, {high}) need finite lower <= upper")


def solve_keypose(pitch_deg: float | tuple[float, float] = PITCH_BOUNDS_DEG,
                  height_m: float | tuple[float, float] = HEIGHT_BOUNDS_M,
                  com_forward_m: float | None = None, arms_rad: Mapping[str, float] | None = None,
                  reference_deg: tuple[float, float, float] = DEFAULT_REFERENCE_DEG,
                  robot_type: int = 0) -> StandupKeypose:
    """Solve a stand-up key pose (see the module docstring); a number for ``pitch_deg`` or ``height_m``
    fixes it, a (low, high) pair bounds it.

    Raises:
        ValueError: bad bounds, an unknown arm joint, or IPOPT found no pose (the message gives its status).
    """
    pitch_bounds = (float(pitch_deg), float(pitch_deg)) if np.isscalar(pitch_deg) else tuple(map(float, pitch_deg))
    height_bounds = (float(height_m), float(height_m)) if np.isscalar(height_m) else tuple(map(float, height_m))
    _check_bounds("pitch_deg", pitch_bounds)  # type: ignore[arg-type]
    _check_bounds("height_m", height_bounds)  # type: ignore[arg-type]
    if com_forward_m is not None and not math.isfinite(com_forward_m):
        raise ValueError(f"com_forward_m: {com_forward_m} is not a number")
    spec = robot_spec(robot_type)
    nao = symbolic_nao(robot_type)
    arms = dict(arms_rad or {})
    unknown = sorted(set(arms) - set(nao.joint_names))
    if unknown:
        raise ValueError(f"arms_rad: unknown joints {unknown}")
    legs = casadi.SX.sym("legs", 3)  # hip pitch, knee, ankle pitch [rad], both sides
    pitch = casadi.SX.sym("pitch")  # torso lean forward [rad]
    t = casadi.SX.sym("margin")  # CoM margin [m]
    q = casadi.SX.zeros(len(nao.joint_names))
    for side in "lr":
        for k, wire in enumerate((f"{side}lj3", f"{side}lj4", f"{side}lj5")):
            q[nao.joint_names.index(wire)] = legs[k]
    for wire, value in arms.items():
        q[nao.joint_names.index(wire)] = value
    cp, sp = casadi.cos(pitch), casadi.sin(pitch)
    rotation = casadi.vertcat(casadi.horzcat(1, 0, 0), casadi.horzcat(0, cp, sp), casadi.horzcat(0, -sp, cp))
    sole_p, sole_r = nao.pose("lsole")(q)
    sole = rotation @ sole_p
    sole_rot = rotation @ sole_r
    com = rotation @ nao.com(q)
    height = -sole[2]
    com_forward = com[1] - sole[1]
    rows = [(sole_rot[2, 1], 0.0, 0.0),  # flat foot (SagittalSolver: atan2(S21, S11) = 0)
            (sole_rot[1, 1], 0.5, casadi.inf),  # ... the right way round
            (height, *height_bounds)]
    if com_forward_m is not None:
        rows.append((com_forward, com_forward_m, com_forward_m))
    # support polygon: the bottom corners of the foot boxes (flat, parallel: a rectangle); the CoM's distance
    # inside each of its edges
    inside = []
    for body, outer in (("lfoot", -1.0), ("rfoot", 1.0)):
        sx, sy, sz = spec.body(body).shape.size
        foot_p, foot_r = nao.pose(body)(q)
        for cx in (-1.0, 1.0):
            for cy in (-1.0, 1.0):
                corner = rotation @ (foot_p + foot_r @ casadi.DM([cx * sx / 2, cy * sy / 2, -sz / 2]))
                inside.append(cy * (corner[1] - com[1]))  # heel behind, toe ahead
                if cx == outer:
                    inside.append(outer * (corner[0] - com[0]))
    if com_forward_m is None:
        rows += [(distance - t, 0.0, casadi.inf) for distance in inside]
    reference = np.radians(reference_deg)
    travel = casadi.sumsqr(legs - casadi.DM(reference))
    objective = travel if com_forward_m is not None else -t + TRAVEL_WEIGHT * travel
    low = np.radians([LEG_LIMITS_DEG[k][0] for k in LEG_JOINTS])
    high = np.radians([LEG_LIMITS_DEG[k][1] for k in LEG_JOINTS])
    x = casadi.vertcat(legs, pitch, t)
    lbx = [*low, math.radians(pitch_bounds[0]), -casadi.inf]
    ubx = [*high, math.radians(pitch_bounds[1]), casadi.inf]
    start = [*np.clip(reference, low, high), math.radians(sum(pitch_bounds) / 2), 0.0]
    solver = casadi.nlpsol("standup_keypose", "ipopt",
                           {"x": x, "f": objective, "g": casadi.vertcat(*[r[0] for r in rows])},
                           {"ipopt.print_level": 0, "print_time": False, "ipopt.sb": "yes", "ipopt.max_iter": 500,
                            "ipopt.tol": 1e-10})
    solution = solver(x0=start, lbx=lbx, ubx=ubx, lbg=[r[1] for r in rows], ubg=[r[2] for r in rows])
    status = solver.stats()["return_status"]
    if not solver.stats()["success"]:
        raise ValueError(f"no stand-up key pose: IPOPT {status} (lean {pitch_bounds} deg, height {height_bounds} m, "
                         f"CoM forward {com_forward_m} m)")
    values = np.array(solution["x"]).ravel()
    figures = casadi.Function("figures", [x], [height, com_forward, casadi.mmin(casadi.vertcat(*inside))])
    h, f, margin = (float(v) for v in figures(values))
    angles = {wire: 0.0 for side in "lr" for wire in (f"{side}lj1", f"{side}lj2", f"{side}lj6")}
    for side in "lr":
        for k, wire in enumerate((f"{side}lj3", f"{side}lj4", f"{side}lj5")):
            angles[wire] = float(np.degrees(values[k]))
    angles.update({wire: math.degrees(value) for wire, value in arms.items()})
    return StandupKeypose(angles, float(np.degrees(values[3])), h, f, margin, status)


def crouch_arms_rad(shoulder_pitch_deg: float, shoulder_roll_deg: float) -> dict[str, float]:
    """The arms of a stand-up's crouch as ``motions.authoring.standup.key_poses`` holds them [rad]."""
    from motions.authoring.common import ARMS
    from motions.authoring.standup import symmetric_angles_rad

    return {k: v for k, v in symmetric_angles_rad(shoulder_pitch_deg=shoulder_pitch_deg,
                                                  shoulder_roll_deg=shoulder_roll_deg).items() if k in ARMS}


def section_keyposes(section: str, pitch_deg: tuple[float, float] = PITCH_BOUNDS_DEG,
                     height_m: tuple[float, float] = HEIGHT_BOUNDS_M,
                     robot_type: int = 0) -> tuple[StandupKeypose, StandupKeypose]:
    """For a stand-up of ``motions/params/standup.toml``: its crouch as authored (matched mode, the section's
    lean, height and CoM offset) and the max-margin crouch within the bounds, with the section's crouch arms,
    nearest the last ground phase's legs (the squat the robot comes up to from lying; the authored crouch's
    legs when it has no ground phase).

    Raises:
        ValueError: an unknown section (the message lists the known ones), or no pose (see solve_keypose).
    """
    from motions.authoring.standup import load_standup_params, stance_params

    sections = load_standup_params()
    if section not in sections:
        raise ValueError(f"unknown stand-up section {section!r}; known: {', '.join(sorted(sections))}")
    params = sections[section]
    arms = crouch_arms_rad(params.crouch_shoulder_pitch_deg, stance_params().arm.shoulder_roll_deg)
    authored = solve_keypose(params.crouch_pitch_deg, params.crouch_height_m, params.crouch_com_forward_m, arms,
                             robot_type=robot_type)
    if params.ground:
        last = params.ground[-1]
        reference = (last.hip_pitch_deg, last.knee_deg, last.ankle_pitch_deg)
    else:
        reference = tuple(authored.angles_deg[w] for w in ("llj3", "llj4", "llj5"))
    best = solve_keypose(pitch_deg, height_m, None, arms, reference, robot_type)  # type: ignore[arg-type]
    return authored, best


__all__ = ["HEIGHT_BOUNDS_M", "PITCH_BOUNDS_DEG", "StandupKeypose", "crouch_arms_rad", "section_keyposes",
           "solve_keypose"]
