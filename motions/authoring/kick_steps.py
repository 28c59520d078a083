"""Small single steps for lining up a kick (a few centimetres forward, backward, left or right), by IK.

Why: the walks are cyclic gaits whose shortest use (a start ramp, one stride, a stop ramp) moves the robot
0.12 m sideways and 0.35 m forward on our simulator, while a kick needs the ball within about 2 cm of its
spot. A kick step moves the robot by ``forward_m`` or ``side_m`` quasi-statically, one foot after the other:

1. ``stance`` (skipped while ``in_walk_position`` is set), 2. ``shift_a``: the CoM over the trailing foot,
3. ``lift_a`` / ``place_a``: the leading foot (the right one for forward, backward and right steps) lifts,
moves by the step and comes down, 4. ``shift_b``: the CoM over the leading foot, 5. ``lift_b`` / ``place_b``:
the trailing foot follows, 6. ``settle``: the walk stance again on the moved feet (``in_walk_position`` set).

Every keyframe is solved with ``motions.authoring.kick.PoseSolver`` (CoM over the support sole, torso pitch
``torso_pitch_deg`` while on one foot, for the reason given in KickParams). ``kick_step_left`` is the mirror
image of ``kick_step_right``. The constants ``step_forward_m`` / ``step_left_m`` give the robot's ego
displacement, so a skill knows what one step does. Parameters: ``motions/params/kick_steps.toml``.

Run ``python -m motions.authoring.kick_steps`` to write the four files into ``motions/files/``.
"""

from __future__ import annotations

import argparse
from dataclasses import dataclass, replace
from pathlib import Path

from motions.authoring.common import FILES_DIR, PARAMS_DIR, FootPose, KeyframeSolver, header, load_params, write_xml_motions
from motions.authoring.gait import STANCE_FLAG, GaitParams, stance_pose
from motions.authoring.gait_params import GAIT_PARAMS_PATH
from motions.authoring.kick import Pose, PoseSolver, _phase, stance_params
from motions.model import XML, Motion

PARAMS_PATH = PARAMS_DIR / "kick_steps.toml"
SECTION = "steps"
#: Motion name -> (ground-frame direction x right, y forward) of the step; left is the mirror of right.
STEPS: dict[str, tuple[float, float]] = {"kick_step_forward": (0.0, 1.0), "kick_step_backward": (0.0, -1.0),
                                         "kick_step_right": (1.0, 0.0)}
MIRRORS = {"kick_step_left": "kick_step_right"}


@dataclass(frozen=True)
class StepParams:
    """The kick steps (lengths in m, times in ms, angles in degrees)."""

    forward_m: float = 0.04
    """Length of kick_step_forward / kick_step_backward [m]."""
    side_m: float = 0.03
    """Length of kick_step_left / kick_step_right [m]."""
    height_m: float = 0.02
    """Sole height of a foot in the air at the middle of its move [m]."""
    torso_pitch_deg: float = 0.0
    """Torso pitch while on one foot [deg]."""
    com_inset_m: float = 0.01
    """CoM target inside the support sole's centre (toward the other foot) [m]."""
    com_forward_m: float = 0.01
    """CoM target ahead of the support sole's centre [m]."""
    shift_ms: int = 400
    """Each weight shift [ms]."""
    lift_ms: int = 160
    """Each lift, the foot rising and moving half the step [ms]."""
    place_ms: int = 200
    """Each placing, the foot moving the other half and coming down [ms]."""
    settle_ms: int = 400
    """The last phase back into the walk stance [ms]."""


def step_params(path: Path = PARAMS_PATH) -> StepParams:
    """The parameters of ``[steps]`` (missing keys keep their defaults)."""
    return load_params(StepParams, path, SECTION)  # type: ignore[return-value]


