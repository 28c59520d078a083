"""Physics previews as background jobs of one tab: start, progress, cancel, result, curves for the plot.

The work runs where the ``Background`` puts it (a worker thread in the server, inline in tests); progress and
the result come back through callbacks on the request thread, so the tab's state is only touched there.
"""

from __future__ import annotations

import logging
import threading
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any, Protocol

import numpy as np

from motions import Motion

from motion_studio.editor.errors import EditorError
from motion_studio.editor.physics_preview import PreviewCancelled, PreviewResult, run_physics_preview

logger = logging.getLogger(__name__)


class Background(Protocol):
    """Runs slow work off the request thread; calls back on it (the server's event loop)."""

    def submit(self, work: Callable[[Callable[[float], None]], Any], on_progress: Callable[[float], None],
               on_done: Callable[[Any, BaseException | None], None]) -> None: ...


class InlineBackground:
    """Runs work at once on the calling thread (tests, scripts)."""

    def submit(self, work: Callable[[Callable[[float], None]], Any], on_progress: Callable[[float], None],
               on_done: Callable[[Any, BaseException | None], None]) -> None:
        try:
            result = work(on_progress)
        except Exception as error:  # handed to on_done, which reports it
            on_done(None, error)
            return
        on_done(result, None)


@dataclass
class PreviewRun:
    """One run: status none/running/done/failed/cancelled, progress (0..1), what it produced, and the
    motion version it played (to tell a stale result)."""

    status: str = "none"
    fraction: float = 0.0
    result: PreviewResult | None = None
    version: int | None = None
    error: str | None = None
    cancel: threading.Event = field(default_factory=threading.Event)


class TabPreview:
    """The physics preview of one tab.

    Args:
        background: where runs execute. robot_type: 0-4.
        on_progress: called with the fraction done. on_finished: called when a run ends (any status).
    """

    def __init__(self, background: Background, robot_type: int, on_progress: Callable[[float], None],
                 on_finished: Callable[[], None]) -> None:
        self.background = background
        self.robot_type = robot_type
        self.on_progress = on_progress
        self.on_finished = on_finished
        self.run = PreviewRun()

    @property
    def result(self) -> PreviewResult | None:
        return self.run.result

    def start(self, motion: Motion, version: int) -> None:
        """Play ``motion`` (a copy the caller will not change) in the background.

        Raises:
            EditorError: a run is already going.
        """
        if self.run.status == "running":
            raise EditorError("a physics preview is already running", field="preview")
        run = PreviewRun(status="running", version=version)
        self.run = run
        robot_type = self.robot_type

        def work(report: Callable[[float], None]) -> PreviewResult:
            return run_physics_preview(motion, robot_type, progress=report, cancel=run.cancel)

        def progress(fraction: float) -> None:
            if self.run is run:
                run.fraction = fraction
                self.on_progress(fraction)

        def done(result: PreviewResult | None, error: BaseException | None) -> None:
            if self.run is not run:
                return  # superseded (another file was opened)
            if isinstance(error, PreviewCancelled):
                run.status = "cancelled"
            elif error is not None:
                logger.error("physics preview failed: %r", error, exc_info=error)
                run.status, run.error = "failed", f"{type(error).__name__}: {error}"
            else:
                run.status, run.result, run.fraction = "done", result, 1.0
            self.on_finished()

        self.background.submit(work, progress, done)

    def cancel(self) -> None:
        self.run.cancel.set()

    def reset(self) -> None:
        """Forget the run (a new file): a running one is cancelled and its result dropped."""
        self.run.cancel.set()
        self.run = PreviewRun()

    def state(self, current_version: int | None) -> dict[str, Any]:
        """Status for the panel; ``stale`` when the motion changed since the run."""
        run = self.run
        info: dict[str, Any] = {"status": run.status, "fraction": round(run.fraction, 3), "error": run.error}
        if run.result is not None:
            info["summary"] = run.result.summary()
            info["stale"] = current_version is None or run.version != current_version
        return info

    def series(self) -> dict[str, Any] | None:
        """Curves for the plot (motion time >= 0): time, torso height, CoM x/y/z (display frame), up-axis z."""
        result = self.run.result
        if result is None:
            return None
        shown = result.times_s >= 0.0
        com = result.com_m[shown]
        return {"t_s": _rounded(result.times_s[shown]), "torso_height_m": _rounded(result.torso_height_m[shown]),
                "com_x_m": _rounded(com[:, 0]), "com_y_m": _rounded(com[:, 1]), "com_z_m": _rounded(com[:, 2]),
                "up_z": _rounded(result.up_z[shown]), "fall_time_s": result.fall_time_s,
                "motion_duration_s": result.motion_duration_s}


def _rounded(values: np.ndarray) -> list[float]:
    return [round(float(v), 5) for v in values]
