"""The tuners' CMA-ES and parameter box: it finds a minimum inside [0, 1]^n, resumes bit for bit from a JSON
checkpoint, and the box maps back to parameters with their steps and bounds."""

import json

import numpy as np
import pytest

from motion_studio.cmaes import CMAES, Dimension


def _loss(x: np.ndarray) -> float:
    return float(np.sum((x - np.array([0.2, 0.7, 0.45])) ** 2))


def test_cmaes_finds_the_minimum_of_a_shifted_bowl():
    es = CMAES.create(np.full(3, 0.5), sigma0=0.3, seed=1)
    for _ in range(60):
        candidates = es.ask()
        assert all(np.all((c >= 0.0) & (c <= 1.0)) for c in candidates)  # always inside the box
        es.tell([_loss(c) for c in candidates])
    assert np.allclose(es.mean, [0.2, 0.7, 0.45], atol=0.02)


def test_a_search_resumed_from_its_json_checkpoint_continues_identically():
    first = CMAES.create(np.full(3, 0.5), seed=3)
    for _ in range(3):
        first.tell([_loss(c) for c in first.ask()])
    resumed = CMAES.from_state(json.loads(json.dumps(first.state())))
    a, b = first.ask(), resumed.ask()
    assert all(np.array_equal(x, y) for x, y in zip(a, b))


def test_dimensions_round_trip_and_respect_steps_and_bounds():
    duration = Dimension("shift_ms", 300, 700, step=20)
    assert duration.from_unit(0.37) == 440 and isinstance(duration.from_unit(0.37), int)
    count = Dimension("ramp_steps", 1, 4, step=1)
    assert [count.from_unit(u) for u in (0.0, 0.5, 1.0)] == [1, 2, 4]  # 2.5 rounds to even
    height = Dimension("torso_height_m", 0.30, 0.36)
    assert height.from_unit(height.to_unit(0.3333)) == pytest.approx(0.3333)
    assert height.from_unit(-1.0) == 0.30 and height.from_unit(2.0) == 0.36  # clipped into the bounds
    assert height.to_unit(0.5) == 1.0
