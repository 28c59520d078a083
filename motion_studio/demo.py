"""The main job's steps: what the toolkit can show end to end today, written to an output folder."""

from __future__ import annotations

import logging
import math
from pathlib import Path

import meshcat
import numpy as np

from kinematics.fk import NaoKinematics
from kinematics.ik import PoseTarget, WholeBodyIK
from kinematics.meshcat_server import visualizer
from kinematics.meshcat_view import NaoPosePainter, add_ground, add_nao, frame_camera
from kinematics.mjcf import write_robot_mjcf
from kinematics.spec import ROBOT_TYPES, robot_spec
from kinematics.urdf import write_robot_urdf

log = logging.getLogger(__name__)


def model_summary() -> list[str]:
    """One line per robot type: mass, standing heights, joint count; then the joint table of type 0."""
    lines = ["type  mass_kg  torso_above_sole_m  camera_height_m  hinges"]
    for robot_type in ROBOT_TYPES:
        spec = robot_spec(robot_type)
        kin = NaoKinematics(robot_type)
        lines.append(f"{robot_type:>4}  {spec.total_mass_kg:7.4f}  {-spec.sole_z_m:18.6f}  "
                     f"{kin.camera_height_m():15.6f}  {len(spec.joints):6d}")
    lines.append("")
    lines.append("wire  effector  nao_name          min_deg  max_deg  axis")
    for joint in robot_spec(0).joints:
        lines.append(f"{joint.perceptor:<5} {joint.effector:<9} {joint.nao_name:<17} {joint.min_deg:7.1f}  "
                     f"{joint.max_deg:7.1f}  {tuple(round(a, 4) for a in joint.axis)}")
    return lines


def crouch_keyframe(torso_height_m: float = 0.33) -> dict[str, float]:
    """A walk-ready crouch by whole-body IK: soles flat under the hips, torso upright at the given height."""
    identity = np.eye(3)
    ik = WholeBodyIK(0)
    result = ik.solve({"lfoot": PoseTarget((-0.055, 0.025, 0.0), identity),
                       "rfoot": PoseTarget((0.055, 0.025, 0.0), identity),
                       "torso": PoseTarget((0.0, 0.0, torso_height_m), identity)})
    return result.angles_rad


def write_preview(path: Path, angles_rad: dict[str, float]) -> Path:
    """Standalone meshcat HTML of the zero pose (ghost) and the IK crouch side by side."""
    with visualizer() as vis:  # the server child ends with the block
        add_ground(vis, 1.5)
        frame_camera(vis)
        painter = NaoPosePainter(0)
        add_nao(vis, "zero_pose", 0, opacity=0.35)
        zero = painter.body_poses()
        for pose in zero.values():
            pose[0, 3] -= 0.25
        for body, pose in zero.items():
            vis[f"zero_pose/{body}"].set_transform(pose)
        add_nao(vis, "crouch", 0)
        painter.paint(vis, "crouch", angles_rad)
        path.write_text(vis.static_html())
    return path


def run_demo(out_dir: Path, match_duration_s: float = 600.0, players_per_team: int = 11) -> list[str]:
    """Model summary, exported models, a preview, then a headless match with a replay; returns report lines."""
    out_dir.mkdir(parents=True, exist_ok=True)
    report = model_summary()
    for robot_type in ROBOT_TYPES:
        write_robot_mjcf(out_dir / f"nao_type{robot_type}.xml", robot_type)
        write_robot_urdf(out_dir / f"nao_type{robot_type}.urdf", robot_type)
    angles = crouch_keyframe()
    report.append("")
    report.append("IK crouch (torso 0.33 m): " + ", ".join(
        f"{n} {math.degrees(v):.1f}" for n, v in angles.items() if abs(v) > 1e-4))
    report.append(f"camera height in the crouch: {NaoKinematics(0).camera_height_m(angles):.4f} m")
    preview = write_preview(out_dir / "preview.html", angles)
    report.append(f"wrote {out_dir}/nao_type*.xml, *.urdf and {preview}")
    if match_duration_s > 0:
        report.extend(play_match(out_dir, match_duration_s, players_per_team))
    return report


def play_match(out_dir: Path, duration_s: float, players_per_team: int) -> list[str]:
    """A headless match of our agents on our simulator, its monitor log and a meshcat replay file."""
    from motion_studio.match_report import run_and_report
    from sim.replay import replay_log

    match_dir = out_dir / "match"
    lines, results = run_and_report(players=players_per_team, duration_s=duration_s, matches=1, workers=1, seed=0,
                                    out=match_dir, log=True, team_left="Left", team_right="Right", resume=False)
    log_path = match_dir / "match-0.log.gz"
    replay = replay_log(log_path, html_out=match_dir / "replay.html", max_frames=1500)
    return [""] + lines + [f"monitor log: {log_path}", f"replay: {replay}"]
