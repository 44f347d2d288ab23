"""ISO 12110-2:2013 Annex A cycle-counting example through fatpack.

The standard's example series of 28 points (also used by fatpack's own test
suite, Gunnstein/fatpack ``fatpack/test.py``) is classified into 11 load
classes of width 1 (ISO rounding: a boundary point goes up at a peak, down at a
valley); the standard lists the class reversals, the 8 closed cycles of the
first pass and the residue. Class values are integers, so the comparison is
exact.
"""

from __future__ import annotations

import numpy as np

from drillfatigue.fatigue.rainflow import _pass, _reversals, find_cycles

SERIES = np.array([4.2, 7.3, 2.0, 9.8, 9.6, 10.3, 5.2, 8.5, 3.0, 4.4, 2.2, 2.4, 2.2, 12.0,
                   5.5, 11.1, 1.0, 4.3, 3.5, 9.5, 6.0, 12.0, 3.9, 8.3, 1.2, 8.6, 3.9, 6.2])
REVERSALS = [4, 7, 2, 10, 5, 9, 3, 4, 2, 12, 5, 11, 1, 4, 3, 10, 6, 12, 4, 8, 1, 9, 4, 6]
CYCLES = [(5, 9), (3, 4), (10, 2), (5, 11), (4, 3), (10, 6), (4, 8), (1, 12)]
RESIDUE = [4, 7, 2, 12, 1, 9, 4, 6]


def test_class_reversals() -> None:
    np.testing.assert_array_equal(_reversals(SERIES, 11), REVERSALS)


def test_first_pass_cycles_and_residue() -> None:
    cyc, res = _pass(_reversals(SERIES, 11))
    assert [tuple(c) for c in cyc.tolist()] == CYCLES
    np.testing.assert_array_equal(res, RESIDUE)


def test_full_count_with_load_classes() -> None:
    cyc = find_cycles(SERIES, residue="half", load_classes=11)
    assert len(cyc) == len(CYCLES) + len(RESIDUE) - 1
    assert float(cyc.count.sum()) == len(CYCLES) + 0.5 * (len(RESIDUE) - 1)
