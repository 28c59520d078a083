"""agent.localization: self-localization (triangulation, the seed's FIFO filter, the default EKF).

Every localizer has the same surface: ``predict(yaw_delta_rad, odometry_m)`` each cycle, ``correct(frame)``
each vision frame, ``pose`` (team frame or None), ``localized``, ``reset()``; :func:`make_localizer` builds
one by name.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Protocol

from agent.errors import ConfigError
from agent.localization.ekf import EkfLocalizer
from agent.localization.fifo_filter import FifoFilter
from agent.localization.seed import SeedLocalizer
from agent.localization.triangulation import triangulate
from agent.world.field import Segment
from agent.world.frames import Pose2D
from agent.world.vision import VisionFrame
from agent.protocol.constants import CYCLE_S


class Localizer(Protocol):
    """What the world model needs from a self-localization method."""

    name: str
    last_triangulation: Pose2D | None

    def reset(self) -> None: ...

    def predict(self, yaw_delta_rad: float, odometry_m: tuple[float, float] | None = None,
                dt_s: float = CYCLE_S) -> None: ...

    def correct(self, frame: VisionFrame) -> None: ...

    @property
    def pose(self) -> Pose2D | None: ...

    @property
    def localized(self) -> bool: ...


#: Name -> constructor; ``ekf`` is the default because it measures better (benchmarks/bench_localization.py).
LOCALIZERS = {"ekf": EkfLocalizer, "seed": SeedLocalizer}
DEFAULT_LOCALIZER = "ekf"


def make_localizer(name: str, landmarks: Mapping[str, tuple[float, float]], lines: Sequence[Segment] = (),
                   **options: float) -> Localizer:
    """A localizer by name.

    Raises:
        ConfigError: unknown name (the message lists the known ones).
    """
    try:
        factory = LOCALIZERS[name]
    except KeyError:
        raise ConfigError(f"unknown localizer {name!r}; known: {', '.join(LOCALIZERS)}", field="localization") from None
    return factory(landmarks, lines, **options)  # type: ignore[return-value]


__all__ = ["DEFAULT_LOCALIZER", "EkfLocalizer", "FifoFilter", "LOCALIZERS", "Localizer", "SeedLocalizer",
           "make_localizer", "triangulate"]
