"""The seed agent's localization as one object: triangulation per frame, then the FIFO filter (Algorithm 1).

Kept as the reference the default must beat (``--localization seed`` selects it). Between vision frames
the belief does not move; the gyro is not used, as in the 2012 agent.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

from agent.localization.fifo_filter import FifoFilter
from agent.localization.triangulation import triangulate
from agent.world.field import Segment
from agent.world.frames import Pose2D
from agent.world.vision import VisionFrame
from agent.protocol.constants import CYCLE_S


class SeedLocalizer:
    """Triangulation + FIFO filter.

    Args:
        landmarks: landmark name -> team-frame (x, y) [m].
        lines: unused (the seed ignores field lines); accepted for a common constructor.
        **fifo_options: passed to :class:`FifoFilter` (``max_size``, ``agree_m``, ``pop_without_push_when_full``).
    """

    name = "seed"

    def __init__(self, landmarks: Mapping[str, tuple[float, float]], lines: Sequence[Segment] = (),
                 **fifo_options: float) -> None:
        self.landmarks = dict(landmarks)
        self.filter = FifoFilter(**fifo_options)  # type: ignore[arg-type]
        self.last_triangulation: Pose2D | None = None

    def reset(self) -> None:
        """Forget the pose."""
        self.filter.reset()

    def predict(self, yaw_delta_rad: float, odometry_m: tuple[float, float] | None = None,
                dt_s: float = CYCLE_S) -> None:
        """No motion model in the seed."""

    def correct(self, frame: VisionFrame) -> None:
        """Triangulate and feed the FIFO."""
        self.last_triangulation = triangulate(frame, self.landmarks)
        if self.last_triangulation is not None:
            self.filter.add(self.last_triangulation)

    @property
    def pose(self) -> Pose2D | None:
        """The FIFO mean."""
        return self.filter.mean

    @property
    def localized(self) -> bool:
        """Queue size >= 5 (2012 code)."""
        return self.filter.well_localized
