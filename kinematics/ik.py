"""Whole-body inverse kinematics with PlaCo: feet, hands, torso orientation and CoM -> 22 joint angles.

World frame ("ground frame"): SimSpark axes (x right, y forward, z up); the zero-pose robot stands with its
soles on z = 0 and its torso centre at (0, 0, 0.385) for type 0. The torso floats: its position follows
from the feet. Targets address the MJCF sites: ``lfoot``/``rfoot`` -> sole centres, ``lhand``/``rhand`` ->
lower-arm tips, ``torso`` -> torso centre. Joint limits are hard constraints of the QP, so no solution ever
leaves them; a target that cannot be met raises IKError naming the task and its residual.
"""

from __future__ import annotations

import contextlib
import logging
import math
import os
import sys
from collections.abc import Iterator, Mapping
from dataclasses import dataclass, field

import numpy as np
import placo

from kinematics.errors import IKError, SpecError
from kinematics.pinocchio_model import mjcf_path
from kinematics.spec import robot_spec

log = logging.getLogger(__name__)

TASK_FRAMES: dict[str, str] = {"lfoot": "lsole", "rfoot": "rsole", "lhand": "lhand", "rhand": "rhand",
                               "torso": "torso"}
# Soft-task weights: feet dominate (they carry the robot), then the torso attitude, then CoM and hands.
DEFAULT_WEIGHTS: dict[str, float] = {"lfoot": 100.0, "rfoot": 100.0, "torso": 10.0, "com": 10.0,
                                     "lhand": 1.0, "rhand": 1.0}


HARD_TASKS = frozenset({"lfoot", "rfoot"})
# Per-iteration step bound: joint speed limit x STEP_DT_S (0.3 rad). Undamped Gauss-Newton steps oscillate
# across the straight-knee singularity; bounded steps walk out of it.
STEP_DT_S = 0.05


@dataclass(frozen=True)
class PoseTarget:
    """Desired pose of a task frame in the ground frame; None leaves that part free.

    position_m: (x, y, z) in m. rotation: 3x3 rotation matrix of the frame in the ground frame.
    """

    position_m: tuple[float, float, float] | np.ndarray | None = None
    rotation: np.ndarray | None = None


@dataclass
class IKResult:
    """A solved keyframe.

    angles_rad: wire name -> SimSpark-signed angle (rad), canonical order.
    residuals: task name -> (position error m, orientation error rad).
    iterations: QP iterations used. torso_pose: 4x4 torso placement in the ground frame.
    """

    angles_rad: dict[str, float]
    residuals: dict[str, tuple[float, float]]
    iterations: int
    torso_pose: np.ndarray = field(repr=False)

    def as_array(self) -> np.ndarray:
        return np.array(list(self.angles_rad.values()))


@contextlib.contextmanager
def _quiet_stdout() -> Iterator[None]:
    """Silence the C-level stdout (library chatter) while keeping Python's own stdout intact."""
    sys.stdout.flush()
    saved = os.dup(1)
    try:
        with open(os.devnull, "w") as devnull:
            os.dup2(devnull.fileno(), 1)
        yield
    finally:
        os.dup2(saved, 1)
        os.close(saved)


def _rotation_error_rad(current: np.ndarray, desired: np.ndarray) -> float:
    cos_angle = (np.trace(desired.T @ current) - 1.0) / 2.0
    return float(math.acos(max(-1.0, min(1.0, cos_angle))))


