"""A progress bar for tuning runs (tqdm, on stderr), fed by the run loop's events: it lives at the CLI edge.

Also the per-iteration line a tuner prints, so every tuner reports alike.
"""

from __future__ import annotations

from collections.abc import Callable
from types import TracebackType

from tqdm import tqdm

from motion_studio.tuning.runner import Event


class ProgressBar:
    """``with ProgressBar(total, "kick") as bar: run(..., on_event=bar)``: one tick per evaluated candidate,
    the best loss in the bar's postfix, and ``line(event)`` (if given) printed above the bar per iteration."""

    def __init__(self, total: int | None, description: str, line: Callable[[Event], str | None] | None = None,
                 disable: bool = False) -> None:
        self._bar = tqdm(total=total, desc=description, unit="cand", dynamic_ncols=True, disable=disable, leave=True)
        self._line = line

    def __call__(self, event: Event) -> None:
        if event.kind == "evaluation":
            self._bar.n = event.evaluations
            self._bar.set_postfix(best=f"{event.best_loss:.4g}", refresh=False)
            self._bar.refresh()
        elif self._line is not None:
            text = self._line(event)
            if text:
                self._bar.write(text)

    def __enter__(self) -> ProgressBar:
        return self

    def __exit__(self, kind: type[BaseException] | None, error: BaseException | None,
                 trace: TracebackType | None) -> None:
        self._bar.close()


__all__ = ["ProgressBar"]
