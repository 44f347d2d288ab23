"""Numba kernels of the surrogate package (numpy/numba only, STYLE.md habit 1)."""

from __future__ import annotations

import numpy as np
from numba import njit

__all__ = ["outside_ranges"]


@njit(cache=True)
def outside_ranges(x: np.ndarray, lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
    """Rows of ``x`` (n, d) with any value below ``lo`` or above ``hi`` (per column).

    One pass, stopping at a row's first offending column (NaN is never
    outside). Needs none of the four (n, d) temporaries of the numpy
    expression, so the range check costs little of a batched prediction.
    """
    n, d = x.shape
    out = np.zeros(n, dtype=np.bool_)
    for i in range(n):
        for j in range(d):
            v = x[i, j]
            if v < lo[j] or v > hi[j]:
                out[i] = True
                break
    return out
