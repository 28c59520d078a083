"""The kicking foot meets the field where ODE's joint drift puts it (``PhysicsParams.swing_drift_ground_m``, 2 cm by
default; sim/physics_candidates/swing_drift_ground.toml holds 1 cm): the real kick's commands then keep our robot
upright and the ground stops the kicking hip, as on the real server."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from sim.physics_params import PHYSICS_FILE_ENV, default_physics_params, load_physics_file
from sim.world import BALL_TWIN_SUFFIX, World
from tests.sim import test_real_skill_traces as traces

CANDIDATE = Path(__file__).parents[2] / "sim" / "physics_candidates" / "swing_drift_ground.toml"
OFF = Path(__file__).parent / "fixtures" / "physics_swing_drift_ground_off.toml"


def _foot_twins(world: World) -> list[str]:
    return sorted(world.model.geom(int(g)).name for g in world._swing_twins)


def test_the_feet_twins_may_meet_the_field_by_default_and_standing_they_meet_the_ball_only():
    off = World(default_physics_params(swing_drift_ground_m=None))
    off.add_robot(1, 0)
    assert _foot_twins(off) == []
    assert default_physics_params(**load_physics_file(CANDIDATE)).swing_drift_ground_m == 0.01
    world = World(default_physics_params())
    world.add_robot(1, 0)
    assert world.params.swing_drift_ground_m == 0.02
    assert _foot_twins(world) == [f"r1_lfoot{BALL_TWIN_SUFFIX}", f"r1_rfoot{BALL_TWIN_SUFFIX}"]
    compiled = world.model.geom_conaffinity[world._swing_twins].copy()   # as built: the ball only
    for _ in range(25):   # standing: both feet loaded, no drift: the twins keep meeting the ball only
        world.step()
    assert np.array_equal(world.model.geom_conaffinity[world._swing_twins], compiled)
    field = world.model.geom("field").id
    assert not np.any(compiled & world.model.geom_contype[field])                  # not the field
    assert not np.any(compiled & world.model.geom_contype[world.ball_geom] == 0)   # the ball, yes


def _kicking_hip(monkeypatch, physics_file: Path | None) -> tuple[bool, list[float], list[float]]:
    if physics_file is None:
        monkeypatch.delenv(PHYSICS_FILE_ENV, raising=False)
    else:
        monkeypatch.setenv(PHYSICS_FILE_ENV, str(physics_file))
    run = traces.replay.__wrapped__("kick")
    start = run.meta["skill_cycle"]
    upright = traces.upright(run.ours, range(start, max(run.real) + 1))
    hip = [run.our_joints[start + i]["rlj3"] for i in (109, 110, 111)]
    real = [run.real_joints[start + i]["rlj3"] for i in (109, 110, 111)]
    return upright, hip, real


def test_the_real_kick_s_commands_keep_the_robot_up_and_the_ground_stops_the_kicking_hip(monkeypatch):
    # The real kicking hip (rlj3) is stopped and thrown back right after the strike (24.8 -> 17.9 -> 12.2 deg while
    # commanded on). Without the mechanism ours follows its commands (25.1 -> 32.1 -> 39.2) and falls ~3 s later;
    # with it the drifted foot scrapes the ground: 25.1 -> 20.8 -> 21.7, upright.
    upright, hip, real = _kicking_hip(monkeypatch, None)
    assert real[2] < real[0] - 10.0                      # the real hip thrown back
    assert upright
    assert max(hip) < 26.0 and hip[2] < hip[0] - 2.0     # ours stopped and thrown back too
    upright_off, hip_off, _ = _kicking_hip(monkeypatch, OFF)
    assert not upright_off                               # without it: falls where the real robot stands
    assert hip_off[2] > hip_off[0] + 10.0                # and the hip follows its commands on
