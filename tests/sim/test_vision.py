"""The vision writer: See bytes straight from the arrays equal the typed frames written by format_sense."""

from __future__ import annotations

import numpy as np
import pytest

from agent.protocol.perceptors import Sense
from agent.protocol.sense import format_sense
from sim.vision import Observer, PlayerParts, SeeWriter, VisionConfig, observe, see
from sim.world import VISIBLE_PARTS


def _scene(seed: int, observers: int, players: int) -> tuple[list[Observer], list[PlayerParts], np.ndarray]:
    rng = np.random.default_rng(seed)
    teams = [PlayerParts("Left" if i % 2 else "Right", i // 2 + 1,
                         rng.uniform((-15, -10, 0.0), (15, 10, 0.6), (5, 3)), VISIBLE_PARTS) for i in range(players)]
    cams = []
    for k in range(observers):
        yaw, pitch = rng.uniform(-np.pi, np.pi), rng.uniform(-0.5, 0.5)
        cz, sz, cp, sp = np.cos(yaw), np.sin(yaw), np.cos(pitch), np.sin(pitch)
        rotation = np.array([[cz, -sz, 0], [sz, cz, 0], [0, 0, 1.0]]) @ np.array([[1, 0, 0], [0, cp, -sp], [0, sp, cp]])
        # An observer stands at one of the players' heads, so it sees its own parts as the server does.
        position = teams[k].parts_m[0] if k < players else rng.uniform((-15, -10, 0.4), (15, 10, 0.6))
        cams.append(Observer(position, rotation, rng.uniform(-0.005, 0.005, 3), "Left", k + 1))
    return cams, teams, rng.uniform((-15, -10, 0.042), (15, 10, 0.042))


@pytest.mark.parametrize("seed, observers, players", [(0, 1, 0), (1, 1, 1), (2, 7, 22), (3, 3, 5), (4, 0, 3)])
@pytest.mark.parametrize("config", [VisionConfig(), VisionConfig(noise=False, calibration=False, lines=False)])
def test_written_see_equals_the_typed_frames(seed: int, observers: int, players: int, config: VisionConfig) -> None:
    cams, teams, ball = _scene(seed, observers, players)
    typed = see(cams, ball, teams, np.random.default_rng(seed), config)
    if not cams:
        assert typed == []
        return
    sighting = observe(np.stack([c.position_m for c in cams]), np.stack([c.rotation for c in cams]),
                       np.stack([c.calibration_m for c in cams]), ball,
                       np.vstack([t.parts_m for t in teams]) if teams else np.zeros((0, 3)),
                       np.random.default_rng(seed), config)
    writer = SeeWriter(VISIBLE_PARTS)
    written = writer.frames(sighting, tuple((t.team, t.unum) for t in teams))
    assert len(written) == len(typed)
    for frame, data in zip(typed, written):
        expected = format_sense(Sense(None, None, None, None, {}, see=frame))
        assert data == expected
    # The item table is cached per set of players: a second cycle gives the same bytes.
    assert writer.frames(sighting, tuple((t.team, t.unum) for t in teams)) == written


def test_the_field_of_view_prefilter_changes_nothing(monkeypatch: pytest.MonkeyPatch) -> None:
    import sim.vision
    for seed in range(6):
        cams, teams, ball = _scene(seed, 7, 22)
        # Points right at the edge of the view cone and behind the camera are the prefilter's hard cases.
        edge = [c.position_m + c.rotation @ np.array([np.tan(np.radians(60.0)) * 3.0, 3.0, z]) for c in cams[:3]
                for z in (-5.2, 0.0, 5.2)]
        teams[0] = type(teams[0])(teams[0].team, teams[0].unum, np.array(edge[:5]), teams[0].part_names)
        arrays = (np.stack([c.position_m for c in cams]), np.stack([c.rotation for c in cams]),
                  np.stack([c.calibration_m for c in cams]), ball, np.vstack([t.parts_m for t in teams]))
        filtered = observe(*arrays, np.random.default_rng(seed))
        monkeypatch.setattr(sim.vision, "_PREFILTER_MIN_POINTS", 10 ** 9)
        plain = observe(*arrays, np.random.default_rng(seed))
        monkeypatch.undo()
        for field in ("seen_k", "seen_p", "values", "line_k", "line_values", "object_rows", "line_rows"):
            assert np.array_equal(getattr(filtered, field), getattr(plain, field)), field


@pytest.mark.parametrize("spell_min_values", [0, 10 ** 9])
def test_spelled_and_printf_numbers_write_the_same_bytes(monkeypatch: pytest.MonkeyPatch, spell_min_values: int) -> None:
    # Few numbers go to printf templates, many are spelled by look-up (sim.fixed2): force each path on scenes
    # that would take the other.
    import sim.vision
    for seed, observers, players in [(0, 1, 0), (1, 1, 1), (2, 7, 22)]:
        cams, teams, ball = _scene(seed, observers, players)
        typed = see(cams, ball, teams, np.random.default_rng(seed))
        sighting = observe(np.stack([c.position_m for c in cams]), np.stack([c.rotation for c in cams]),
                           np.stack([c.calibration_m for c in cams]), ball,
                           np.vstack([t.parts_m for t in teams]) if teams else np.zeros((0, 3)),
                           np.random.default_rng(seed))
        monkeypatch.setattr(sim.vision, "SPELL_MIN_VALUES", spell_min_values)
        written = SeeWriter(VISIBLE_PARTS).frames(sighting, tuple((t.team, t.unum) for t in teams))
        monkeypatch.undo()
        assert written == [format_sense(Sense(None, None, None, None, {}, see=frame)) for frame in typed]


def test_line_clipping_equals_the_plain_plane_by_plane_clip() -> None:
    """`_clip_to_pyramid`'s masked reductions give the bounds of the plain formulation (every crossing, entering
    planes raise the start, leaving planes lower the end), bit for bit, parallel segments included."""
    from sim.vision import _PLANES_T, _clip_to_pyramid
    rng = np.random.default_rng(0)
    segments = rng.uniform(-10.0, 10.0, (3, 200, 2, 3))
    segments[:, :40, 1, 0] = segments[:, :40, 0, 0]     # parallel to the x planes' normals' x part
    segments[:, 40:60, 1] = segments[:, 40:60, 0]       # zero length
    segments[:, 60:80, :, 1] = 0.0                      # in the camera's own plane
    start, direction = segments[..., 0, :], segments[..., 1, :] - segments[..., 0, :]
    at_start, along = start @ _PLANES_T, direction @ _PLANES_T
    with np.errstate(divide="ignore", invalid="ignore"):
        t_cross = -at_start / along
    low = np.maximum(0.0, np.where(along > 0, t_cross, -np.inf).max(axis=2))
    high = np.minimum(1.0, np.where(along < 0, t_cross, np.inf).min(axis=2))
    visible = (low < high) & ~((along == 0) & (at_start < 0)).any(axis=2)
    clipped, got_visible = _clip_to_pyramid(segments)
    assert np.array_equal(got_visible, visible) and 0 < visible.sum() < visible.size
    assert np.array_equal(clipped[visible, 0], (start + low[..., None] * direction)[visible])
    assert np.array_equal(clipped[visible, 1], (start + high[..., None] * direction)[visible])
