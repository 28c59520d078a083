"""Writing a finished matplotlib figure as a PNG: the one place that lays it out, makes the folder, saves and
frees it (a figure left open keeps its memory for the rest of a long tuning or benchmark run)."""

from __future__ import annotations

from pathlib import Path
from typing import Any


def write_png(figure: Any, path: Path, dpi: int = 100) -> Path:
    """Lay ``figure`` out tightly, write it to ``path`` (parent folders made) at ``dpi`` and close it; returns
    ``path``."""
    import matplotlib.pyplot as plt

    figure.tight_layout()
    path.parent.mkdir(parents=True, exist_ok=True)
    figure.savefig(path, dpi=dpi)
    plt.close(figure)
    return path


__all__ = ["write_png"]
