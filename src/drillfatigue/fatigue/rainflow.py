"""Rainflow counting on exact reversals, built on fatpack's pieces.

fatpack's ``find_reversals`` bins a signal into k load classes and
``find_rainflow_ranges`` closes the residue by repeating it; here the reversals
are exact (no hidden binning) unless the caller asks for load classes, and the
residue is closed as the user chooses:

* ``half``: ASTM E1049-85 (2017) counting; each adjacent pair of the residue
  is a half cycle;
* ``repeat``: the residue is concatenated with itself and counted once more
  (fatpack's convention; conservative for a block that repeats);
* ``carry``: streaming; :class:`RainflowStream` carries the residue from one
  chunk to the next with ``fatpack.concatenate_reversals`` and closes it at the
  end (as half cycles by default).

An indexed count (start and end sample of every cycle) comes from the numba
kernel :func:`drillfatigue.fatigue.kernels.rainflow_indexed`; tests cross-check
it against fatpack and the ``rainflow`` package.

References
----------
ASTM E1049-85 (reapproved 2017), Standard Practices for Cycle Counting in
Fatigue Analysis, section 5.4.4 and Fig. 6.
ISO 12110-2:2013, Metallic materials - Fatigue testing - Variable amplitude
fatigue testing - Part 2: Cycle counting, Annex A (worked example).
Amzallag et al., Int. J. Fatigue 16 (1994) 287-293 (4-point method).
"""

from __future__ import annotations

from dataclasses import dataclass

import fatpack
import numpy as np

from drillfatigue.errors import InputError, raise_for_status
from drillfatigue.fatigue import kernels as K

RESIDUE_MODES: tuple[str, ...] = ("half", "repeat", "carry")
_KERNEL_MODE = {"half": K.RESIDUE_HALF, "repeat": K.RESIDUE_REPEAT}


@dataclass(frozen=True)
class Cycles:
    """Counted cycles.

    Attributes
    ----------
    start, end : ndarray, shape (n,)
        Values at the two ends of each cycle (signal unit).
    count : ndarray, shape (n,)
        1.0 for a full cycle, 0.5 for a half cycle.
    """

    start: np.ndarray
    end: np.ndarray
    count: np.ndarray

    @property
    def ranges(self) -> np.ndarray:
        """Ranges |end - start|, shape (n,)."""
        return np.abs(self.end - self.start)

    @property
    def means(self) -> np.ndarray:
        """Means (start + end)/2, shape (n,)."""
        return 0.5 * (self.start + self.end)

    def __len__(self) -> int:
        return int(self.count.shape[0])

    @staticmethod
    def empty() -> Cycles:
        z = np.zeros(0)
        return Cycles(z, z.copy(), z.copy())

    @staticmethod
    def concat(parts: list[Cycles]) -> Cycles:
        parts = [p for p in parts if len(p)]
        if not parts:
            return Cycles.empty()
        return Cycles(np.concatenate([p.start for p in parts]),
                      np.concatenate([p.end for p in parts]),
                      np.concatenate([p.count for p in parts]))


def _check_signal(y: np.ndarray, name: str = "signal") -> np.ndarray:
    y = np.asarray(y, dtype=np.float64)
    if y.ndim != 1:
        raise InputError(name, f"must be one-dimensional, got shape {y.shape}", "shape (n,)")
    if y.size == 0:
        raise InputError(name, "is empty (zero-length history)", "at least one sample")
    if not np.all(np.isfinite(y)):
        raise InputError(name, "contains NaN or infinite values", "finite numbers")
    return y


def check_residue_mode(mode: str) -> str:
    """Return ``mode`` if it is a known residue mode, else raise InputError."""
    if mode not in RESIDUE_MODES:
        raise InputError("fatigue.residue", f"unknown residue mode {mode!r}",
                         ", ".join(RESIDUE_MODES))
    return mode


def residue_closure(mode: str) -> str:
    """How the residue of a whole history is closed under residue mode ``mode``:
    'repeat', else 'half' (``carry`` on a whole history behaves as ``half``)."""
    return "repeat" if mode == "repeat" else "half"


