"""Joint slack on the real rcssserver3d 0.7.3: how far the real robot's bodies lie from where its joint angles put
them.

Why: SimSpark's joints are ODE constraint rows, held by the world's error reduction (ERP) one step at a time, so
under load the bodies of a chain drift apart by millimetres while the hinge angles (HJ) stay what they are; our
MuJoCo joints are generalized coordinates and never separate. Where the drift matters the two servers disagree
even with the same joint angles: the real kicking foot swinging down at the strike lies 7-13 mm below its joint
angles and meets a ball 8 mm beyond its spot under its centre (4.0 m), ours meets it with the sole (1.8 m).

The measure: for each monitor frame of a real run (full states), the monitor's torso pose and the HJ angles of
the sense message with the same game time go through our kinematics (``sim.world.World``, the robot's own type);
the residual is our forward kinematics minus the monitor's body position [mm] (z > 0: the real body hangs below
its joint angles). On ours the same measure is zero by construction; standing still on the real server it is
under a millimetre.

    motion-studio real joint-slack walk_forward kick --json out/joint_slack.json --plot out/joint_slack.png
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from pathlib import Path

import mujoco
import numpy as np

from agent.protocol.constants import CYCLE_S
from agent.protocol.sense import parse_sense
from kinematics.spec import robot_spec
from sim.replay import ReplayFrame
from sim.world import World

#: Bodies measured by default (the monitor reports every body by name; the feet carry the contacts).
DEFAULT_BODIES = ("rfoot", "lfoot")


@dataclass
class BodySlack:
    """The residual of one body over a run: rows of (game time [s], dx, dy, dz [mm]), FK minus the monitor."""

    body: str
    rows: np.ndarray

    def summary(self) -> dict[str, float]:
        """Frames, |residual| median / 90th percentile / max [mm], and the z residual's median, min, max [mm]."""
        norm = np.linalg.norm(self.rows[:, 1:], axis=1)
        z = self.rows[:, 3]
        return {"frames": int(len(self.rows)), "median_mm": float(np.median(norm)),
                "p90_mm": float(np.percentile(norm, 90)), "max_mm": float(norm.max()),
                "z_median_mm": float(np.median(z)), "z_min_mm": float(z.min()), "z_max_mm": float(z.max())}


def hinge_angles_by_cycle(messages: Iterable[str | bytes]) -> dict[int, dict[str, float]]:
    """HJ angles [rad] of each sense message, keyed by its game time in cycles (messages without a game state or
    without joints are skipped)."""
    angles: dict[int, dict[str, float]] = {}
    for message in messages:
        sense = parse_sense(message)
        if sense.game_state is None or not sense.joints:
            continue
        angles[round(sense.game_state.game_time_s / CYCLE_S)] = {name: math.radians(value)
                                                                 for name, value in sense.joints.items()}
    return angles


