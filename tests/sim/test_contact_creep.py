"""Feet that creep under a steady sideways force, as SimSpark's (mu = inf with force-dependent slip) do: the stance
before the 13 cm walk's first step (tests/sim/fixtures/real_0.7.3_skill_walk_fast_13cm_candidate), replayed open
loop with the default contact and with sim/physics_candidates/contact_fit_2026-11-28.toml (not the default).

Measured 2026-11-28: standing in the walk's stance, the real feet push 5 N sideways against each other (FRP);
ours 33 N with Coulomb mu = 2 and the default impedance, 3 N with the fitted soft friction. The first step's hip
yaw-pitch (rlj1, commanded -5.77 deg in one cycle against the twisting stance foot) moves -4.44 deg on the real
server, -2.91 with the default contact and -3.89 with the fitted one.
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from sim.physics_params import PHYSICS_FILE_ENV
from tests.sim import test_real_skill_traces as traces

CANDIDATE = Path(__file__).parents[2] / "sim" / "physics_candidates" / "contact_fit_2026-11-28.toml"
#: Cycles after the skill phase's start: standing in the stance (0.50 s), and the first step's hip twist (0.56 s).
STANCE, TWIST = 25, 28
_FRP = re.compile(rb"\(FRP \(n (lf|rf)\) \(c [-0-9.e]+ [-0-9.e]+ [-0-9.e]+\) \(f ([-0-9.e]+) [-0-9.e]+ [-0-9.e]+\)\)")


def _replay(monkeypatch, physics_file: Path | None) -> traces.Replay:
    if physics_file is None:
        monkeypatch.delenv(PHYSICS_FILE_ENV, raising=False)
    else:
        monkeypatch.setenv(PHYSICS_FILE_ENV, str(physics_file))
    return traces.replay.__wrapped__(traces.WALK_13CM)


def _sideways_n(message: bytes) -> dict[str, float]:
    """Each foot's sideways force (FRP f x) [N]."""
    return {m.group(1).decode(): float(m.group(2)) for m in _FRP.finditer(message)}


def _twist_deg(run: traces.Replay, joints: dict[int, dict[str, float]]) -> float:
    start = run.meta["skill_cycle"]
    return joints[start + TWIST + 1]["rlj1"] - joints[start + TWIST]["rlj1"]


@pytest.mark.parametrize(("physics_file", "squeeze_n", "twist_deg"), [
    (None, (25.0, 40.0), (-3.3, -2.5)),          # measured 33.5 N, -2.91 deg
    (CANDIDATE, (0.0, 6.0), (-4.6, -3.6)),       # measured 3.0 N, -3.89 deg
])
def test_standing_feet_squeeze_and_the_first_step_s_hip_twist(monkeypatch, physics_file, squeeze_n, twist_deg):
    run = _replay(monkeypatch, physics_file)
    start = run.meta["skill_cycle"]
    real, ours = _sideways_n(run.real_messages[start + STANCE]), _sideways_n(run.our_messages[start + STANCE])
    assert 3.5 < real["lf"] < 5.5 and abs(real["lf"] + real["rf"]) < 0.5   # the real feet: 4.5 N, opposite
    assert squeeze_n[0] <= abs(ours["lf"]) <= squeeze_n[1]
    assert _twist_deg(run, run.real_joints) == pytest.approx(-4.44, abs=0.05)
    assert twist_deg[0] <= _twist_deg(run, run.our_joints) <= twist_deg[1]
