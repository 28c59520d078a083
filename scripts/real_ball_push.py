"""Gentle ball contacts on the real rcssserver3d 0.7.3 and on ours: walks that run into a ball lying in their
path. Usage (re-runs itself inside netns.sh): python scripts/real_ball_push.py OUTDIR [physics.toml ...]
Ours (our agent, closed loop) is run with the default physics and once per physics file given
(NAO3D_PHYSICS_FILE). Prints one JSON row per case: ball travel [m], farthest, end position, fallen; the real runs
are written to OUTDIR as fixtures (real_0.7.3_skill_<case>.jsonl.gz)."""
import json, math, os, sys
from dataclasses import replace
from pathlib import Path
from motion_studio.realserver import process
from motion_studio.realserver.cases import CASES, Case, SkillSequence, motion_source
from agent.skills.base import PlayMotion

scripts = Path(os.environ.get("NAO3D_REAL_SERVER_DIR", Path(__file__).resolve().parents[2] / "shared" / "real-server"))
if not process.in_netns():
    process.reexec_in_netns(scripts, [sys.executable, *sys.argv])
from motion_studio.realserver.skill_runs import run_real, run_sim
from motion_studio.realserver.fixtures import fixture_path, write_fixture

out = Path(sys.argv[1]); out.mkdir(parents=True, exist_ok=True)
physics = sys.argv[2:]
motions = motion_source("HEAD", out / "motions")

def walk(name, seconds, **kw):
    n = int(seconds / 0.02)
    return Case(name, lambda: SkillSequence((PlayMotion(kw.pop("motion_", name.split("@")[0]), repeat=True), n), (None, None)), n + 100, **kw)

cases = [
    replace(walk("walk_forward@ball_right_foot", 5.0), position_m=(-8.0, 0.0), ball_m=(-7.7, -0.055), motion="walk_forward"),
    replace(walk("walk_forward@ball_centre", 5.0), position_m=(-8.0, 0.0), ball_m=(-7.7, 0.0), motion="walk_forward"),
    replace(walk("walk_forward@ball_left_foot", 5.0), position_m=(-8.0, 0.0), ball_m=(-7.7, 0.06), motion="walk_forward"),
]
# side-step into a ball beside the left foot (robot faces +x, left = +y)
cases.append(Case("walk_left@ball_beside", lambda: SkillSequence((PlayMotion("walk_left", repeat=True), 150), (None, None)), 250,
                  position_m=(-8.0, 0.0), ball_m=(-7.95, 0.2), motion="walk_left"))
rows = []
for case in cases:
    name = case.name.replace("@", "_")
    case = replace(case, name=name)
    try:
        real, lines = run_real(case, motions, scripts, out, tool="scripts/real_ball_push.py")
        write_fixture(lines, fixture_path(out, name))
    except Exception as e:
        print(name, "real failed", e); continue
    def travel(run):
        ts = [t for t in run.truths if t is not None]
        return round(math.dist(ts[0].ball_m[:2], ts[-1].ball_m[:2]), 3), round(max(math.dist(ts[0].ball_m[:2], t.ball_m[:2]) for t in ts), 3), [round(v, 3) for v in ts[-1].ball_m[:2]], any(t.fallen for t in ts)
    row = {"case": name, "real": travel(real)}
    for ph in [None, *physics]:
        if ph: os.environ["NAO3D_PHYSICS_FILE"] = ph
        else: os.environ.pop("NAO3D_PHYSICS_FILE", None)
        row[ph or "default"] = travel(run_sim(case, motions))
    os.environ.pop("NAO3D_PHYSICS_FILE", None)
    print(json.dumps(row), flush=True)
    rows.append(row)
(out / "push.json").write_text(json.dumps(rows, indent=1))
