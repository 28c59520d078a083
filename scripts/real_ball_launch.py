"""Ball launches on the real rcssserver3d 0.7.3 (no robot near): how far a ball goes per launch speed and
elevation, from the ground (centre at 0.042 m, touching it) or clean in the air (0.07 m), to judge whether a
lofted kick pays. Usage (re-runs itself inside netns.sh):

    python scripts/real_ball_launch.py [--speeds 4.6,6,8] [--elevations 0,15,30,45] [--heights 0.042,0.07]

Prints one line per launch: rest distance, where the first bounce landed, the highest point. The trainer's
``(ball (pos x y z)(vel vx 0 vz))`` sets no spin. Measured 2026-11-26 (issue 14): 6 m/s from the ground goes
4.06 m flat, 4.56 m at 30 deg; clean in the air 5.97 m at 30 deg; 8 m/s clean at 30 deg 8.80 m; 4.6 m/s
clean at 30 deg 4.12 m. A ball touching the ground when launched loses about 2/7 of its horizontal speed in
the first step (it starts to roll), and each bounce (restitution about 0.7 on the soft ground) takes 20-25 %
of its horizontal speed.
"""
import argparse
import math
import sys
from pathlib import Path

from motion_studio.realserver.paths import checked_scripts_dir
from motion_studio.realserver.process import reexec_in_netns

reexec_in_netns(checked_scripts_dir(None), [sys.executable, *sys.argv])

from motion_studio.realserver.rollout_kick import RealKickBench, parse_truth  # noqa: E402
from motion_studio.tune_kick import library_for  # noqa: E402
from motions.authoring.kick import kick_params, stance_params  # noqa: E402

parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("--speeds", default="4.6,6,8")
parser.add_argument("--elevations", default="0,15,30,45")
parser.add_argument("--heights", default="0.042,0.07")
parser.add_argument("--out", type=Path, default=Path("out/real_ball_launch"))
args = parser.parse_args()
START = (-12.0, 4.0)  # the robot stands at (-8, 0), out of the way
with RealKickBench(args.out) as bench:
    bench._open(library_for(kick_params("kick"), stance_params()))
    session = bench.session
    for speed in (float(v) for v in args.speeds.split(",")):
        for elevation in (float(v) for v in args.elevations.split(",")):
            for height in (float(v) for v in args.heights.split(",")):
                x0, y0 = START
                vx, vz = speed * math.cos(math.radians(elevation)), speed * math.sin(math.radians(elevation))
                since = len(session.monitor.frames)
                session.command("(reqfullstate)")
                session.command(f"(ball (pos {x0} {y0} {height})(vel {vx:.4f} 0 {vz:.4f}))")
                bench._steps(600, think=False)  # 12 s: every launch here rests well before
                bench._wait_frame(since, session.game_time_s)
                samples = parse_truth(session.monitor.frames[since:], bench.workdir)
                del session.monitor.frames[:]
                keys = sorted(samples)
                start = next(k for k in keys if abs(samples[k]["ball"][0] - x0) < 0.3
                             and abs(samples[k]["ball"][1] - y0) < 0.01)
                landed = next((k for k in keys if k > start + 2 and samples[k]["ball"][2] < 0.045), None)
                top = max(samples[k]["ball"][2] for k in keys if k >= start)
                first = "-" if landed is None else f"{samples[landed]['ball'][0] - x0:.2f} m"
                print(f"{speed:.1f} m/s at {elevation:.0f} deg from z {height:.3f}: rest "
                      f"{samples[keys[-1]]['ball'][0] - x0:.2f} m, first bounce {first}, top {top:.2f} m", flush=True)
