"""Many sense-message floats spelled at once: printf ``%.2f`` by table look-up instead of formatting each.

Why: with 22 robots the server writes about 4,000 floats per cycle, and formatting them one by one was its
largest Python cost after the agents' parsing. agent.protocol.numbers.fixed2_table holds the spelling of
every hundredth up to 400.00; this module finds each value's entry with a few numpy operations over all the
values of a cycle, and the writers insert the spellings with ``%s`` (five times cheaper than ``%.2f``).

Exactness: printf rounds the exact binary value x to the nearest hundredth, ties to even. y = x * 100 is
off the exact product by at most half an ulp of y, so ``rint(y)`` is that hundredth unless y lies within an
ulp of a half-integer (a tie, or nearly). Those values, values beyond the table and values that are not
finite are formatted by printf itself; tests/sim/test_fixed2.py checks every path against it.
"""

from __future__ import annotations

from functools import cache

import numpy as np

from agent.protocol.numbers import FIXED2, FIXED2_TABLE_HUNDREDTHS, fixed2_table

#: Below this many values in one call printf is cheaper than the look-up (its numpy calls cost a fixed ~8 µs;
#: measured crossover ~130 values): writers then pass the floats to ``%.2f`` templates (the same bytes).
SPELL_MIN_VALUES = 128

_SPELL = FIXED2.encode("ascii")
# Two ulps of y bound (for normal y: ulp(y) <= |y| 2^-52); subnormal y are far from any half-integer.
_TWO_ULPS = 4.5e-16
# The scalar operands as 0-d arrays: numpy converts a Python number operand on every call, which costs about as
# much as the operation itself on a cycle's few hundred values (the same values, so the same results).
_HUNDRED = np.array(100.0)
_HALF = np.array(0.5)
_TWO_ULPS_ARRAY = np.array(_TWO_ULPS)
_TABLE_END = np.array(float(FIXED2_TABLE_HUNDREDTHS))
_NEGATIVE_OFFSET = np.array(FIXED2_TABLE_HUNDREDTHS, dtype=np.intp)


@cache
def _table() -> np.ndarray:
    table = np.empty(2 * FIXED2_TABLE_HUNDREDTHS, dtype=object)
    table[:] = fixed2_table()
    return table


def spell_fixed2(values: np.ndarray) -> np.ndarray:
    """``b"%.2f" % v`` of every value of ``values``, as an object array of the same shape.

    Args:
        values: float64 array of any shape.
    """
    flat = values.ravel()
    scaled = flat * _HUNDRED
    rounded = np.rint(scaled)
    magnitude = np.abs(rounded)
    # Not provably on one side of a half-hundredth, beyond the table, or not finite.
    with np.errstate(invalid="ignore"):   # inf - inf: such values are unsure anyway
        unsure = (_HALF - np.abs(scaled - rounded) <= _TWO_ULPS_ARRAY * np.abs(scaled)) | ~(magnitude < _TABLE_END)
    odd = unsure.nonzero()[0]   # (np.flatnonzero of a 1-d array, without its Python wrapper)
    if odd.size:
        magnitude[odd] = 0.0
    index = magnitude.astype(np.intp)
    index += np.signbit(flat) * _NEGATIVE_OFFSET
    spelled = _table()[index]
    for i in odd.tolist():
        spelled[i] = _SPELL % float(flat[i])
    return spelled.reshape(values.shape)