def kernel_residue_mode(mode: str) -> int:
    """The kernels' residue code (``RESIDUE_*``) of residue mode ``mode`` on a whole history."""
    return _KERNEL_MODE[residue_closure(mode)]


def find_exact_reversals(y: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Peak-valley filter without binning.

    The first and last samples are kept; on a plateau the reversal is the
    plateau's first sample.

    Parameters
    ----------
    y : ndarray, shape (n,)

    Returns
    -------
    reversals : ndarray, shape (r,)
        Values of the reversals.
    indices : ndarray, shape (r,), int
        Their sample indices.
    """
    y = _check_signal(y)
    idx = np.flatnonzero(np.r_[True, np.diff(y) != 0.0])
    z = y[idx]
    if z.size < 3:
        return z, idx
    d = np.diff(z)
    # a turn is a change of the difference's sign (no difference is zero here): compared
    # by sign, not by the product, which underflows to -0.0 for differences below ~1e-154
    rising = d > 0.0
    turn = np.flatnonzero(rising[:-1] != rising[1:]) + 1
    ridx = np.r_[0, turn, z.size - 1]
    return z[ridx], idx[ridx]


def _reversals(y: np.ndarray, load_classes: int | None) -> np.ndarray:
    if load_classes is None:
        return find_exact_reversals(y)[0]
    if int(load_classes) < 2:
        raise InputError("fatigue.load_classes", f"must be >= 2, got {load_classes}", ">= 2 or null")
    if np.ptp(y) == 0.0:
        return y[:1].copy()
    # ISO 12110-2 class rounding (boundary points rounded outwards)
    rev, _ = fatpack.rainflow.find_reversals_strict(y, k=int(load_classes))
    return rev


def _pass(reversals: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """One 4-point pass with fatpack; cycles as (n, 2) and the residue."""
    if reversals.size < 4:
        return np.zeros((0, 2)), reversals.copy()
    cyc, res = fatpack.find_rainflow_cycles(reversals)
    if cyc.ndim != 2:
        cyc = np.zeros((0, 2))
    return cyc, np.asarray(res, dtype=np.float64)


def concatenate_reversals(r1: np.ndarray, r2: np.ndarray) -> np.ndarray:
    """Join two reversal sequences, keeping the true turning points at the junction.

    Uses ``fatpack.concatenate_reversals`` when the end of ``r1`` and the start
    of ``r2`` run in the same direction. fatpack 0.7.8 keeps the wrong point
    when they run in opposite directions (e.g. [0, 5] + [6, 1] gives [0, 5, 1]
    instead of [0, 6, 1]; [0, 5] + [4, 1] gives [0, 4, 1] instead of
    [0, 5, 1]), so those cases, and sequences shorter than two points, are
    joined by an exact peak-valley filter of the concatenation.
    """
    if (r1.size >= 2 and r2.size >= 2 and r1[-1] != r1[-2] and r2[1] != r2[0]
            and (r1[-1] > r1[-2]) == (r2[1] > r2[0])):
        try:
            return fatpack.concatenate_reversals(r1, r2)
        except ValueError:
            pass
    return find_exact_reversals(np.concatenate([r1, r2]))[0]


_concat_reversals = concatenate_reversals


def _close_residue(residue: np.ndarray, mode: str) -> Cycles:
    if residue.size < 2:
        return Cycles.empty()
    if mode == "half":
        return Cycles(residue[:-1].copy(), residue[1:].copy(), np.full(residue.size - 1, 0.5))
    if mode == "repeat":
        cyc, _ = _pass(_concat_reversals(residue, residue))
        return Cycles(cyc[:, 0], cyc[:, 1], np.ones(cyc.shape[0]))
    return Cycles.empty()


def find_cycles(y: np.ndarray, residue: str = "half", load_classes: int | None = None) -> Cycles:
    """Rainflow cycles of a whole history.

    Parameters
    ----------
    y : ndarray, shape (n,)
        Signal, any unit.
    residue : {'half', 'repeat', 'carry'}
        Residue closure (``carry`` on a whole history behaves as ``half``).
    load_classes : int, optional
        Bin into this many load classes first (ISO 12110-2 strict rounding);
        default None: exact reversals.

    Returns
    -------
    Cycles
    """
    check_residue_mode(residue)
    y = _check_signal(y)
    rev = _reversals(y, load_classes)
    cyc, res = _pass(rev)
    closed = Cycles(cyc[:, 0], cyc[:, 1], np.ones(cyc.shape[0]))
    return Cycles.concat([closed, _close_residue(res, residue_closure(residue))])


def find_cycles_indexed(y: np.ndarray, residue: str = "half"
                        ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Rainflow cycles with the sample index of each cycle's two ends (numba).

    Parameters
    ----------
    y : ndarray, shape (n,)
    residue : {'half', 'repeat'}

    Returns
    -------
    i_from, i_to : ndarray, shape (n_cycles,), int64
        Sample indices of the start and end of each cycle.
    count : ndarray, shape (n_cycles,)
        1.0 or 0.5.
    """
    check_residue_mode(residue)
    y = _check_signal(y)
    n = y.size
    cap = 2 * n + 2
    i_from = np.empty(cap, dtype=np.int64)
    i_to = np.empty(cap, dtype=np.int64)
    count = np.empty(cap)
    res = np.empty(n + 1, dtype=np.int64)
    nc = K.rainflow_indexed(y, kernel_residue_mode(residue), i_from, i_to, count, res)
    if nc < 0:  # pragma: no cover - capacity is a proven bound
        raise_for_status(-nc, "rainflow_indexed")
    return i_from[:nc].copy(), i_to[:nc].copy(), count[:nc].copy()


class RainflowStream:
    """Streaming rainflow (residue mode ``carry``): feed chunks, then finish.

    Cycles closed inside the carried sequence are final as soon as they are
    found, so the sum over chunks equals the count of the whole history.

    Parameters
    ----------
    close : {'half', 'repeat'}
        How :meth:`finish` closes the final residue.
    """

    def __init__(self, close: str = "half") -> None:
        if close not in ("half", "repeat"):
            raise InputError("close", f"unknown residue closure {close!r}", "half, repeat")
        self.close = close
        self.residue_ = np.zeros(0)
        self.n_samples_ = 0

    def feed(self, chunk: np.ndarray) -> Cycles:
        """Count one chunk; return the cycles it closed."""
        y = _check_signal(chunk, "chunk")
        rev = find_exact_reversals(y)[0]
        seq = rev if self.residue_.size == 0 else _concat_reversals(self.residue_, rev)
        cyc, self.residue_ = _pass(seq)
        self.n_samples_ += y.size
        return Cycles(cyc[:, 0], cyc[:, 1], np.ones(cyc.shape[0]))

    def finish(self) -> Cycles:
        """Close the carried residue (half or repeated cycles)."""
        return _close_residue(self.residue_, self.close)


def rainflow_matrix(cycles: Cycles, n_bins: int = 32) -> tuple[np.ndarray, np.ndarray]:
    """From-to rainflow matrix (counts) on equal bins, for plotting.

    Returns
    -------
    matrix : ndarray, shape (n_bins, n_bins)
    edges : ndarray, shape (n_bins + 1,)
    """
    if len(cycles) == 0:
        return np.zeros((n_bins, n_bins)), np.linspace(0.0, 1.0, n_bins + 1)
    lo = float(min(cycles.start.min(), cycles.end.min()))
    hi = float(max(cycles.start.max(), cycles.end.max()))
    if hi <= lo:
        hi = lo + 1.0
    edges = np.linspace(lo, hi, n_bins + 1)
    data = np.column_stack([cycles.start, cycles.end])
    mat = fatpack.find_rainflow_matrix(data, edges, edges, counts=cycles.count)
    return np.asarray(mat), edges