class WholeBodyIK:
    """Keyframe IK for one robot type; keeps its PlaCo robot and warm-starts from the last solution.

    Args:
        robot_type: 0-4.
        weights: per-task soft weights overriding DEFAULT_WEIGHTS (task names as TASK_FRAMES plus "com").
    """

    def __init__(self, robot_type: int = 0, weights: Mapping[str, float] | None = None) -> None:
        self.spec = robot_spec(robot_type)
        with _quiet_stdout():  # PlaCo's loader prints "Loading model: ..." from C++
            self.robot = placo.RobotWrapper(str(mjcf_path(robot_type, True)),
                                            placo.Flags.mjcf | placo.Flags.ignore_collisions)
        self.joint_names = self.spec.joint_names
        for joint in self.spec.joints:  # the MJCF carries no speed limits; they bound each IK step
            self.robot.set_velocity_limit(joint.perceptor, joint.max_speed_rad_s)
        self.weights = {**DEFAULT_WEIGHTS, **(weights or {})}
        self._solvers: dict[tuple[str, ...], tuple[placo.KinematicsSolver, dict[str, object]]] = {}
        self.reset()

    def reset(self, seed_rad: Mapping[str, float] | np.ndarray | None = None) -> None:
        """Put the robot at the seed pose (zero pose by default), standing with its soles on the ground."""
        self.robot.state.q = self.robot.neutral_state().q
        if seed_rad is not None:
            self._set_angles(seed_rad)
        self.robot.update_kinematics()
        # Re-seat the free base so that the lower sole rests on z = 0 and the torso is upright.
        lowest = min(self.robot.get_T_world_frame(f)[2, 3] for f in ("lsole", "rsole"))
        self.robot.state.q[2] -= lowest
        self.robot.update_kinematics()

    def _set_angles(self, angles: Mapping[str, float] | np.ndarray) -> None:
        if isinstance(angles, Mapping):
            items = [(self.spec.joint(name).perceptor, value) for name, value in angles.items()]
        else:
            values = np.asarray(angles, dtype=float)
            if values.shape != (len(self.joint_names),):
                raise SpecError(f"expected {len(self.joint_names)} seed angles, got shape {values.shape}",
                                field="seed_rad")
            items = list(zip(self.joint_names, values))
        for name, value in items:
            if not math.isfinite(value):
                raise SpecError(f"joint {name}: seed angle must be finite, got {value!r}", field=name)
            self.robot.set_joint(name, float(value))

    def angles(self) -> dict[str, float]:
        """Current joint angles (wire name -> rad)."""
        return {name: float(self.robot.get_joint(name)) for name in self.joint_names}

    def _solver_for(self, task_names: tuple[str, ...]) -> tuple[placo.KinematicsSolver, dict[str, object]]:
        """One solver per task set, so repeated keyframes of the same kind reuse their QP structure."""
        if task_names not in self._solvers:
            solver = placo.KinematicsSolver(self.robot)
            solver.enable_joint_limits(True)
            solver.enable_velocity_limits(True)
            solver.dt = STEP_DT_S
            tasks: dict[str, object] = {}
            for name in task_names:
                weight = self.weights[name.partition(":")[0]]
                if name == "com":
                    task = solver.add_com_task(np.zeros(3))
                    task.mask.set_axises("xy")
                    task.configure("com", "soft", weight)
                else:
                    kind, _, _ = name.partition(":")
                    frame = TASK_FRAMES[kind]
                    if name.endswith(":pos"):
                        task = solver.add_position_task(frame, np.zeros(3))
                        task.configure(name, "soft", weight)
                    elif name.endswith(":rot"):
                        task = solver.add_orientation_task(frame, np.eye(3))
                        task.configure(name, "soft", weight)
                    else:
                        task = solver.add_frame_task(frame, np.eye(4))
                        # Feet are contacts: hard equality constraints keep the other tasks from dragging
                        # them (soft feet let a far hand target pull the whole robot into a local minimum).
                        priority = "hard" if kind in HARD_TASKS else "soft"
                        task.configure(name, priority, weight, weight)
                tasks[name] = task
            solver.add_regularization_task(1e-6)
            self._solvers[task_names] = (solver, tasks)
        return self._solvers[task_names]

    def solve(self, targets: Mapping[str, PoseTarget], com_xy_m: tuple[float, float] | None = None,
              seed_rad: Mapping[str, float] | np.ndarray | None = None, position_tol_m: float = 1e-3,
              rotation_tol_rad: float = math.radians(1.0), max_iterations: int = 60) -> IKResult:
        """Solve one keyframe.

        Args:
            targets: task name (lfoot, rfoot, lhand, rhand, torso) -> PoseTarget in the ground frame.
            com_xy_m: desired CoM ground projection (x, y) in m, or None.
            seed_rad: start pose; None warm-starts from the previous solution.
            position_tol_m / rotation_tol_rad: success tolerances per task.
            max_iterations: QP iterations before giving up.

        Returns:
            IKResult with angles within the joint limits.

        Raises:
            SpecError: unknown task name or non-finite target.
            IKError: a target is not met within tolerance (names the worst task and its residual).
        """
        goals = self._goals(targets, com_xy_m)
        if seed_rad is not None:
            self.reset(seed_rad)
        solver, tasks = self._solver_for(tuple(goals))
        for name, goal in goals.items():
            task = tasks[name]
            if name == "com":
                task.target_world = np.array([goal[0], goal[1], 0.0])
            elif name.endswith(":pos"):
                task.target_world = goal
            elif name.endswith(":rot"):
                task.R_world_frame = goal
            else:
                task.T_world_frame = goal
        residuals: dict[str, tuple[float, float]] = {}
        iterations = 0
        previous_worst = math.inf
        stalled = 0
        for iterations in range(1, max_iterations + 1):
            try:
                solver.solve(True)
            except RuntimeError as error:  # PlaCo reports an infeasible QP (hard feet vs joint limits)
                residuals = self._residuals(goals)
                name = max((n for n in goals if n.split(":")[0] in HARD_TASKS),
                           key=lambda n: residuals[n][0], default=next(iter(goals)))
                raise IKError(f"IK infeasible at iteration {iterations}: hard task {name!r} (residual "
                              f"{residuals[name][0]:.4g} m) cannot be met within the joint limits ({error})",
                              task=name, residual=residuals[name][0]) from error
            self.robot.update_kinematics()
            residuals = self._residuals(goals)
            worst = max(p / position_tol_m + r / rotation_tol_rad for p, r in residuals.values())
            # Converge well inside the tolerance (a tenth), so that accepted keyframes are not borderline.
            if all(p <= 0.1 * position_tol_m and r <= 0.1 * rotation_tol_rad for p, r in residuals.values()):
                break
            stalled = stalled + 1 if previous_worst - worst < 1e-4 * max(worst, 1.0) else 0
            previous_worst = worst
            if stalled >= 5:
                break
        failing = {n: r for n, r in residuals.items() if r[0] > position_tol_m or r[1] > rotation_tol_rad}
        if failing:
            name, (pos_err, rot_err) = max(failing.items(),
                                           key=lambda kv: kv[1][0] / position_tol_m + kv[1][1] / rotation_tol_rad)
            residual = pos_err if pos_err > position_tol_m else rot_err
            unit = "m" if pos_err > position_tol_m else "rad"
            others = ", ".join(f"{n} ({p:.4g} m, {math.degrees(r):.3g} deg)" for n, (p, r) in failing.items())
            raise IKError(f"IK target {name!r} not reachable: residual {residual:.4g} {unit} after "
                          f"{iterations} iterations (tolerance {position_tol_m} m / "
                          f"{math.degrees(rotation_tol_rad):.2f} deg); failing tasks: {others}",
                          task=name, residual=residual)
        return IKResult(self.angles(), residuals, iterations, self.robot.get_T_world_frame("torso").copy())

    def _goals(self, targets: Mapping[str, PoseTarget], com_xy_m: tuple[float, float] | None) -> dict[str, object]:
        goals: dict[str, object] = {}
        for name, target in targets.items():
            if name not in TASK_FRAMES:
                raise SpecError(f"unknown IK task {name!r}; known: {', '.join(TASK_FRAMES)}", field="targets")
            position = None if target.position_m is None else np.asarray(target.position_m, dtype=float)
            rotation = None if target.rotation is None else np.asarray(target.rotation, dtype=float)
            for value in (position, rotation):
                if value is not None and not np.isfinite(value).all():
                    raise SpecError(f"IK target {name!r} has a non-finite value", field=name)
            if position is not None and rotation is not None:
                pose = np.eye(4)
                pose[:3, :3], pose[:3, 3] = rotation, position
                goals[name] = pose
            elif position is not None:
                goals[f"{name}:pos"] = position
            elif rotation is not None:
                goals[f"{name}:rot"] = rotation
        if com_xy_m is not None:
            if not all(math.isfinite(v) for v in com_xy_m):
                raise SpecError("CoM target must be finite", field="com_xy_m")
            goals["com"] = (float(com_xy_m[0]), float(com_xy_m[1]))
        return goals

    def _residuals(self, goals: Mapping[str, object]) -> dict[str, tuple[float, float]]:
        residuals = {}
        for name, goal in goals.items():
            if name == "com":
                com = self.robot.com_world()
                residuals[name] = (float(math.hypot(com[0] - goal[0], com[1] - goal[1])), 0.0)
                continue
            frame = TASK_FRAMES[name.partition(":")[0]]
            current = self.robot.get_T_world_frame(frame)
            if name.endswith(":pos"):
                residuals[name] = (float(np.linalg.norm(current[:3, 3] - goal)), 0.0)
            elif name.endswith(":rot"):
                residuals[name] = (0.0, _rotation_error_rad(current[:3, :3], goal))
            else:
                residuals[name] = (float(np.linalg.norm(current[:3, 3] - goal[:3, 3])),
                                   _rotation_error_rad(current[:3, :3], goal[:3, :3]))
        return residuals
