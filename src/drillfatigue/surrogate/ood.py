"""Out-of-domain detection for surrogate queries.

A query is flagged (never silently extrapolated) when

1. **range**: any numeric feature lies outside its domain: the design range
   of the sweep that produced the training data (``sweep.variables``, saved
   with the model at training) for a feature that is a design variable, the
   [min, max] seen in training for a feature derived from the design (the
   location's MD, distance from the bit, hole geometry), or
2. **joint distance**: the mean Euclidean distance to its k nearest training
   points, in standardised numeric-feature space, exceeds the ``quantile``
   (default 99th percentile) of the same distance for the held-out
   calibration rows (which are not in the reference set). A point inside all
   per-feature ranges but in an empty corner of the design (e.g. high rpm
   combined with low WOB if no case had both) is thereby flagged.

Categorical levels unseen in training are rejected earlier, as input errors.
A flagged query is refused by the public answers (:meth:`Surrogate.predict`,
``drillfatigue query``, the service): :meth:`DomainChecker.refusal` gives the
one-line error naming the first variable outside its range and that range.
The reference set is a seeded subsample of the training rows (at most
``reference_rows``) to bound memory and query cost. The distance is exact
(float64 differences): a compiled search (:class:`KnnIndex`,
:func:`~drillfatigue.surrogate.kernels.knn_mean_distance`) over the distinct
reference rows grouped by case-level columns, which skips a group, or a row,
once a partial sum reaches the current k-th best. The flag needs less: by
default (:meth:`DomainChecker.check`) a row's search goes best first over
super-groups of cases and stops once the row is certainly within the
threshold (:func:`~drillfatigue.surrogate.kernels.knn_within`); every flag
is exact, and so is the distance of every row beyond the threshold, the
only one a refusal names. Batches run in chunks on the thread pool (the
kernels release the GIL).
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence

import numpy as np

from drillfatigue.errors import InputError
from drillfatigue.surrogate.kernels import knn_mean_distance, knn_within, outside_ranges
from drillfatigue.surrogate.parallel import map_chunks

_CHUNK = 4096  # rows per worker call of the domain check
_ONE_THREAD_ROWS = 2048  # up to this many rows, check on the calling thread
# distinct rows per group up to which the served flag search goes best first over
# super-groups, scanning groups whole (CPU time per row, one thread, against the search of
# every distance, which walks its first group outward: 154 groups of 12 rows 0.41 vs 1.35 us,
# 36 synthetic groups of 8 rows 0.21 vs 0.28 us, 20 groups of 45 rows 0.49 vs 0.47 us)
_BEST_FIRST_ROWS_PER_GROUP = 24


def _partition_labels(col: np.ndarray) -> np.ndarray:
    """Labels of the equal values of ``col``, numbered by first occurrence (canonical)."""
    _, first, inverse = np.unique(col, return_index=True, return_inverse=True)
    rank = np.empty(first.size, dtype=np.int64)
    rank[np.argsort(first, kind="stable")] = np.arange(first.size)
    return rank[inverse.ravel()]


def key_columns(unique_rows: np.ndarray) -> list[int]:
    """Columns of the k-NN index's group key: the largest set that partitions the rows alike.

    Rows of one simulated case share every operating condition (rpm, ROP,
    mud, friction, ...) and differ only in the location features, so those
    columns split the reference into the same groups, one per case. Among
    the sets of columns with the same partition of ``unique_rows`` into
    groups of equal values, the one with the most columns (then the fewest
    groups) is the key, if its groups hold two rows on average or more; else
    none (one group: a plain scan). Only the speed of
    :func:`~drillfatigue.surrogate.kernels.knn_mean_distance` depends on it,
    never its result.
    """
    n, d = unique_rows.shape
    classes: dict[bytes, list[int]] = {}
    groups: dict[bytes, int] = {}
    for c in range(d):
        lab = _partition_labels(unique_rows[:, c])
        key = lab.tobytes()
        classes.setdefault(key, []).append(c)
        groups[key] = int(lab.max()) + 1 if n else 0
    best: list[int] = []
    best_groups = n
    for key, cols in classes.items():
        if 2 * groups[key] > n:
            continue
        if len(cols) > len(best) or (len(cols) == len(best) and groups[key] < best_groups):
            best, best_groups = cols, groups[key]
    return best


def super_groups(keys: np.ndarray, size: int) -> list[np.ndarray]:
    """Groups split into super-groups of at most ``size`` by their keys, a k-d tree's leaves.

    ``keys`` (n_groups, n_key): the groups' key values. The groups are split
    at the median of the key column of widest spread, recursively, until a
    part holds ``size`` groups or fewer; the parts, left to right. Near keys
    share a super-group, so its box stays small. Only the speed of
    :func:`~drillfatigue.surrogate.kernels.knn_within` depends on the
    split, never its result.
    """
    parts: list[np.ndarray] = []
    todo = [np.arange(keys.shape[0])]
    while todo:
        part = todo.pop()
        spread = np.ptp(keys[part], axis=0) if keys.shape[1] else np.zeros(1)
        if part.size <= size or not np.any(spread > 0):
            parts.append(part)
            continue
        c = int(np.argmax(spread))
        order = part[np.argsort(keys[part, c], kind="stable")]
        half = order.size // 2
        todo += [order[half:], order[:half]]  # the left part is split first
    return parts


class KnnIndex:
    """Reference rows of the k-NN distance, de-duplicated and grouped by key columns.

    Groups (rows of equal key columns: one per simulated case) are gathered
    into super-groups of about the square root of their number
    (:func:`super_groups`), each with the box of its groups' columns, so a
    query bounds a few super-groups and the groups of the nearest ones
    rather than every group.

    Parameters
    ----------
    reference : ndarray, shape (n_ref, d)
        Standardised reference rows (any float dtype; searched in float64).
    """

    def __init__(self, reference: np.ndarray) -> None:
        ref = np.asarray(reference, dtype=np.float64)
        self.n_rows, d = ref.shape
        uniq, count = np.unique(ref, axis=0, return_counts=True)
        key = key_columns(uniq)
        rest = [c for c in range(d) if c not in key]
        group = (_partition_labels(uniq[:, key[0]]) if key
                 else np.zeros(uniq.shape[0], dtype=np.int64))
        n_groups = int(group.max()) + 1
        keys = np.zeros((n_groups, len(key)))
        keys[group] = uniq[:, key]
        # groups renumbered super-group by super-group
        parts = super_groups(keys, max(4, math.isqrt(n_groups - 1) + 1))
        renumber = np.empty(n_groups, dtype=np.int64)
        renumber[np.concatenate(parts)] = np.arange(n_groups)
        group = renumber[group]
        keys[renumber] = keys.copy()
        self.super_start = np.concatenate(
            [[0], np.cumsum([p.size for p in parts])]).astype(np.int64)
        if rest:
            # rows of a group sorted by the column that spreads them most within the
            # groups: the nearest group is walked outward along it
            size = np.bincount(group, minlength=n_groups)
            means = np.stack([np.bincount(group, weights=uniq[:, c], minlength=n_groups) / size
                              for c in rest], axis=1)
            within = ((uniq[:, rest] - means[group]) ** 2).sum(axis=0)
            rest.insert(0, rest.pop(int(np.argmax(within))))
        self.perm = np.asarray(key + rest, dtype=np.int64)
        self.n_key = len(key)
        col0 = uniq[:, rest[0]] if rest else np.zeros(uniq.shape[0])
        order = np.lexsort((col0, group))
        self.keys_t = np.ascontiguousarray(keys.T)
        self.rest = np.ascontiguousarray(uniq[order][:, rest], dtype=np.float64)
        self.rest_t = np.ascontiguousarray(self.rest.T)
        self.box_lo = np.full((len(rest), n_groups), np.inf)
        self.box_hi = np.full((len(rest), n_groups), -np.inf)
        np.minimum.at(self.box_lo.T, group, uniq[:, rest])
        np.maximum.at(self.box_hi.T, group, uniq[:, rest])
        # box of a super-group: every column, key columns first (the kernel's order)
        lo = np.vstack([self.keys_t, self.box_lo])
        hi = np.vstack([self.keys_t, self.box_hi])
        # each group's box as a row: the few groups of one super-group are bounded row by row
        self.group_lo = np.ascontiguousarray(lo.T)
        self.group_hi = np.ascontiguousarray(hi.T)
        self.super_lo = np.ascontiguousarray(np.minimum.reduceat(lo, self.super_start[:-1], axis=1))
        self.super_hi = np.ascontiguousarray(np.maximum.reduceat(hi, self.super_start[:-1], axis=1))
        self.count = np.ascontiguousarray(count[order], dtype=np.int64)
        self.group_start = np.concatenate(
            [[0], np.cumsum(np.bincount(group, minlength=n_groups))]).astype(np.int64)

    def mean_distance(self, x: np.ndarray, mean: np.ndarray, scale: np.ndarray, k: int,
                      out: np.ndarray) -> None:
        """Mean distance of rows ``(x - mean) / scale`` to their ``k`` nearest reference rows."""
        knn_mean_distance(x, mean, scale, self.perm, self.n_key, self.keys_t, self.group_start,
                          self.rest, self.rest_t, self.box_lo, self.box_hi, self.count,
                          min(int(k), self.n_rows), out)

    def distance_beyond(self, x: np.ndarray, mean: np.ndarray, scale: np.ndarray, k: int,
                        threshold: float, out: np.ndarray) -> None:
        """:meth:`mean_distance` where it exceeds ``threshold``, NaN where it does not.

        The search of a row stops once ``k`` reference rows within a mean
        distance ``threshold`` are found
        (:func:`~drillfatigue.surrogate.kernels.knn_within`, which scans
        groups whole); with more than 24 distinct rows per group on average
        every distance is computed instead (:meth:`mean_distance`, which
        walks its first group outward and is as fast there). Either way the
        flag ``distance > threshold`` of every row is exact, and so is the
        distance of every row beyond it.
        """
        if self.rest.shape[0] > _BEST_FIRST_ROWS_PER_GROUP * self.keys_t.shape[1]:
            self.mean_distance(x, mean, scale, k, out)
            out[out <= threshold] = np.nan
        else:
            knn_within(x, mean, scale, self.perm, self.n_key, self.group_start,
                       self.rest_t, self.group_lo, self.group_hi, self.count, self.super_start,
                       self.super_lo, self.super_hi, min(int(k), self.n_rows), float(threshold),
                       out)


def knn_distance(z: np.ndarray, reference: np.ndarray, k: int) -> np.ndarray:
    """Mean distance of each row of ``z`` to its ``k`` nearest rows of ``reference``.

    Exact (float64 differences, no expansion of the square); see
    :class:`KnnIndex` and :func:`~drillfatigue.surrogate.kernels.knn_mean_distance`.

    Parameters
    ----------
    z : ndarray, shape (n, d)
        Standardised query points.
    reference : ndarray, shape (n_ref, d)
    k : int

    Returns
    -------
    ndarray, shape (n,)
    """
    z = np.ascontiguousarray(z, dtype=np.float64)
    d = z.shape[1]
    out = np.empty(z.shape[0])
    KnnIndex(reference).mean_distance(z, np.zeros(d), np.ones(d), k, out)
    return out


class DomainChecker:
    """Per-feature range and k-NN distance out-of-domain test.

    Parameters
    ----------
    names : sequence of str
        Numeric feature names (for the reason text).
    k : int
        Neighbours of the joint-distance test.
    quantile : float
        Calibration quantile of the k-NN distance used as threshold.
    reference_rows : int
        Largest reference subsample.
    seed : int
        Subsampling seed.
    """

    def __init__(self, names: Sequence[str], k: int = 5, quantile: float = 0.99,
                 reference_rows: int = 5000, seed: int = 0) -> None:
        self.names = list(names)
        self.k = k
        self.quantile = quantile
        self.reference_rows = reference_rows
        self.seed = seed

    def fit(self, x_train: np.ndarray, x_cal: np.ndarray, mean: np.ndarray,
            scale: np.ndarray,
            design_bounds: Mapping[str, tuple[float, float]] | None = None) -> DomainChecker:
        """Ranges and threshold (raw SI arrays (n, d)).

        ``design_bounds``: per feature name the design range (low, high) of
        the sweep; a feature not in it takes the [min, max] of ``x_train``.
        The k-NN threshold comes from ``x_cal``.
        """
        self._fit_reference(x_train, mean, scale, design_bounds)
        d_cal = np.empty(x_cal.shape[0])
        self.index.mean_distance(np.ascontiguousarray(x_cal, dtype=np.float64), self.mean_,
                                 self.scale_, self.k, d_cal)
        self.threshold_ = float(np.quantile(d_cal, self.quantile))
        self.threshold_source_ = "calibration rows"
        return self

    def fit_cross(self, x: np.ndarray, folds: np.ndarray, mean: np.ndarray,
                  scale: np.ndarray,
                  design_bounds: Mapping[str, tuple[float, float]] | None = None
                  ) -> DomainChecker:
        """Reference of every row of ``x``, threshold cross-fitted over ``folds`` of whole cases.

        The served reference is the seeded subsample of all of ``x`` (every
        case the served model trains on), so no case is spent on
        calibration. The threshold is the ``quantile`` of the out-of-fold
        distances: each row's k-NN distance to the reference rows of the
        other folds' cases, the distance a new case of the design has to
        cases it is not part of. That reference holds (K - 1)/K of the
        served one, so its distances are a little longer (by about
        (K/(K - 1))^(1/d) in d dimensions of uniform density) and the
        threshold errs towards answering, not towards refusing in-design
        queries.

        Parameters
        ----------
        x : ndarray, shape (n, d)
            Raw SI numeric features of the training rows.
        folds : ndarray of int, shape (n,)
            Fold per row, whole cases per fold
            (:func:`drillfatigue.surrogate.data.case_folds`), at least two folds.
        mean, scale : ndarray, shape (d,)
        design_bounds : mapping, optional
            As in :meth:`fit`.
        """
        folds = np.asarray(folds)
        labels = np.unique(folds)
        if labels.size < 2:
            raise ValueError("fit_cross needs rows of two folds or more")
        keep = self._fit_reference(x, mean, scale, design_bounds)
        ref_fold = folds[keep]
        x = np.ascontiguousarray(x, dtype=np.float64)
        d_oof = np.empty(x.shape[0])
        for f in labels:
            other = ref_fold != f
            if not other.any():
                raise ValueError(f"fold {f} holds every reference row")
            rows = np.flatnonzero(folds == f)
            d = np.empty(rows.size)
            KnnIndex(self.reference_[other]).mean_distance(
                np.ascontiguousarray(x[rows]), self.mean_, self.scale_, self.k, d)
            d_oof[rows] = d
        self.threshold_ = float(np.quantile(d_oof, self.quantile))
        self.threshold_source_ = f"cross-fitted, {labels.size} folds of whole cases"
        return self

    def _fit_reference(self, x_train: np.ndarray, mean: np.ndarray, scale: np.ndarray,
                       design_bounds: Mapping[str, tuple[float, float]] | None
                       ) -> np.ndarray:
        """Ranges, standardisation and the reference subsample; the rows kept (indices)."""
        self.min_ = x_train.min(axis=0).astype(np.float64)
        self.max_ = x_train.max(axis=0).astype(np.float64)
        self.source_ = ["training"] * len(self.names)
        for j, name in enumerate(self.names):
            if design_bounds and name in design_bounds:
                lo, hi = design_bounds[name]
                self.min_[j], self.max_[j] = float(lo), float(hi)
                self.source_[j] = "design"
        self.mean_ = np.asarray(mean, dtype=np.float64)
        self.scale_ = np.asarray(scale, dtype=np.float64)
        z = (x_train - self.mean_) / self.scale_
        keep = np.arange(z.shape[0])
        if z.shape[0] > self.reference_rows:
            rng = np.random.default_rng(self.seed)
            keep = np.sort(rng.choice(z.shape[0], self.reference_rows, replace=False))
            z = z[keep]
        self.reference_ = z.astype(np.float32)
        return keep

    @property
    def index(self) -> KnnIndex:
        """The k-NN index of :attr:`reference_` (built on first use, rebuilt if replaced)."""
        if getattr(self, "_index_of", None) is not self.reference_:
            self._index = KnnIndex(self.reference_)
            self._index_of = self.reference_
        return self._index

    def check(self, x: np.ndarray, knn: bool = True, distances: bool = False
              ) -> tuple[np.ndarray, np.ndarray]:
        """Flag rows of ``x`` (raw SI, shape (n, d)).

        ``distances``: the k-NN distance of every row; by default only that
        of the rows beyond the threshold (the number their refusal names),
        NaN for the others, whose search stops as soon as they are certainly
        within it (:meth:`KnnIndex.distance_beyond`: the flags are the same).

        Returns
        -------
        flag : ndarray of bool, shape (n,)
        distance : ndarray, shape (n,)
            k-NN distance (NaN when ``knn`` is False, and within the
            threshold unless ``distances``).
        """
        x = np.ascontiguousarray(x, dtype=np.float64)
        n = x.shape[0]
        span = self.max_ - self.min_
        tol = 1e-9 * np.where(span > 0, span, np.abs(self.max_) + 1.0)
        lo = np.asarray(self.min_ - tol, dtype=np.float64)
        hi = np.asarray(self.max_ + tol, dtype=np.float64)
        flag = np.empty(n, dtype=bool)
        dist = np.full(n, np.nan)
        index = self.index if knn else None
        mean = np.ascontiguousarray(self.mean_, dtype=np.float64)
        scale = np.ascontiguousarray(self.scale_, dtype=np.float64)

        def run(a: int, b: int) -> None:
            f = outside_ranges(x[a:b], lo, hi)
            if index is not None:
                if distances:
                    index.mean_distance(x[a:b], mean, scale, self.k, dist[a:b])
                else:
                    index.distance_beyond(x[a:b], mean, scale, self.k, self.threshold_,
                                          dist[a:b])
                f |= dist[a:b] > self.threshold_
            flag[a:b] = f

        if n <= _ONE_THREAD_ROWS:  # few rows: no pool to wake
            run(0, n)
        else:  # both kernels release the GIL: chunks on the pool's threads
            map_chunks(lambda a: run(a, min(a + _CHUNK, n)), range(0, n, _CHUNK))
        return flag, dist

    def reasons(self, x: np.ndarray, dist: np.ndarray, flag: np.ndarray) -> np.ndarray:
        """One text per row: why it is out of domain ('' when in domain)."""
        out = np.full(x.shape[0], "", dtype=object)
        span = self.max_ - self.min_
        tol = 1e-9 * np.where(span > 0, span, np.abs(self.max_) + 1.0)
        for i in np.flatnonzero(flag):
            bits = []
            for j, name in enumerate(self.names):
                if x[i, j] < self.min_[j] - tol[j] or x[i, j] > self.max_[j] + tol[j]:
                    bits.append(f"{name}={x[i, j]:.6g} {self._outside(j, x[i, j])}")
            if np.isfinite(dist[i]) and dist[i] > self.threshold_:
                bits.append(f"far from training data (kNN distance {dist[i]:.3g} "
                            f"> {self.threshold_:.3g})")
            out[i] = "; ".join(bits)
        return out

    def _outside(self, j: int, v: float) -> str:
        side = "below" if v < self.min_[j] else "above"
        what = ("the design range" if self.source_[j] == "design"
                else "the range of the training data")
        return f"{side} {what} {self.min_[j]:.6g} .. {self.max_[j]:.6g}"

    def refusal(self, x_row: np.ndarray, dist: float, field_prefix: str = "") -> InputError:
        """The one-line error refusing an out-of-domain row (raw SI, shape (d,)).

        Field: the first feature outside its range (its design range, or the
        training data's for a derived feature), with that range as the allowed
        values; a row inside every range but far from the training data names
        the k-NN distance and its threshold.
        """
        span = self.max_ - self.min_
        tol = 1e-9 * np.where(span > 0, span, np.abs(self.max_) + 1.0)
        for j, name in enumerate(self.names):
            v = float(x_row[j])
            if v < self.min_[j] - tol[j] or v > self.max_[j] + tol[j]:
                what = "design range" if self.source_[j] == "design" else "training data"
                return InputError(field_prefix + name,
                                  f"{v:.6g} is outside the surrogate's {what}: no answer",
                                  f"{self.min_[j]:.6g} <= {name} <= {self.max_[j]:.6g}")
        return InputError(field_prefix + "query",
                          f"far from the training data (kNN distance {dist:.3g} in "
                          "standardised features): no answer",
                          f"kNN distance <= {self.threshold_:.3g}, a condition like "
                          "the simulated ones")

    def to_dict(self) -> dict:
        return {"names": self.names, "k": self.k, "quantile": self.quantile,
                "reference_rows": self.reference_rows, "seed": self.seed,
                "min": self.min_.tolist(), "max": self.max_.tolist(),
                "source": list(self.source_),
                "mean": self.mean_.tolist(), "scale": self.scale_.tolist(),
                "threshold": self.threshold_,
                "threshold_source": getattr(self, "threshold_source_", "calibration rows")}

    @classmethod
    def from_dict(cls, d: dict, reference: np.ndarray) -> DomainChecker:
        c = cls(d["names"], d["k"], d["quantile"], d["reference_rows"], d["seed"])
        c.min_ = np.asarray(d["min"])
        c.max_ = np.asarray(d["max"])
        c.source_ = list(d.get("source", ["training"] * len(c.names)))
        c.mean_ = np.asarray(d["mean"])
        c.scale_ = np.asarray(d["scale"])
        c.threshold_ = float(d["threshold"])
        c.threshold_source_ = d.get("threshold_source", "calibration rows")
        c.reference_ = np.asarray(reference, dtype=np.float32)
        return c
