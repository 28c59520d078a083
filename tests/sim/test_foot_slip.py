"""Feet that slip as SimSpark's do (``PhysicsParams.foot_slip_m_s_per_n``, sim/physics_candidates/foot_slip.toml):
ODE's unbounded friction with force-dependent slip, a tangential damper of 1 / slip N·s/m per contact point, done
as implicit dampers at the foot corners that are below the field.

Measured 2026-11-29 (the numbers the assertions keep): a standing robot pushed sideways with 3 N creeps at
3 N x 0.005 m/s per N / 8 corners = 1.875 mm/s (1.873 measured; MuJoCo's Coulomb contact 0.28 mm/s), and its
FRP carries the push; the 13 cm walk's stance squeezes the feet 4.87 N sideways where the real ones push 4.97 N
(MuJoCo's Coulomb mu = 2: 33.5 N); the real server's back stand-up of the shipped motion, replayed open loop,
stands this world's robot up as it stood the real one, where the default world falls back.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from sim.physics_params import PHYSICS_FILE_ENV, default_physics_params
from sim.world import World
from tests.sim import test_contact_creep as creep
from tests.sim import test_real_skill_traces as traces

CANDIDATE = Path(__file__).parents[2] / "sim" / "physics_candidates" / "foot_slip.toml"
SLIP_M_S_PER_N = 0.005
PUSH_N = 3.0
#: The real server's lying-on-back stand-up of the motions at 35e251e (``motion-studio transfer --case
#: standup_front --record``): the real robot stands at the first attempt.
BACK_STAND_UP_35E251E = "standup_front_35e251e"


def _standing(slip: float | None) -> World:
    world = World(default_physics_params(foot_slip_m_s_per_n=slip))
    world.add_robot(0, 0)
    world.set_team(0, "left", 1)
    world.place_robot(0, -10.0, -3.0, 0.0, z_m=0.385)
    for _ in range(50):
        world.begin_cycle()
        world.step()
        world.end_cycle()
    return world


def _creep_mm_s(world: World) -> tuple[float, np.ndarray]:
    """Push the torso sideways with `PUSH_N` for 2 s: the left foot's speed over the second second [mm/s] and
    the FRP forces at the end (foot frames)."""
    foot, torso = world.by_key[0].foot_bodies["lf"], world.by_key[0].torso_body
    positions = []
    for _ in range(100):
        world.data.xfrc_applied[torso, :3] = [0.0, PUSH_N, 0.0]
        world.begin_cycle()
        world.step()
        world.end_cycle()
        positions.append(world.data.xpos[foot].copy())
    return float(np.linalg.norm(positions[-1] - positions[49]) / 1.0 * 1000.0), world.frp_force.copy()


def test_a_pushed_robot_creeps_at_the_force_dependent_slip_speed_and_its_feet_feel_the_push() -> None:
    speed, frp = _creep_mm_s(_standing(SLIP_M_S_PER_N))
    # every corner of both soles below the field: 8 dampers of 200 N.s/m share the push
    assert speed == pytest.approx(PUSH_N * SLIP_M_S_PER_N / 8 * 1000.0, rel=0.05)
    assert np.linalg.norm(frp[:, :2].sum(axis=0)) == pytest.approx(PUSH_N, abs=0.1)
    assert frp[:, 2].sum() == pytest.approx(4.6071 * 9.81, abs=0.5)
    coulomb_speed, _ = _creep_mm_s(_standing(None))
    assert coulomb_speed < 0.5   # MuJoCo's soft Coulomb contact: 0.28 mm/s


def test_robots_join_and_leave_with_their_frictionless_foot_pairs() -> None:
    world = World(default_physics_params(foot_slip_m_s_per_n=SLIP_M_S_PER_N))
    world.add_robot(0, 0)
    world.add_robot(1, 4)   # type 4: its toes are force-sensing boxes too
    pairs = sorted(pair.name for pair in world.spec.pairs if pair.name)
    assert pairs == ["r0_slip_lfoot", "r0_slip_rfoot", "r1_slip_lfoot", "r1_slip_ltoe", "r1_slip_rfoot",
                     "r1_slip_rtoe"]
    world.remove_robot(0)
    assert sorted(pair.name for pair in world.spec.pairs if pair.name) == pairs[2:]
    assert world.model.nu == 4 * 8 * 2   # 4 boxes x 8 corners x 2 axes
    for _ in range(5):
        world.step()


def test_the_walk_stance_squeezes_the_feet_as_on_the_real_server(monkeypatch) -> None:
    run = creep._replay(monkeypatch, CANDIDATE)
    start = run.meta["skill_cycle"]
    for cycle in (20, creep.STANCE, creep.TWIST):   # real 6.71, 4.97, 4.69 N; measured 6.63, 4.87, 4.60
        real, ours = (creep._sideways_n(messages[start + cycle]) for messages in (run.real_messages, run.our_messages))
        assert ours["lf"] == pytest.approx(real["lf"], abs=0.3)
        assert ours["rf"] == pytest.approx(real["rf"], abs=0.3)


def _stood_at_the_end(monkeypatch, physics_file: Path | None) -> tuple[bool, bool]:
    if physics_file is None:
        monkeypatch.delenv(PHYSICS_FILE_ENV, raising=False)
    else:
        monkeypatch.setenv(PHYSICS_FILE_ENV, str(physics_file))
    run = traces.replay.__wrapped__(BACK_STAND_UP_35E251E)
    last_second = range(max(run.real) - 49, max(run.real) + 1)   # the transfer's 1 s hold at 50 cycles a second
    return traces._stood(run.real, last_second), traces._stood(run.ours, last_second)


def test_the_real_back_stand_up_of_the_shipped_motion_stands_the_slipping_robot_up(monkeypatch) -> None:
    assert _stood_at_the_end(monkeypatch, CANDIDATE) == (True, True)


@pytest.mark.xfail(strict=True, reason="measured disagreement (2026-11-29): the real server's lying-on-back stand-up "
                   "of the motions at 35e251e, replayed open loop, tips the default world's robot forward 4.8 s into "
                   "the skill (torso x -7.78 m where the real one stands at -8.00) and it falls; with the feet "
                   "slipping as ODE's it stands as the real one (the test above)")
def test_the_real_back_stand_up_of_the_shipped_motion_stands_the_default_robot_up(monkeypatch) -> None:
    assert _stood_at_the_end(monkeypatch, None) == (True, True)
