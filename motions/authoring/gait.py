"""Walk engine: a parametrised foot-trajectory gait with a crouched torso, solved keyframe by keyframe with IK.

The gait (one family: forward, backward, sideways, turning, in place):

1. **Footsteps.** Steps alternate, the left foot first. Each swing foot lands relative to the stance foot:
   ``step_length_m`` ahead, ``foot_spacing_m`` to its side; a sideways or turning gait *opens* with the
   leading foot (it lands ``side_step_m`` farther out / ``turn_step_deg`` rotated outward) and *closes*
   with the other (it lands parallel at ``foot_spacing_m``), because the hip yaw joints of the Nao turn a
   foot outward only (REFERENCE §2.2 limits). ``ramp_steps`` steps grow to full size at the start and
   shrink at the stop, where the last step closes the feet side by side.
2. **Torso.** Its ground point moves linearly from one mid-feet pose (at the end of a step) to the next;
   it is ``torso_forward_m`` ahead of that point, at ``torso_height_m``, pitched ``torso_pitch_deg``
   forward, and sways ``sway_m`` toward the stance foot (a sine over each step, shifted by
   ``sway_phase``): the lateral motion a linear inverted pendulum at this step rate needs is a few
   millimetres, so a small sway plus the feet's width carry the robot.
3. **Swing.** Each step starts with ``double_support_cycles`` on both feet; then the swing foot travels
   on a cycloid (zero speed at lift-off and touch-down) and rises ``step_height_m`` on a raised cosine.
4. **Keyframes.** One keyframe per 20 ms cycle, each solved with ``kinematics.ik.WholeBodyIK`` (feet hard,
   torso soft), written as XML phases: ``start_*`` (stance, ramp-up), ``cycle_*`` (one stride = a left and
   a right step; ``next`` loops), ``stop_*`` (ramp-down to the stance). The last phase of the stride has
   ``finalize`` -> the stop and ``isFinal``; the stance phase is skipped when ``in_walk_position`` is set.
   The swing leg's hip yaw, hip pitch and ankle pitch in the cycle phases carry ``computed`` walk-lean
   names, so the controller can steer the walk (REFERENCE §7.2; ``agent.motion.dynamic.WalkLean``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from pathlib import Path

from motions.authoring.common import (ANGLE_DECIMALS, ARMS, LEGS, ArmPose, FootPose, KeyframeSolver,
                                      targets_deg)
from motions.model import SERVER_CYCLE_MS, XML, JointTarget, Keyframe, Motion

CYCLE_S = SERVER_CYCLE_MS / 1000.0
#: Flag set while the robot stands in the walk stance (skips the stance phase of walks and kicks).
STANCE_FLAG = "in_walk_position"


@dataclass(frozen=True)
class GaitParams:
    """Parameters of one gait (units in the names; angles SimSpark-signed)."""

    step_cycles: int = 8
    """Cycles per step (one foot's swing plus the double support) [cycles of 20 ms]."""
    double_support_cycles: int = 1
    """Cycles at the start of each step with both feet on the ground."""
    step_length_m: float = 0.06
    """Forward distance of a landing foot ahead of the stance foot [m] (negative walks backward)."""
    side_step_m: float = 0.0
    """Extra sideways opening of the leading foot per stride [m] (+ = to the right)."""
    turn_step_deg: float = 0.0
    """Turn per stride [deg] (+ = left), made by opening the leading foot."""
    step_height_m: float = 0.025
    """Height of the swing foot's sole at mid-swing [m]."""
    torso_height_m: float = 0.345
    """Torso centre above the ground [m] (0.385 standing straight, type 0)."""
    torso_pitch_deg: float = 8.0
    """Torso lean forward [deg]."""
    torso_forward_m: float = 0.0
    """Torso centre ahead of the mid-feet point [m] (places the CoM over the feet)."""
    foot_spacing_m: float = 0.11
    """Distance between the sole centres, side to side [m]."""
    sway_m: float = 0.01
    """Sideways torso shift toward the stance foot at mid-step [m]."""
    sway_phase: float = 0.0
    """Shift of the sway curve against the step, as a fraction of a step (+ = later)."""
    arm: ArmPose = ArmPose()
    """Arm pose."""
    arm_swing_deg: float = 0.0
    """Shoulder pitch swing amplitude [deg] (the arm opposite the swing leg goes forward)."""
    ramp_steps: int = 2
    """Steps of growing size at the start (and shrinking at the stop)."""
    stance_ms: int = 300
    """Duration of the stance phase that starts the motion [ms]."""
    stop_hold_ms: int = 200
    """Duration of the last stop phase (holding the stance) [ms]."""
    toe_out_deg: float = 0.0
    """Each foot yawed outward by this [deg] (the hip yaw-pitch joints turn a foot outward only, so with
    hip roll and deep pitch a straight foot can need an inward yaw beyond their 1° limit)."""
    swing_linear: float = 0.0
    """Blend of the swing foot's travel profile: 0 = cycloid (zero speed at lift-off and touch-down), 1 =
    linear (lowest peak speed; the hip joints' 6.14 rad/s limit caps the swing speed)."""

    @property
    def step_s(self) -> float:
        return self.step_cycles * CYCLE_S

    @property
    def speed_m_s(self) -> float:
        """Nominal forward speed [m/s]."""
        return self.step_length_m / self.step_s

    @property
    def side_speed_m_s(self) -> float:
        """Nominal sideways speed [m/s], + = left (one opening per stride of two steps)."""
        return -self.side_step_m / (2.0 * self.step_s)


@dataclass(frozen=True)
class Step:
    """One planned step: which foot swings, where it lands (ground frame), the size scale used."""

    side: str
    landing: FootPose
    scale: float


def _relative(base: FootPose, dx: float, dy: float, dyaw: float) -> FootPose:
    """The pose (dx right, dy forward, dyaw) in ``base``'s frame, in the ground frame."""
    c, s = math.cos(base.yaw_rad), math.sin(base.yaw_rad)
    return FootPose(base.x_m + c * dx - s * dy, base.y_m + s * dx + c * dy, 0.0, base.yaw_rad + dyaw)


def plan_steps(params: GaitParams, scales: list[float]) -> tuple[FootPose, FootPose, list[Step]]:
    """Footsteps for a sequence of step scales (0 = close the feet side by side, 1 = full step).

    Returns:
        (left start, right start, steps): both feet start side by side around the origin.
    """
    half = params.foot_spacing_m / 2.0
    left, right = FootPose(-half, 0.0), FootPose(half, 0.0)
    feet = {"left": left, "right": right}
    steps = []
    side = "left"
    turn_rad = math.radians(params.turn_step_deg)
    for scale in scales:
        stance = feet["right" if side == "left" else "left"]
        outward = -1.0 if side == "left" else 1.0  # the swing foot's outward direction along x
        lateral = outward * params.foot_spacing_m
        yaw = 0.0
        leading = (params.side_step_m < 0) == (side == "left") if params.side_step_m else False
        if leading:
            lateral += scale * params.side_step_m
        turning_leader = (params.turn_step_deg > 0) == (side == "left") if params.turn_step_deg else False
        if turning_leader:
            yaw = scale * turn_rad
        landing = _relative(stance, lateral, scale * params.step_length_m, yaw)
        steps.append(Step(side, landing, scale))
        feet[side] = landing
        side = "right" if side == "left" else "left"
    return left, right, steps


def _mid(a: FootPose, b: FootPose) -> tuple[float, float, float]:
    return (a.x_m + b.x_m) / 2.0, (a.y_m + b.y_m) / 2.0, (a.yaw_rad + b.yaw_rad) / 2.0


def _cycloid(phase: float) -> float:
    return phase - math.sin(2.0 * math.pi * phase) / (2.0 * math.pi)


@dataclass(frozen=True)
class Sample:
    """One keyframe's geometry: feet in the torso's ground frame, sway, arm swing, where it belongs."""

    left: FootPose
    right: FootPose
    swing_side: str | None
    arm_phase: float


def sample_steps(params: GaitParams, left: FootPose, right: FootPose, steps: list[Step],
                 sway_scale: list[float] | None = None) -> list[Sample]:
    """Keyframe geometry at the end of every cycle of every step, relative to the moving torso point."""
    samples = []
    feet = {"left": left, "right": right}
    n, ds = params.step_cycles, params.double_support_cycles
    for index, step in enumerate(steps):
        start = dict(feet)
        mid_start = _mid(start["left"], start["right"])
        end = dict(start)
        end[step.side] = step.landing
        mid_end = _mid(end["left"], end["right"])
        sway_amount = params.sway_m * (sway_scale[index] if sway_scale else 1.0)
        stance_sign = 1.0 if step.side == "left" else -1.0  # torso shifts toward the stance foot (+x = right)
        for cycle in range(1, n + 1):
            u = cycle / n
            swing_phase = 0.0 if cycle <= ds else (cycle - ds) / (n - ds)
            blend = (1.0 - params.swing_linear) * _cycloid(swing_phase) + params.swing_linear * swing_phase
            origin = start[step.side]
            swing = FootPose(origin.x_m + blend * (step.landing.x_m - origin.x_m),
                             origin.y_m + blend * (step.landing.y_m - origin.y_m),
                             params.step_height_m * (1.0 - math.cos(2.0 * math.pi * swing_phase)) / 2.0,
                             origin.yaw_rad + blend * (step.landing.yaw_rad - origin.yaw_rad))
            now = dict(start)
            now[step.side] = swing
            torso_x = mid_start[0] + u * (mid_end[0] - mid_start[0])
            torso_y = mid_start[1] + u * (mid_end[1] - mid_start[1])
            torso_yaw = mid_start[2] + u * (mid_end[2] - mid_start[2])
            sway = stance_sign * sway_amount * math.sin(math.pi * ((u - params.sway_phase) % 1.0))
            relative = {}
            c, s = math.cos(-torso_yaw), math.sin(-torso_yaw)
            for side, foot in now.items():
                dx, dy = foot.x_m - torso_x, foot.y_m - torso_y
                relative[side] = FootPose(c * dx - s * dy - sway, s * dx + c * dy - params.torso_forward_m, foot.z_m,
                                          foot.yaw_rad - torso_yaw)
            arm_phase = (u / 2.0 if step.side == "left" else 0.5 + u / 2.0) * step.scale
            samples.append(Sample(relative["left"], relative["right"], step.side, arm_phase))
        feet = end
    return samples


def _arm_offsets(params: GaitParams, sample: Sample) -> tuple[float, float]:
    """Shoulder pitch offsets (left, right) [deg]: the arm opposite the swinging leg swings forward."""
    if not params.arm_swing_deg or sample.swing_side is None:
        return 0.0, 0.0
    swing = params.arm_swing_deg * math.sin(2.0 * math.pi * sample.arm_phase)
    return -swing, swing


def solve_samples(params: GaitParams, samples: list[Sample], solver: KeyframeSolver) -> list[dict[str, float]]:
    """Joint angles (wire -> rad) of each sample (IK for the legs, the arm pose for the arms)."""
    pitch = math.radians(params.torso_pitch_deg)
    poses = []
    toe_out = math.radians(params.toe_out_deg)
    for sample in samples:
        left = replace(sample.left, yaw_rad=sample.left.yaw_rad + toe_out)
        right = replace(sample.right, yaw_rad=sample.right.yaw_rad - toe_out)
        angles = dict(solver.solve(params.torso_height_m, left, right, pitch))
        angles.update(params.arm.angles_rad(*_arm_offsets(params, sample)))
        poses.append(angles)
    return poses


def stance_pose(params: GaitParams, solver: KeyframeSolver) -> dict[str, float]:
    """The walk stance: feet side by side, torso at its height and pitch, arms in their pose."""
    half = params.foot_spacing_m / 2.0
    sample = Sample(FootPose(-half, -params.torso_forward_m), FootPose(half, -params.torso_forward_m), None, 0.0)
    return solve_samples(params, [sample], solver)[0]


def _phase(name: str, angles: dict[str, float], duration_ms: int, joints: tuple[str, ...] = LEGS + ARMS,
           **attributes: object) -> Keyframe:
    return Keyframe(name, duration_ms / 1000.0, targets_deg(angles, joints), **attributes)  # type: ignore[arg-type]


#: Leg joints whose cycle targets carry walk-lean names: hip yaw-pitch, hip pitch and ankle pitch (the seed
#: agent's lean, REFERENCE §7.2). The hip yaw-pitch can only turn a foot outward (limit +1°); measured on
#: our simulator, a foot turned outward through its swing curves the walk toward the *other* side (its
#: 45° axis also pitches the hip), so the hip yaw-pitch carries the opposite lean's name (a left lean turns
#: the right foot out); hip and ankle pitch carry their own side's name as in the seed agent.
LEAN_JOINTS = (1, 3, 5)
OPPOSITE_LEAN_JOINTS = (1,)


def lean_side(cycle_index: int, params: GaitParams) -> str:
    """The leg whose walk-lean values a cycle phase carries (the cycle starts with the left step): the
    swinging leg, from its lift-off through the double support after its landing, so that its offsets
    are set in the air and released only when the other foot lifts (a release in double support would
    twist the robot on both soles)."""
    n, ds = params.step_cycles, params.double_support_cycles
    shifted = (cycle_index - ds) % (2 * n)
    return "left" if shifted < n else "right"


def _with_lean(keyframe: Keyframe, side: str) -> Keyframe:
    """Mark the lean joints of ``side``'s leg in a cycle phase as ``{lean}_walk_lean_{effector}`` computed
    values, ``lean`` = ``side`` (hip and ankle pitch) or the other side (hip yaw-pitch, OPPOSITE_LEAN_JOINTS)."""
    prefix = side[0]
    other = "right" if side == "left" else "left"
    targets = dict(keyframe.targets)
    for number in LEAN_JOINTS:
        joint, effector = f"{prefix}lj{number}", f"{prefix}le{number}"
        lean = other if number in OPPOSITE_LEAN_JOINTS else side
        targets[joint] = JointTarget(targets[joint].angle_rad, f"{lean}_walk_lean_{effector}")
    return replace(keyframe, targets=targets)


def ramp_scales(ramp_steps: int) -> list[float]:
    """Step scales of the start ramp: (1 .. ramp) / (ramp + 1)."""
    return [(i + 1) / (ramp_steps + 1) for i in range(ramp_steps)]


def build_walk(name: str, params: GaitParams, solver: KeyframeSolver | None = None,
               header_comments: tuple[str, ...] = (), measured: dict[str, float] | None = None,
               stance: GaitParams | None = None) -> Motion:
    """The XML phase motion of a gait: stance, ramp-up, a cyclic stride, and a stop through ``finalize``.

    ``stance`` (default: ``params``) gives the pose of the stance phase and of ``stop_hold``: the shared
    walk stance of ``stand``. Why: the stance flag (``in_walk_position``) that ``stand``, the walks' stops,
    turns and kicks set makes every walk skip its own stance phase, so a walk whose stance differed from
    ``stand``'s (e.g. by its toe-out) started from two different poses and ended its stop in a pose the
    next start did not expect; measured on our simulator, walk_forward (toe-out 3.3°) restarted from its
    own stance fell in 10 of 10 trials and from ``stand``'s in 0 of 10.

    Constants written into the file: ``speed_m_s`` (nominal forward speed; the controller's slowdown and
    walk lean key on it), ``side_speed_m_s`` (nominal, + = left), ``step_s``, ``turn_per_stride_deg``, and
    ``measured`` figures (e.g. ``measured_forward_m_s`` from the tuner's runs on the simulator).

    The start and the cycle come from one footstep plan (ramp, then full steps), so the last start phase
    leads into the cycle without a jump; the stop is planned from the cycle's end state.

    Raises:
        kinematics.IKError: a keyframe out of reach.
    """
    solver = solver or KeyframeSolver()
    solver.ik.reset()  # the IK warm-starts: a motion must not depend on what was solved before it
    ramp = ramp_scales(params.ramp_steps)
    # The ramp has an even number of steps before the cycle so that the cycle starts with the left foot.
    if len(ramp) % 2:
        ramp = [ramp[0] / 2.0] + ramp
    scales = ramp + [1.0, 1.0, 1.0, 1.0]
    left, right, steps = plan_steps(params, scales)
    sway = [min(1.0, 0.5 + s) for s in scales]
    samples = sample_steps(params, left, right, steps, sway)
    n = params.step_cycles
    start_samples = samples[:(len(ramp) + 2) * n]  # the ramp and one full stride, which ends steady
    cycle_samples = samples[(len(ramp) + 2) * n:(len(ramp) + 4) * n]  # the second full stride: steady
    stop_scales = [1.0, 1.0] + list(reversed(ramp_scales(params.ramp_steps))) + [0.0]
    if (len(stop_scales) - 2) % 2:
        stop_scales = stop_scales[:-1] + [stop_scales[-2] / 2.0, 0.0]
    s_left, s_right, s_steps = plan_steps(params, stop_scales)
    s_sway = [min(1.0, 0.5 + s) for s in stop_scales]
    stop_samples = sample_steps(params, s_left, s_right, s_steps, s_sway)[2 * n:]

    stance_angles = stance_pose(params, solver)  # also the IK's warm start for the keyframes that follow
    start_poses = solve_samples(params, start_samples, solver)
    cycle_poses = solve_samples(params, cycle_samples, solver)
    stop_poses = solve_samples(params, stop_samples, solver)
    if stance is not None:
        solver.ik.reset()  # solved as build_stance solves it: the same angles as ``stand``
        stance_angles = stance_pose(stance, solver)
    ms = round(CYCLE_S * 1000)

    phases: list[Keyframe] = []
    first_cycle = "cycle_00"
    phases.append(_phase("stance", stance_angles, params.stance_ms, next="start_00" if start_poses else first_cycle,
                         skip_if_flag=STANCE_FLAG))
    for i, pose in enumerate(start_poses):
        following = f"start_{i + 1:02d}" if i + 1 < len(start_poses) else first_cycle
        phases.append(_phase(f"start_{i:02d}", pose, ms, next=following,
                             set_flag_false=STANCE_FLAG if i == 0 else None))
    for i, pose in enumerate(cycle_poses):
        last = i + 1 == len(cycle_poses)
        keyframe = _phase(f"cycle_{i:02d}", pose, ms, next=first_cycle if last else f"cycle_{i + 1:02d}",
                          is_final=True if last else None, finalize="stop_00" if last else None,
                          set_flag_false=STANCE_FLAG if i == 0 else None)
        phases.append(_with_lean(keyframe, lean_side(i, params)))
    for i, pose in enumerate(stop_poses):
        following = f"stop_{i + 1:02d}" if i + 1 < len(stop_poses) else "stop_hold"
        phases.append(_phase(f"stop_{i:02d}", pose, ms, next=following))
    phases.append(_phase("stop_hold", stance_angles, params.stop_hold_ms, is_final=True, set_flag_true=STANCE_FLAG))
    constants = {"speed_m_s": round(params.speed_m_s, 4), "side_speed_m_s": round(params.side_speed_m_s, 4),
                 "step_s": round(params.step_s, 4), "turn_per_stride_deg": params.turn_step_deg,
                 **{key: round(value, 4) for key, value in (measured or {}).items()}}
    return Motion(name, phases, source_format=XML, first_phase="stance", constants=constants,
                  header_comments=header_comments)


def build_stance(name: str, params: GaitParams, solver: KeyframeSolver | None = None,
                 header_comments: tuple[str, ...] = (), duration_ms: int = 400) -> Motion:
    """A one-phase motion that goes to the walk stance and sets ``in_walk_position``."""
    solver = solver or KeyframeSolver()
    solver.ik.reset()
    pose = stance_pose(params, solver)
    phase = _phase("stance", pose, duration_ms, is_final=True, set_flag_true=STANCE_FLAG)
    return Motion(name, [phase], source_format=XML, first_phase="stance", header_comments=header_comments)


#: Motions written by ``python -m motions.authoring.gait`` (the stance first: walks start from it).
MOTION_NAMES = ("stand", "walk_forward", "walk_fast", "walk_backward", "walk_left", "walk_right", "orbit_left",
                "orbit_right")
#: Section keys of the parameter file copied into a walk's constants (the tuner's measurements).
MEASURED_KEYS = ("measured_forward_m_s", "measured_left_m_s", "measured_stop_m")
COMMAND = "python -m motions.authoring.gait"


def build_named(name: str, params: GaitParams, header_comments: tuple[str, ...] = (),
                measured: dict[str, float] | None = None, solver: KeyframeSolver | None = None,
                stance: GaitParams | None = None) -> Motion:
    """The motion ``name`` of MOTION_NAMES (``stand`` = the stance alone, else a walk whose stance and
    stop end are ``stance``'s, see :func:`build_walk`)."""
    if name == "stand":
        return build_stance(name, params, solver, header_comments)
    return build_walk(name, params, solver, header_comments, measured, stance)


def write_gait_files(params_path: Path | None = None, out_dir: Path | None = None,
                     names: tuple[str, ...] = MOTION_NAMES) -> list[Path]:
    """Generate the gait motions from the parameter file and write them as ``<name>.xml``.

    Returns:
        The paths written.

    Raises:
        ValueError: a bad parameter file or a motion missing from it; kinematics.IKError: a keyframe out of
        reach.
    """
    import tomllib

    from motions import save
    from motions.authoring.common import FILES_DIR, header
    from motions.authoring.gait_params import GAIT_PARAMS_PATH, load_gait_params

    params_path = Path(params_path or GAIT_PARAMS_PATH)
    out_dir = Path(out_dir or FILES_DIR)
    table = load_gait_params(params_path)
    raw = tomllib.loads(params_path.read_text(encoding="utf-8"))
    missing = [name for name in names if name not in table]
    if missing:
        raise ValueError(f"{params_path}: no section for {missing}; sections: {sorted(table)}")
    out_dir.mkdir(parents=True, exist_ok=True)
    written = []
    solver = KeyframeSolver()
    for name in names:
        params = table[name]
        section = raw.get(name, {})
        lines = header("motions.authoring.gait", params_path, name, params, COMMAND)
        if section.get("provenance"):
            lines = lines[:-1] + (f" Provenance: {section['provenance']} ".replace("--", "- -"),) + lines[-1:]
        measured = {key: float(section[key]) for key in MEASURED_KEYS if key in section}
        motion = build_named(name, params, lines, measured, solver, table.get("stand"))
        path = out_dir / f"{name}.xml"
        save(motion, path)
        written.append(path)
    return written


def main(argv: list[str] | None = None) -> int:
    """``python -m motions.authoring.gait [--params FILE] [--out DIR] [NAME ...]``."""
    import argparse

    parser = argparse.ArgumentParser(prog=COMMAND, description="Write the walk motions from the gait parameters.")
    parser.add_argument("names", nargs="*", help=f"motions to write (default: {' '.join(MOTION_NAMES)})")
    parser.add_argument("--params", type=Path, default=None, help="gait parameter file (motions/params/gait.toml)")
    parser.add_argument("--out", type=Path, default=None, help="output folder (motions/files)")
    args = parser.parse_args(argv)
    for path in write_gait_files(args.params, args.out, tuple(args.names) or MOTION_NAMES):
        print(path)
    return 0


__all__ = ["ANGLE_DECIMALS", "MOTION_NAMES", "STANCE_FLAG", "GaitParams", "Sample", "Step", "build_named",
           "build_stance", "build_walk", "lean_side", "plan_steps", "ramp_scales", "sample_steps", "solve_samples",
           "stance_pose", "write_gait_files"]


if __name__ == "__main__":
    raise SystemExit(main())
