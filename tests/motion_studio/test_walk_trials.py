"""Walk transition trials (motion_studio.walk_trials): scripts look like the skills' requests, keyframe noise
touches only the walk's leg targets, and a scripted restart during a walk's stop plays on the simulator."""

from __future__ import annotations

import math
import random

import pytest

from agent.motion import default_library
from motion_studio.walk_trials import STARTS, Script, Segment, perturbed, run_script, transition_script


@pytest.fixture(scope="module")
def library():
    return default_library(0)


def test_transition_scripts_cover_every_start_and_walk_the_motion(library):
    rng = random.Random(0)
    scripts = [transition_script(rng, library, "walk_forward") for _ in range(40)]
    assert {s.label.split(":")[1] for s in scripts} == set(STARTS)
    for script in scripts:
        walked = sum(s.duration_s for s in script.segments if s.motion == "walk_forward")
        assert walked >= 1.0
        assert all(-1.0 <= s.lean <= 1.0 for s in script.segments)
        assert len(script.pushes) == 1 and math.hypot(script.pushes[0].forward_m_s, script.pushes[0].left_m_s) <= 0.04


@pytest.mark.parametrize("walk", ["walk_forward", "walk_fast"])
def test_the_forward_walks_transition_scripts_change_the_lean_and_the_others_do_not(library, walk):
    """Both forward walks steer with the walk lean in a match, so their trials change it as steering does."""
    rng = random.Random(1)
    leaning = [any(s.lean != 0.0 for s in transition_script(rng, library, walk).segments) for _ in range(20)]
    assert sum(leaning) >= 10
    sideways = [s for _ in range(10) for s in transition_script(rng, library, "walk_left").segments]
    assert all(s.lean == 0.0 for s in sideways)


def test_perturbed_walk_moves_only_leg_targets_of_the_walking_phases(library):
    walk = library.get("walk_forward")
    noisy = perturbed(walk, random.Random(1), 0.5)
    changed = set()
    for a, b in zip(walk.keyframes, noisy.keyframes):
        for wire, target in a.targets.items():
            if target.angle_rad != b.targets[wire].angle_rad:
                changed.add((a.name.split("_")[0], wire[1:3]))
            assert b.targets[wire].computed == target.computed  # the walk lean still steers
    assert {kind for kind, _ in changed} == {"start", "cycle", "stop"}
    assert {joint for _, joint in changed} == {"lj"}


def test_a_walk_restarted_during_its_stop_keeps_walking(library):
    script = Script((Segment("stand", 0.5), Segment("walk_forward", 1.5), Segment(None, 0.3),
                     Segment("walk_forward", 1.5)))
    result = run_script(library, script)
    assert not result.fell
    assert result.distance_m > 1.0
