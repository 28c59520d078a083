"""sim.fixed2: the table look-up spells every float exactly as printf ``%.2f`` does."""

from __future__ import annotations

import numpy as np

from agent.protocol.numbers import FIXED2_TABLE_HUNDREDTHS, fixed2_table
from sim.fixed2 import spell_fixed2


def _printf(values: np.ndarray) -> list[bytes]:
    return [b"%.2f" % float(v) for v in values.ravel()]


def test_the_table_holds_every_hundredth() -> None:
    table = fixed2_table()
    count = FIXED2_TABLE_HUNDREDTHS
    assert len(table) == 2 * count
    for m in list(range(0, 2000)) + list(range(count - 2000, count)):
        assert table[m] == b"%d.%02d" % divmod(m, 100)
        assert table[count + m] == b"-%d.%02d" % divmod(m, 100)


def test_random_values_near_ties_and_edge_cases_match_printf() -> None:
    rng = np.random.default_rng(7)
    ties = np.arange(-90_000, 90_000) / 200.0          # every half-hundredth up to 450, as doubles
    cases = [
        rng.uniform(-450.0, 450.0, 200_000), rng.normal(0.0, 1.0, 100_000), rng.normal(0.0, 0.01, 100_000),
        np.arange(-45_000, 45_000) / 100.0, ties, np.nextafter(ties, np.inf), np.nextafter(ties, -np.inf),
        np.arange(-4000, 4000) * 0.125,
        np.array([0.0, -0.0, 1e-300, -1e-300, 5e-324, -5e-324, np.nan, -np.nan, np.inf, -np.inf, 1e300, -1e300,
                  399.995, -399.995, 399.994999, 400.0, -400.0, 0.005, -0.005, 0.125, 2.675, 1.005, -61.93]),
    ]
    for values in cases:
        assert spell_fixed2(values).tolist() == _printf(values)


def test_the_shape_is_kept() -> None:
    values = np.arange(24.0).reshape(2, 4, 3) / 7.0
    spelled = spell_fixed2(values)
    assert spelled.shape == (2, 4, 3) and spelled.ravel().tolist() == _printf(values)
