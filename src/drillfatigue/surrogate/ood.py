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


#: Fewest distances of a group's own for its k-NN threshold; a group with fewer (a
#: combination that few cases have) takes the quantile pooled over every group.
MIN_GROUP_THRESHOLD_ROWS = 30
#: Code base of the combined categorical key (levels per categorical below it).
_CODE_BASE = 1 << 16


class DomainChecker:
    """Out-of-domain test per combination of the categorical features.

    The training rows are grouped by their categorical combination (component
    type x location). A query row is out of domain when

    - its combination is not in the training data (a collar ``upset``), or
    - a numeric feature is outside its range: for an operating input (a
      dotted configuration path such as ``operation.rpm``) its design range,
      or the range of all training rows when it was not designed, the same
      for every group; for a feature of the location (the
      location's MD, its distance from the bit, the hole geometry there) the
      [min, max] of that group's training rows (a collar 550 m behind the
      bit, drill pipe 5 m behind it), or
    - its mean distance to the ``k`` nearest training rows *of its group*, in
      standardised numeric features, exceeds the group's threshold: the
      ``quantile`` of the same distance of held-out (or cross-fitted) rows of
      that group (pooled over every group for a group with fewer than
      :data:`MIN_GROUP_THRESHOLD_ROWS` such rows).

    Without categorical features (``cat`` not given at fit) there is one group.

    Parameters
    ----------
    names : sequence of str
        Numeric feature names (for the reason text).
    k : int
        Neighbours of the joint-distance test.
    quantile : float
        Calibration quantile of the k-NN distance used as threshold.
    reference_rows : int
        Largest reference subsample per group.
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

    # -- fitting ---------------------------------------------------------------
    def fit(self, x_train: np.ndarray, x_cal: np.ndarray, mean: np.ndarray,
            scale: np.ndarray,
            design_bounds: Mapping[str, tuple[float, float]] | None = None,
            cat_train: np.ndarray | None = None, cat_cal: np.ndarray | None = None,
            categories: Mapping[str, Sequence[str]] | None = None) -> DomainChecker:
        """Ranges and thresholds (raw SI arrays (n, d); category codes (n, n_cat)).

        ``design_bounds``: per feature name the design range (low, high) of
        the sweep; a feature not in it takes the [min, max] of its group's
        rows of ``x_train``. The k-NN thresholds come from ``x_cal``.
        ``categories``: the level names per categorical feature, in code order.
        """
        self._fit_reference(x_train, cat_train, mean, scale, design_bounds, categories)
        g_cal = self._group_of(cat_cal, x_cal.shape[0])
        d_cal = np.full(x_cal.shape[0], np.nan)
        x_cal = np.ascontiguousarray(x_cal, dtype=np.float64)
        for gi in range(self.n_groups):
            rows = np.flatnonzero(g_cal == gi)
            if rows.size:
                d = np.empty(rows.size)
                self._index(gi).mean_distance(np.ascontiguousarray(x_cal[rows]), self.mean_,
                                              self.scale_, self.k, d)
                d_cal[rows] = d
        self._set_thresholds(d_cal, g_cal, "calibration rows")
        return self

    def fit_cross(self, x: np.ndarray, folds: np.ndarray, mean: np.ndarray,
                  scale: np.ndarray,
                  design_bounds: Mapping[str, tuple[float, float]] | None = None,
                  cat: np.ndarray | None = None,
                  categories: Mapping[str, Sequence[str]] | None = None) -> DomainChecker:
        """Reference of every row of ``x``, thresholds cross-fitted over ``folds`` of whole cases.

        The served reference is the seeded subsample of all of ``x`` (every
        case the served model trains on), so no case is spent on
        calibration. A group's threshold is the ``quantile`` of its rows'
        out-of-fold distances: each row's k-NN distance to the reference rows
        of its group from the other folds' cases, the distance a new case of
        the design has to cases it is not part of. That reference holds
        (K - 1)/K of the served one, so its distances are a little longer and
        the threshold errs towards answering, not towards refusing in-design
        queries.

        Parameters
        ----------
        x : ndarray, shape (n, d)
            Raw SI numeric features of the training rows.
        folds : ndarray of int, shape (n,)
            Fold per row, whole cases per fold
            (:func:`drillfatigue.surrogate.data.case_folds`), at least two folds.
        mean, scale : ndarray, shape (d,)
        design_bounds, categories : as in :meth:`fit`.
        cat : ndarray of int, shape (n, n_cat), optional
            Category codes of the rows.
        """
        folds = np.asarray(folds)
        labels = np.unique(folds)
        if labels.size < 2:
            raise ValueError("fit_cross needs rows of two folds or more")
        keep = self._fit_reference(x, cat, mean, scale, design_bounds, categories)
        g_all = self._group_of(cat, x.shape[0])
        x = np.ascontiguousarray(x, dtype=np.float64)
        d_oof = np.full(x.shape[0], np.nan)
        for gi in range(self.n_groups):
            ref_rows = keep[gi]
            ref = self.reference_[self.group_offsets_[gi]:self.group_offsets_[gi + 1]]
            ref_fold = folds[ref_rows]
            for f in labels:
                other = ref_fold != f
                rows = np.flatnonzero((folds == f) & (g_all == gi))
                if not rows.size or not other.any():
                    continue  # a combination of one fold's cases only: pooled threshold
                d = np.empty(rows.size)
                KnnIndex(ref[other]).mean_distance(np.ascontiguousarray(x[rows]), self.mean_,
                                                   self.scale_, self.k, d)
                d_oof[rows] = d
        self._set_thresholds(d_oof, g_all, f"cross-fitted, {labels.size} folds of whole cases")
        return self

    def _set_thresholds(self, dist: np.ndarray, groups: np.ndarray, source: str) -> None:
        ok = np.isfinite(dist) & (groups >= 0)
        if not ok.any():
            raise ValueError("no distances to set the out-of-domain threshold from")
        self.threshold_ = float(np.quantile(dist[ok], self.quantile))  # pooled
        self.threshold_source_ = source
        self.group_threshold_ = np.full(self.n_groups, self.threshold_)
        self.group_threshold_own_ = np.zeros(self.n_groups, dtype=bool)
        for gi in range(self.n_groups):
            d = dist[ok & (groups == gi)]
            if d.size >= MIN_GROUP_THRESHOLD_ROWS:
                self.group_threshold_[gi] = float(np.quantile(d, self.quantile))
                self.group_threshold_own_[gi] = True

    def _fit_reference(self, x_train: np.ndarray, cat: np.ndarray | None, mean: np.ndarray,
                       scale: np.ndarray,
                       design_bounds: Mapping[str, tuple[float, float]] | None,
                       categories: Mapping[str, Sequence[str]] | None) -> list[np.ndarray]:
        """Groups, ranges, standardisation and the reference subsample per group; the rows
        kept per group (indices into ``x_train``)."""
        n, d = x_train.shape
        self.cat_names_ = list(categories) if categories else []
        self.levels_ = [list(map(str, categories[c])) for c in self.cat_names_] \
            if categories else []
        if cat is None or not self.cat_names_:
            codes = np.zeros((1, 0), dtype=np.int64)
            inverse = np.zeros(n, dtype=np.int64)
        else:
            cat = np.asarray(cat, dtype=np.int64).reshape(n, -1)
            codes, inverse = np.unique(cat, axis=0, return_inverse=True)
            inverse = np.asarray(inverse).reshape(-1)
        self.group_codes_ = codes.astype(np.int64)
        self._set_group_keys()
        self.source_ = ["training"] * len(self.names)
        design = np.zeros(d, dtype=bool)
        lo_d = np.zeros(d)
        hi_d = np.zeros(d)
        for j, name in enumerate(self.names):
            # an operating input is a dotted configuration path (operation.rpm): its design
            # range, else the range of all training rows; the location's features (md_m,
            # s_from_bit_m, the hole geometry there) take their group's training range
            if "." not in name:
                continue
            if design_bounds and name in design_bounds:
                lo_d[j], hi_d[j] = (float(v) for v in design_bounds[name])
                self.source_[j] = "design"
            else:
                lo_d[j], hi_d[j] = float(x_train[:, j].min()), float(x_train[:, j].max())
            design[j] = True
        self.mean_ = np.asarray(mean, dtype=np.float64)
        self.scale_ = np.asarray(scale, dtype=np.float64)
        rng = np.random.default_rng(self.seed)
        g_min, g_max, refs, keep = [], [], [], []
        for gi in range(self.n_groups):
            rows = np.flatnonzero(inverse == gi)
            xg = x_train[rows]
            g_min.append(np.where(design, lo_d, xg.min(axis=0)))
            g_max.append(np.where(design, hi_d, xg.max(axis=0)))
            if rows.size > self.reference_rows:
                rows = np.sort(rng.choice(rows, self.reference_rows, replace=False))
            keep.append(rows)
            refs.append(((x_train[rows] - self.mean_) / self.scale_).astype(np.float32))
        self.group_min_ = np.asarray(g_min, dtype=np.float64)
        self.group_max_ = np.asarray(g_max, dtype=np.float64)
        self.min_ = self.group_min_.min(axis=0)
        self.max_ = self.group_max_.max(axis=0)
        self.group_offsets_ = np.concatenate([[0], np.cumsum([r.shape[0] for r in refs])]
                                             ).astype(np.int64)
        self.reference_ = np.concatenate(refs, axis=0)
        self._indexes: dict[int, KnnIndex] = {}
        return keep

    def _set_group_keys(self) -> None:
        key = self._keys(self.group_codes_)
        self._key_order = np.argsort(key, kind="stable")
        self._key_sorted = key[self._key_order]

    @staticmethod
    def _keys(codes: np.ndarray) -> np.ndarray:
        codes = np.asarray(codes, dtype=np.int64)
        if codes.shape[1] == 0:
            return np.zeros(codes.shape[0], dtype=np.int64)
        base = np.int64(_CODE_BASE) ** np.arange(codes.shape[1], dtype=np.int64)
        return codes @ base

    @property
    def n_groups(self) -> int:
        """Number of categorical combinations in the training data."""
        return int(self.group_codes_.shape[0])

    @property
    def index(self) -> KnnIndex:
        """The k-NN index of the first group (the only one without categorical features)."""
        return self._index(0)

    def _index(self, gi: int) -> KnnIndex:
        """The k-NN index of group ``gi``'s reference rows (built on first use)."""
        idx = self.__dict__.setdefault("_indexes", {})
        if gi not in idx:
            idx[gi] = KnnIndex(self.reference_[self.group_offsets_[gi]:self.group_offsets_[gi + 1]])
        return idx[gi]

    def _group_of(self, x_cat: np.ndarray | None, n: int) -> np.ndarray:
        """Group of each row (-1: a combination not in the training data)."""
        if self.group_codes_.shape[1] == 0 or x_cat is None:
            return np.zeros(n, dtype=np.int64)
        x_cat = np.asarray(x_cat, dtype=np.int64).reshape(n, -1)
        if x_cat.shape[1] != self.group_codes_.shape[1]:
            raise ValueError(f"{x_cat.shape[1]} categorical columns, the domain has "
                             f"{self.group_codes_.shape[1]}")
        key = self._keys(x_cat)
        pos = np.searchsorted(self._key_sorted, key)
        pos_c = np.minimum(pos, self._key_sorted.size - 1)
        hit = self._key_sorted[pos_c] == key
        return np.where(hit, self._key_order[pos_c], -1).astype(np.int64)

    # -- checking --------------------------------------------------------------
    def check(self, x: np.ndarray, x_cat: np.ndarray | None = None, knn: bool = True,
              distances: bool = False) -> tuple[np.ndarray, np.ndarray]:
        """Flag rows of ``x`` (raw SI, shape (n, d)) with category codes ``x_cat`` (n, n_cat).

        ``distances``: the k-NN distance of every row; by default only that
        of the rows beyond their group's threshold (the number their refusal
        names), NaN for the others, whose search stops as soon as they are
        certainly within it (:meth:`KnnIndex.distance_beyond`: the flags are
        the same). A row of a combination not in the training data is
        flagged, its distance NaN.

        Returns
        -------
        flag : ndarray of bool, shape (n,)
        distance : ndarray, shape (n,)
            k-NN distance within the row's group (NaN when ``knn`` is False,
            and within the threshold unless ``distances``).
        """
        x = np.ascontiguousarray(x, dtype=np.float64)
        n = x.shape[0]
        g = self._group_of(x_cat, n)
        flag = np.ones(n, dtype=bool)
        dist = np.full(n, np.nan)
        present = np.unique(g[g >= 0]) if n else np.zeros(0, dtype=np.int64)
        if present.size == 1 and present[0] >= 0 and not (g < 0).any():
            self._check_group(int(present[0]), x, knn, distances, flag, dist)
            return flag, dist
        for gi in present:
            rows = np.flatnonzero(g == gi)
            f = np.empty(rows.size, dtype=bool)
            dd = np.full(rows.size, np.nan)
            self._check_group(int(gi), np.ascontiguousarray(x[rows]), knn, distances, f, dd)
            flag[rows] = f
            dist[rows] = dd
        return flag, dist

    def _bounds(self, gi: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        lo, hi = self.group_min_[gi], self.group_max_[gi]
        span = hi - lo
        tol = 1e-9 * np.where(span > 0, span, np.abs(hi) + 1.0)
        return lo, hi, tol

    def _check_group(self, gi: int, x: np.ndarray, knn: bool, distances: bool,
                     flag: np.ndarray, dist: np.ndarray) -> None:
        lo, hi, tol = self._bounds(gi)
        lo_t = np.ascontiguousarray(lo - tol, dtype=np.float64)
        hi_t = np.ascontiguousarray(hi + tol, dtype=np.float64)
        n = x.shape[0]
        index = self._index(gi) if knn else None
        mean = np.ascontiguousarray(self.mean_, dtype=np.float64)
        scale = np.ascontiguousarray(self.scale_, dtype=np.float64)
        threshold = float(self.group_threshold_[gi])

        def run(a: int, b: int) -> None:
            f = outside_ranges(x[a:b], lo_t, hi_t)
            if index is not None:
                if distances:
                    index.mean_distance(x[a:b], mean, scale, self.k, dist[a:b])
                else:
                    index.distance_beyond(x[a:b], mean, scale, self.k, threshold, dist[a:b])
                f |= dist[a:b] > threshold
            flag[a:b] = f

        if n <= _ONE_THREAD_ROWS:  # few rows: no pool to wake
            run(0, n)
        else:  # both kernels release the GIL: chunks on the pool's threads
            map_chunks(lambda a: run(a, min(a + _CHUNK, n)), range(0, n, _CHUNK))

    # -- explaining ------------------------------------------------------------
    def combination_text(self, cat_row: np.ndarray) -> str:
        """``component_type=collar, location=upset`` for a row of category codes."""
        parts = []
        for j, name in enumerate(self.cat_names_):
            code = int(cat_row[j])
            lv = self.levels_[j]
            parts.append(f"{name}={lv[code] if 0 <= code < len(lv) else code}")
        return ", ".join(parts)

    def seen_combinations(self) -> list[str]:
        """The categorical combinations of the training data, as text."""
        return [self._seen_combination(gi) for gi in range(len(self.group_codes_))]

    def _seen_combination(self, gi: int) -> str:
        """Training combination ``gi`` as text (``collar body``)."""
        c = self.group_codes_[gi]
        return " ".join(self.levels_[j][int(c[j])] for j in range(len(self.cat_names_)))

    def _why(self, x_row: np.ndarray, dist: float, gi: int, cat_row: np.ndarray | None
             ) -> list[tuple[str, str, str]]:
        """(field, problem, allowed) for each reason a row is out of domain."""
        if gi < 0:
            combo = self.combination_text(cat_row) if cat_row is not None else "?"
            return [(self.cat_names_[0] if self.cat_names_ else "query",
                     f"{combo}: a combination the training data does not have: no answer",
                     "one of " + ", ".join(self.seen_combinations()))]
        lo, hi, tol = self._bounds(gi)
        where = (f" for {self._seen_combination(gi)}" if self.cat_names_ else "")
        out = []
        for j, name in enumerate(self.names):
            v = float(x_row[j])
            if v < lo[j] - tol[j] or v > hi[j] + tol[j]:
                what = ("design range" if self.source_[j] == "design"
                        else "training data" + ("" if "." in name else where))
                out.append((name, f"{v:.6g} is outside the surrogate's {what}: no answer",
                            f"{lo[j]:.6g} <= {name} <= {hi[j]:.6g}"))
        thr = float(self.group_threshold_[gi])
        if np.isfinite(dist) and dist > thr:
            out.append(("query", f"far from the training data{where} (kNN distance "
                        f"{dist:.3g} in standardised features): no answer",
                        f"kNN distance <= {thr:.3g}, a condition like the simulated ones"))
        return out

    def reasons(self, x: np.ndarray, dist: np.ndarray, flag: np.ndarray,
                x_cat: np.ndarray | None = None) -> np.ndarray:
        """One text per row: why it is out of domain ('' when in domain)."""
        out = np.full(x.shape[0], "", dtype=object)
        rows = np.flatnonzero(flag)
        if not rows.size:
            return out
        g = self._group_of(None if x_cat is None else np.asarray(x_cat)[rows], rows.size)
        combos = self.seen_combinations() if self.cat_names_ else []  # once, not per row
        for r, i in enumerate(rows):
            gi = int(g[r])
            if gi < 0:
                combo = self.combination_text(np.asarray(x_cat)[i])
                out[i] = f"{combo}: a combination the training data does not have"
                continue
            lo, hi, tol = self._bounds(gi)
            where = f" for {combos[gi]}" if combos else ""
            bits = []
            for j, name in enumerate(self.names):
                v = float(x[i, j])
                if v < lo[j] - tol[j] or v > hi[j] + tol[j]:
                    what = ("the design range" if self.source_[j] == "design"
                            else "the range of the training data"
                            + ("" if "." in name else where))
                    bits.append(f"{name}={v:.6g} {'below' if v < lo[j] else 'above'} {what} "
                                f"{lo[j]:.6g} .. {hi[j]:.6g}")
            thr = float(self.group_threshold_[gi])
            if np.isfinite(dist[i]) and dist[i] > thr:
                bits.append(f"far from training data{where} (kNN distance {dist[i]:.3g} "
                            f"> {thr:.3g})")
            out[i] = "; ".join(bits)
        return out

    def refusal(self, x_row: np.ndarray, dist: float, field_prefix: str = "",
                cat_row: np.ndarray | None = None) -> InputError:
        """The one-line error refusing an out-of-domain row (raw SI, shape (d,)).

        Field: the categorical feature of an unseen combination, else the
        first feature outside its range (its design range, or its group's
        training data for a derived feature), with that range as the allowed
        values; a row inside every range but far from its group's training
        data names the k-NN distance and its threshold.
        """
        gi = int(self._group_of(None if cat_row is None else np.asarray(cat_row)[None, :], 1)[0])
        why = self._why(np.asarray(x_row, dtype=np.float64), float(dist), gi, cat_row)
        if not why:  # flagged by a distance not computed here: name the threshold
            why = [("query", "far from the training data: no answer",
                    f"kNN distance <= {float(self.group_threshold_[max(gi, 0)]):.3g}")]
        field, problem, allowed = why[0]
        return InputError(field_prefix + field, problem, allowed)

    # -- persistence -----------------------------------------------------------
    def to_dict(self) -> dict:
        return {"names": self.names, "k": self.k, "quantile": self.quantile,
                "reference_rows": self.reference_rows, "seed": self.seed,
                "min": self.min_.tolist(), "max": self.max_.tolist(),
                "source": list(self.source_),
                "mean": self.mean_.tolist(), "scale": self.scale_.tolist(),
                "threshold": self.threshold_,
                "threshold_source": getattr(self, "threshold_source_", "calibration rows"),
                "categorical": self.cat_names_, "levels": self.levels_,
                "groups": [{"codes": self.group_codes_[gi].tolist(),
                            "combination": (self.combination_text(self.group_codes_[gi])
                                            if self.cat_names_ else ""),
                            "min": self.group_min_[gi].tolist(),
                            "max": self.group_max_[gi].tolist(),
                            "threshold": float(self.group_threshold_[gi]),
                            "threshold_own": bool(self.group_threshold_own_[gi]),
                            "reference_rows": int(self.group_offsets_[gi + 1]
                                                  - self.group_offsets_[gi])}
                           for gi in range(self.n_groups)]}

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
        c.cat_names_ = list(d.get("categorical", []))
        c.levels_ = [list(v) for v in d.get("levels", [])]
        groups = d.get("groups") or [{"codes": [], "min": d["min"], "max": d["max"],
                                      "threshold": d["threshold"], "threshold_own": True,
                                      "reference_rows": int(c.reference_.shape[0])}]
        c.group_codes_ = np.asarray([gr["codes"] for gr in groups], dtype=np.int64
                                    ).reshape(len(groups), -1)
        c.group_min_ = np.asarray([gr["min"] for gr in groups], dtype=np.float64)
        c.group_max_ = np.asarray([gr["max"] for gr in groups], dtype=np.float64)
        c.group_threshold_ = np.asarray([gr["threshold"] for gr in groups], dtype=np.float64)
        c.group_threshold_own_ = np.asarray([gr.get("threshold_own", True) for gr in groups])
        c.group_offsets_ = np.concatenate(
            [[0], np.cumsum([gr["reference_rows"] for gr in groups])]).astype(np.int64)
        c._set_group_keys()
        c._indexes = {}
        return c
