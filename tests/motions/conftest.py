"""Shared helpers of the motions tests: fixture paths and a way to forget a motion's file layout."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import pytest

from motions import Motion

FIXTURES = Path(__file__).parent / "fixtures"


def without_sources(motion: Motion) -> Motion:
    """The same motion with no memory of its file, so writers must produce the canonical layout."""
    frames = [dataclasses.replace(k, source=None) for k in motion.keyframes]
    return dataclasses.replace(motion, keyframes=frames, source=None)


@pytest.fixture
def fixture_text():
    """Read a fixture file as text with its line endings untouched."""

    def read(name: str) -> str:
        return (FIXTURES / name).read_bytes().decode("utf-8")

    return read


def assert_same_motion(actual: Motion, expected: Motion, angle_tolerance_rad: float = 1e-12) -> None:
    """Equal motions, angles within ``angle_tolerance_rad``: degree text in XML files cannot hit every
    radian float exactly (radians(d) skips some floats), so XML round trips agree to about one ulp."""
    assert [k.name for k in actual.keyframes] == [k.name for k in expected.keyframes]
    for got, want in zip(actual.keyframes, expected.keyframes):
        assert list(got.targets) == list(want.targets), want.name
        for wire, target in want.targets.items():
            other = got.targets[wire]
            assert other.computed == target.computed
            if target.angle_rad is None:
                assert other.angle_rad is None
            else:
                assert other.angle_rad == pytest.approx(target.angle_rad, rel=0, abs=angle_tolerance_rad)
    flat = [dataclasses.replace(k, targets={}) for k in actual.keyframes]
    want_flat = [dataclasses.replace(k, targets={}) for k in expected.keyframes]
    assert dataclasses.replace(actual, keyframes=flat) == dataclasses.replace(expected, keyframes=want_flat)


def assert_shipped_as_generated(shipped: Motion, fresh: Motion, angle_tolerance_rad: float = 1e-9) -> None:
    """A shipped generated file plays as the generator's fresh output: the same phases, durations, angles and
    constants (its header, with the day it was written, may differ)."""
    assert [k.name for k in shipped.keyframes] == [k.name for k in fresh.keyframes], fresh.name
    for got, want in zip(shipped.keyframes, fresh.keyframes):
        assert got.duration_s == pytest.approx(want.duration_s)
        for wire, target in want.targets.items():
            assert got.angle_rad(wire) == pytest.approx(target.angle_rad, abs=angle_tolerance_rad), \
                (fresh.name, got.name, wire)
    assert shipped.constants == pytest.approx(fresh.constants)