def body_slack(frames: Iterable[ReplayFrame], angles: dict[int, dict[str, float]], robot_type: int = 0,
               bodies: Sequence[str] = DEFAULT_BODIES, robot: str | None = None) -> list[BodySlack]:
    """The residual of ``bodies`` over the frames that have HJ angles of the same game time.

    Args:
        frames: monitor frames (``sim.replay.read_log``); only full states carry every body.
        angles: :func:`hinge_angles_by_cycle` of the same run.
        robot: the monitor's robot key (``left_1``); None = the first robot of each frame.

    Raises:
        KeyError: a body name the monitor does not report.
    """
    world = World()
    world.add_robot(1, robot_type)
    model_robot = world.by_key[1]
    body_ids = {name: mujoco.mj_name2id(world.model, mujoco.mjtObj.mjOBJ_BODY, model_robot.prefix + name)
                for name in bodies}
    missing = [name for name, index in body_ids.items() if index < 0]
    if missing:
        raise KeyError(f"no body {missing[0]!r} in our robot model (known: the SimSpark body names, e.g. rfoot)")
    qpos, joints = world.data.qpos, world.motors.qadr[world.motors.span(1)]
    names = [joint.perceptor for joint in robot_spec(robot_type).joints]   # spec order, as the motors hold them
    rows: dict[str, list[tuple[float, float, float, float]]] = {name: [] for name in bodies}
    quaternion = np.zeros(4)
    for frame in frames:
        pose = frame.robots.get(robot) if robot is not None else next(iter(frame.robots.values()), None)
        hinges = angles.get(round(frame.time_s / CYCLE_S))
        if pose is None or hinges is None or "torso" not in pose.bodies:
            continue
        torso = pose.bodies["torso"]
        qpos[model_robot.root_qadr:model_robot.root_qadr + 3] = torso[:3, 3]
        mujoco.mju_mat2Quat(quaternion, np.ascontiguousarray(torso[:3, :3]).reshape(-1))
        qpos[model_robot.root_qadr + 3:model_robot.root_qadr + 7] = quaternion
        qpos[joints] = [hinges.get(name, 0.0) for name in names]
        mujoco.mj_kinematics(world.model, world.data)
        for name, index in body_ids.items():
            if name not in pose.bodies:
                raise KeyError(f"the monitor reports no body {name!r} (it has: {', '.join(sorted(pose.bodies))})")
            dx, dy, dz = 1000.0 * (world.data.xpos[index] - pose.bodies[name][:3, 3])
            rows[name].append((frame.time_s, float(dx), float(dy), float(dz)))
    return [BodySlack(name, np.array(rows[name], dtype=float).reshape(-1, 4)) for name in bodies]


def table(results: dict[str, list[BodySlack]], server: str = "real") -> str:
    """One line per case and body: frames, |residual| median / p90 / max and the z residual [mm]; ``server``
    names whose monitor and HJ angles were measured."""
    lines = [f"{'case':18s} {'body':8s} {'frames':>6s} {'median':>7s} {'p90':>6s} {'max':>6s} {'z med':>6s} "
             f"{'z min':>6s} {'z max':>6s}   [mm, our FK of the {server} torso + HJ minus the {server} body]"]
    for case, slacks in results.items():
        for slack in slacks:
            if not len(slack.rows):
                lines.append(f"{case:18s} {slack.body:8s} {0:6d}   (no frame with HJ angles)")
                continue
            s = slack.summary()
            lines.append(f"{case:18s} {slack.body:8s} {s['frames']:6d} {s['median_mm']:7.1f} {s['p90_mm']:6.1f} "
                         f"{s['max_mm']:6.1f} {s['z_median_mm']:+6.1f} {s['z_min_mm']:+6.1f} {s['z_max_mm']:+6.1f}")
    return "\n".join(lines)


def plot(results: dict[str, list[BodySlack]], path: Path,
         ours: dict[str, list[BodySlack]] | None = None) -> None:
    """The z residual of each body over game time, one panel per case (PNG); ``ours`` (the same cases on our
    simulator) dashed in the same colours."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(len(results), 1, figsize=(9, 2.6 * len(results)), squeeze=False)
    for axis, (case, slacks) in zip(axes[:, 0], results.items()):
        mine = {slack.body: slack for slack in (ours or {}).get(case, [])}
        for slack in slacks:
            if len(slack.rows):
                line, = axis.plot(slack.rows[:, 0], slack.rows[:, 3], label=f"{slack.body} real", linewidth=0.9)
                other = mine.get(slack.body)
                if other is not None and len(other.rows):
                    axis.plot(other.rows[:, 0], other.rows[:, 3], "--", color=line.get_color(),
                              label=f"{slack.body} ours", linewidth=0.9)
        axis.axhline(0.0, color="grey", linewidth=0.5)
        axis.set_title(f"{case}: body below its joint angles (FK - monitor, z)", fontsize=9)
        axis.set_ylabel("mm")
        axis.legend(fontsize=8)
    axes[-1, 0].set_xlabel("game time [s]")
    fig.tight_layout()
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=110)
    plt.close(fig)


__all__ = ["BodySlack", "DEFAULT_BODIES", "body_slack", "hinge_angles_by_cycle", "plot", "table"]