def build_step(name: str, direction: tuple[float, float], params: StepParams, stance: GaitParams,
               solver: KeyframeSolver | None = None, header_comments: tuple[str, ...] = ()) -> Motion:
    """One kick step along ``direction`` (ground frame: x right, y forward; the right foot leads).

    Raises:
        kinematics.IKError: a keyframe out of reach.
    """
    solver = solver or KeyframeSolver()
    solver.ik.reset()
    stand = stance_pose(stance, solver)
    length = params.side_m if direction[0] else params.forward_m
    dx, dy = direction[0] * length, direction[1] * length
    half = stance.foot_spacing_m / 2.0
    left, right = FootPose(-half, 0.0), FootPose(half, 0.0)
    moved_left, moved_right = FootPose(-half + dx, dy), FootPose(half + dx, dy)
    pitch = params.torso_pitch_deg
    # Leading = right foot: the left one supports first (CoM inset toward +x), then the moved right one.
    over_left = (left.x_m + params.com_inset_m, left.y_m + params.com_forward_m)
    over_right = (moved_right.x_m - params.com_inset_m, moved_right.y_m + params.com_forward_m)
    poses = [
        ("shift_a", params.shift_ms, Pose(right, left, over_left, pitch)),
        ("lift_a", params.lift_ms, Pose(FootPose(half + dx / 2, dy / 2, params.height_m), left, over_left, pitch)),
        ("place_a", params.place_ms, Pose(moved_right, left, over_left, pitch)),
        ("shift_b", params.shift_ms, Pose(moved_right, left, over_right, pitch)),
        ("lift_b", params.lift_ms, Pose(moved_right, FootPose(-half + dx / 2, dy / 2, params.height_m), over_right,
                                        pitch)),
        ("place_b", params.place_ms, Pose(moved_right, moved_left, over_right, pitch)),
    ]
    pose_solver = PoseSolver(stance, solver, clamp_to_reach=False)
    pose_solver.solve(Pose(right, left, None, stance.torso_pitch_deg))
    names = ["stance"] + [p[0] for p in poses] + ["settle"]
    phases = [_phase("stance", stand, stance.stance_ms, next=names[1], skip_if_flag=STANCE_FLAG)]
    for index, (phase_name, duration_ms, pose) in enumerate(poses, start=1):
        phases.append(_phase(phase_name, pose_solver.solve(pose), duration_ms, next=names[index + 1],
                             set_flag_false=STANCE_FLAG if index == 1 else None))
    phases.append(_phase("settle", stand, params.settle_ms, is_final=True, set_flag_true=STANCE_FLAG))
    # Ego displacement of the robot: forward = ground +y, left = ground -x.
    constants = {"step_forward_m": round(dy, 4), "step_left_m": round(-dx, 4)}
    return Motion(name, phases, source_format=XML, first_phase="stance", constants=constants,
                  header_comments=header_comments)


def build_all(path: Path = PARAMS_PATH, gait_path: Path = GAIT_PARAMS_PATH,
              solver: KeyframeSolver | None = None) -> dict[str, Motion]:
    """The four kick steps (motion name -> Motion, with header comments)."""
    solver = solver or KeyframeSolver()
    params = step_params(path)
    stance = stance_params(gait_path)
    comments = header("motions.authoring.kick_steps", path, SECTION, params, "python -m motions.authoring.kick_steps")
    comments += (f" Stance: [stand] of {gait_path.name} (torso_height_m={stance.torso_height_m}, "
                 f"torso_pitch_deg={stance.torso_pitch_deg}, foot_spacing_m={stance.foot_spacing_m}). ",)
    out = {name: build_step(name, direction, params, stance, solver, comments) for name, direction in STEPS.items()}
    for name, source in MIRRORS.items():
        mirrored = out[source].mirrored()
        constants = {"step_forward_m": mirrored.constants["step_forward_m"],
                     "step_left_m": -mirrored.constants["step_left_m"]}
        out[name] = replace(mirrored, name=name, constants=constants,
                            header_comments=comments + (f" Mirror image of {source} (motions.mirror). ",))
    return out


def write_all(out_dir: Path = FILES_DIR, path: Path = PARAMS_PATH, gait_path: Path = GAIT_PARAMS_PATH) -> list[Path]:
    """Generate, validate and write the kick steps; returns the paths written."""
    return write_xml_motions(build_all(path, gait_path), out_dir)


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--params", type=Path, default=PARAMS_PATH)
    parser.add_argument("--gait-params", type=Path, default=GAIT_PARAMS_PATH)
    parser.add_argument("--out", type=Path, default=FILES_DIR)
    args = parser.parse_args(argv)
    for target in write_all(args.out, args.params, args.gait_params):
        print(f"wrote {target}")


if __name__ == "__main__":
    main()


__all__ = ["STEPS", "StepParams", "build_all", "build_step", "step_params", "write_all"]
