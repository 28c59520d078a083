"""Play a motion file on a simulated robot, headless: the result in numbers, a plot and an HTML animation.

Why: the quickest answer to "does this motion work?" without opening the editor — the same physics
preview the editor runs (the agent's motion controller on our MuJoCo world, through the protocol bytes),
usable from scripts and CI jobs of a motion author.
"""

from __future__ import annotations

import logging
from pathlib import Path

import numpy as np

from motion_studio.editor.physics_preview import PreviewResult, run_physics_preview
from motion_studio.figures import write_png
from motions import Motion

logger = logging.getLogger(__name__)

#: Frames per second of the HTML animation (the physics runs at 50 Hz; every second cycle is drawn).
ANIMATION_FPS = 25


#: File-name prefixes of motions played from lying: a stand-up starts on the side its name ends with.
LYING_PREFIXES = ("standup_", "stand_up_", "getup_", "get_up_")


def default_start(path: Path) -> str:
    """The start ``play --start auto`` picks: lying on the back for ``standup_back.xml`` (front for
    ``..._front``), standing for every other motion."""
    stem = path.stem.lower()
    if stem.startswith(LYING_PREFIXES):
        for side in ("back", "front", "side"):
            if stem.endswith(side):
                return side
    return "standing"


def play_motion(motion: Motion, robot_type: int = 0, hold_s: float = 1.0, start: str = "standing") -> PreviewResult:
    """Run the motion on a simulated robot from ``start`` (see ``motion_studio.editor.physics_preview``)."""
    return run_physics_preview(motion, robot_type, hold_s=hold_s, start=start)


def write_plot(result: PreviewResult, title: str, path: Path) -> Path:
    """Torso height and torso up-axis z over the motion's time, with the fall threshold, as a PNG."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    figure, (height, up) = plt.subplots(2, 1, figsize=(8, 5), sharex=True)
    height.plot(result.times_s, result.torso_height_m, color="tab:blue")
    height.set_ylabel("torso height [m]")
    height.axvline(result.motion_duration_s, color="grey", linestyle=":", label="authored end")
    height.legend(loc="lower left")
    up.plot(result.times_s, result.up_z, color="tab:red")
    up.axhline(0.6, color="grey", linestyle="--", label="fall threshold (REFERENCE §8.1)")
    up.set_ylabel("torso up-axis z")
    up.set_xlabel("motion time [s] (negative: standing before the start)")
    up.legend(loc="lower left")
    if result.start == "standing":
        verdict = f"fell at {result.fall_time_s:.2f} s" if result.fell else "stayed up"
    else:
        verdict = f"from lying on the {result.start}: " + ("down after the motion" if result.fell else "stood up")
    figure.suptitle(f"{title}: {verdict}")
    return write_png(figure, path)


def write_animation(result: PreviewResult, robot_type: int, path: Path) -> Path:
    """A standalone meshcat HTML animation of the simulated robot."""
    import meshcat
    import meshcat.animation

    from kinematics.meshcat_server import visualizer
    from kinematics.meshcat_view import add_ground, add_nao, frame_camera

    with visualizer() as vis:
        add_ground(vis, 3.0)
        add_nao(vis, "sim", robot_type)
        frame_camera(vis)
        stride = max(1, round(1.0 / (ANIMATION_FPS * 0.02)))
        animation = meshcat.animation.Animation(default_framerate=ANIMATION_FPS)
        for frame, poses in enumerate(result.body_poses[::stride]):
            with animation.at_frame(vis, frame) as at:
                for body, pose in poses.items():
                    at[f"sim/{body}"].set_transform(np.asarray(pose))
        vis.set_animation(animation, play=False, repetitions=1)
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(vis.static_html())
    return path


__all__ = ["default_start", "play_motion", "write_animation", "write_plot"]
