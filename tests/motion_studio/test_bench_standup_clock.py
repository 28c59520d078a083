"""The stand-up benchmark's clock on our simulator: a robot pushed over while walking that stands up and walks on is
clocked when it stood up, not after its walk's flight cycles (both feet off the ground for a cycle)."""

from __future__ import annotations

import random

import pytest

from motion_studio.skill_bench import standup

# rng seed 5 with simulator seed 1001: a type-0 robot pushed while walking falls onto its front, plays the front
# stand-up once and is upright on its feet 2.04 s after the fall; the walk it then resumes has flight cycles.
PUSH_RNG_SEED, SIM_SEED = 5, 1001


def test_a_robot_that_stands_up_and_walks_on_is_clocked_at_its_stand_up():
    trial = standup.pushed_trial(True, random.Random(PUSH_RNG_SEED), SIM_SEED)
    assert trial.fell and trial.sides == ["front"]
    assert trial.time_s is not None and trial.time_s <= 2.2
    assert trial.success


def test_every_cycle_with_both_feet_off_restarting_the_hold_clocks_the_walk_instead(monkeypatch: pytest.MonkeyPatch):
    """The same trial without the gap: the walk's flight cycles restart the 1 s hold (what the clock did before)."""
    monkeypatch.setattr(standup, "FEET_OFF_GAP_CYCLES", 0)
    trial = standup.pushed_trial(True, random.Random(PUSH_RNG_SEED), SIM_SEED)
    assert trial.sides == ["front"]
    assert trial.time_s is not None and trial.time_s > 3.0
