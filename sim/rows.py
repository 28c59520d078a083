"""Flat row gathers of MuJoCo's pose arrays (shared by the world and the joint drift)."""

from __future__ import annotations

import numpy as np


def row_index(rows: np.ndarray, width: int) -> np.ndarray:
    """Flat indices of whole rows of an (n, ``width``) array, for gathering them from its flat view.

    Why: numpy's row gather of a 2-D array (``xmat[bodies]``) costs ~1.8 us for a few rows, a 1-D gather by
    these indices and a reshape ~0.3 us, for the same values in the same layout; the world gathers pose rows
    of MuJoCo's arrays several times a cycle.
    """
    return (np.asarray(rows, dtype=np.intp)[:, None] * width + np.arange(width)).ravel()


__all__ = ["row_index"]
