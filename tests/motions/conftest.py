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
