"""ASTM E1049-85 (2017) rainflow worked example (section 5.4.4, Fig. 6), exact.

Sequence -2, 1, -3, 5, -1, 3, -4, 4, -2 (load units). The standard's table of
counts: range 3: 0.5, 4: 1.5, 6: 0.5, 8: 1.0, 9: 0.5. Exact equality: every
value is a small integer, so no rounding can occur.
"""

from __future__ import annotations

from collections import Counter

import numpy as np

from drillfatigue.fatigue.rainflow import find_cycles, find_cycles_indexed

Y = np.array([-2.0, 1.0, -3.0, 5.0, -1.0, 3.0, -4.0, 4.0, -2.0])
EXPECTED = {3.0: 0.5, 4.0: 1.5, 6.0: 0.5, 8.0: 1.0, 9.0: 0.5}


def _table(ranges: np.ndarray, counts: np.ndarray) -> dict[float, float]:
    c: Counter[float] = Counter()
    for r, n in zip(ranges, counts, strict=True):
        c[float(r)] += float(n)
    return dict(c)


def test_fatpack_route_reproduces_astm_table() -> None:
    cyc = find_cycles(Y, residue="half")
    assert _table(cyc.ranges, cyc.count) == EXPECTED


def test_indexed_kernel_reproduces_astm_table_and_indices() -> None:
    i0, i1, cnt = find_cycles_indexed(Y, residue="half")
    assert _table(np.abs(Y[i1] - Y[i0]), cnt) == EXPECTED
    # the only full cycle is -1 -> 3 (samples 4 and 5)
    full = [(int(a), int(b)) for a, b, n in zip(i0, i1, cnt, strict=True) if n == 1.0]
    assert full == [(4, 5)]
