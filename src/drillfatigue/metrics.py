"""Accuracy measures shared by the noise-floor study and the surrogate evaluation.

Damage rates are compared on log10 scale (decades): two rates are within a
factor of 2 when their log10 values differ by less than ``log10 2``. The
replicate ceiling (:mod:`drillfatigue.sweep.replicates`) and each model's
score (:mod:`drillfatigue.surrogate.evaluation`) are broken down by decade of
damage rate with the same functions, so their tables line up.
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["FACTOR2_DECADES", "decade_label", "factor2_by_decade"]

#: log10(2): a factor of 2 on damage, in decades.
FACTOR2_DECADES = math.log10(2.0)


def decade_label(y: np.ndarray) -> np.ndarray:
    """Decade of each log10 damage rate per hour: ``'1e-05'`` for rates in
    [1e-5, 1e-4) per h (the lower edge; ``floor(y)``, so a rate censored at the
    floor has the floor's decade). Shape of ``y``, dtype object."""
    d = _decade(y)
    keys, inv = np.unique(d, return_inverse=True)
    names = np.array([_label(k) for k in keys], dtype=object)
    return names[inv.reshape(d.shape)]


def _label(k: int) -> str:
    """Name of decade k: '1e-05' for k = -5."""
    return f"1e{int(k):+03d}"


def _decade(y: np.ndarray) -> np.ndarray:
    """floor(y) as int64; 1e-9 decades of slack so that log10 of an exact power
    of ten rounded just below it (log10(1e-3) may give -2.9999999999999996)
    keeps its decade."""
    return np.floor(np.asarray(y, dtype=np.float64) + 1e-9).astype(np.int64)


def factor2_by_decade(y_ref: np.ndarray, err: np.ndarray) -> dict[str, dict[str, float | int]]:
    """Fraction of errors within a factor of 2, per decade of ``y_ref``.

    Parameters
    ----------
    y_ref : ndarray, shape (n,)
        log10 damage rate per hour that sets each row's decade.
    err : ndarray, shape (n,)
        Error of each row, decades (|err| < log10 2 counts as within a factor 2).

    Returns
    -------
    dict
        ``{decade_label: {"n": rows, "factor2_fraction": fraction}}``, decades
        in ascending order; empty for no rows.
    """
    y_ref = np.asarray(y_ref, dtype=np.float64)
    err = np.asarray(err, dtype=np.float64)
    if y_ref.shape != err.shape:
        raise ValueError(f"y_ref {y_ref.shape} and err {err.shape} differ in shape")
    if y_ref.size == 0:
        return {}
    d = _decade(y_ref)
    ok = np.abs(err) < FACTOR2_DECADES
    out: dict[str, dict[str, float | int]] = {}
    for k in np.unique(d):  # ascending
        m = d == k
        out[_label(k)] = {"n": int(m.sum()), "factor2_fraction": float(ok[m].mean())}
    return out
