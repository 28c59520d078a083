"""Body parts that slip as SimSpark's do (``PhysicsParams.body_slip_m_s_per_n``, sim/physics_candidates/body_slip.toml):
the torso, arm, thigh and shank boxes meet the field through the feet's implicit corner dampers (force-dependent
slip: a sliding speed in proportion to the push, whatever the weight on the part) instead of Coulomb friction.

Measured 2026-11-29 (the numbers the assertions keep): the back stand-up after scripted falls onto the back
(StandUpBench, seed 0) reaches its knees_in phase with the torso's forward axis at z -0.20 / -0.21 on the real
server in every start; with the default Coulomb friction (0.95 on those parts) ours at -0.41, -0.59 and -0.27 in
starts 0, 1 and 3 (the second then falls forward), with this candidate at -0.31, -0.27 and -0.29: the body slip
makes ours converge as the real robot does.
"""

from __future__ import annotations

from pathlib import Path

from agent.motion import default_library
from motion_studio.realserver.rollout_standup import SimWorld, StandUpBench, real_starts
from sim.physics_params import PHYSICS_FILE_ENV, PhysicsParams, default_physics_params, load_physics_file
from sim.world import World

CANDIDATE = Path(__file__).parents[2] / "sim" / "physics_candidates" / "body_slip.toml"
SLIP_M_S_PER_N = 0.02
#: The type 0 robot's boxes other than the feet: torso, upper and lower arms, thighs, shanks.
BOXES = ["llowerarm", "lshank", "lthigh", "lupperarm", "rlowerarm", "rshank", "rthigh", "rupperarm", "torso"]


def _lean_at_knees_in(starts: tuple[int, ...]) -> list[float]:
    """z of the torso's forward axis when the back stand-up's knees_in phase starts, per scripted back fall."""
    bench = StandUpBench(lambda behavior: SimWorld(behavior), default_library(0), 0)
    try:
        lying = real_starts("back", max(starts) + 1, 0)
        leans = []
        for index in starts:
            outcome = bench.rollout({}, "standup_back", lying[index], use_skill=True, trace=True)
            leans.append(next(row["fwd_z"] for row in outcome.trace if row.get("phase", "").endswith(":knees_in")))
        return leans
    finally:
        bench.close()


def test_the_back_stand_up_reaches_its_knees_in_pose_alike_from_every_fall(monkeypatch) -> None:
    monkeypatch.setenv(PHYSICS_FILE_ENV, str(CANDIDATE))
    slipping = _lean_at_knees_in((0, 1, 3))
    assert max(slipping) - min(slipping) < 0.1
    assert all(-0.45 < lean < -0.1 for lean in slipping)   # leaning forward over its feet, as the real one
    monkeypatch.delenv(PHYSICS_FILE_ENV)
    coulomb = _lean_at_knees_in((0, 1, 3))
    assert max(coulomb) - min(coulomb) > 0.2


def test_the_boxes_meet_the_field_without_friction_and_the_candidate_file_switches_it_on() -> None:
    world = World(default_physics_params(body_slip_m_s_per_n=SLIP_M_S_PER_N))
    world.add_robot(0, 0)
    assert sorted(pair.name for pair in world.spec.pairs if pair.name) == [f"r0_slip_{box}" for box in BOXES]
    assert world.model.nu == len(BOXES) * 8 * 2   # 8 corners x 2 axes, the head and the feet keep their friction
    assert load_physics_file(CANDIDATE) == {"body_slip_m_s_per_n": SLIP_M_S_PER_N}
    assert PhysicsParams().body_slip_m_s_per_n is None   # not the default (its header says why)
