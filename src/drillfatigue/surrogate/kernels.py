"""Numba kernels of the surrogate package (numpy/numba only, STYLE.md habit 1).

The forest kernels take their arrays in named bundles (numba compiles a field
access to a plain array access; the caller passes the arrays it holds, no copies):

:data:`Design`
    How the model's input column ``j`` is built from a row: per numeric
    feature ``mean``, ``scale`` (float64); per input column ``col_cat`` (0
    numeric, 1 one-hot level), ``col_index`` (the feature) and ``col_level``
    (the level of a one-hot column), int64.
:data:`Outputs`
    Which output each tree adds to, ``tree_output`` (n_trees,) int64, and each
    output's ``baseline`` (n_outputs,) float64.
:data:`Trees`
    The trees as nodes for the float walk of :func:`forest_sum`: ``feature``,
    ``threshold``, ``child`` (n_nodes, 2), ``nan_right``, leaf ``value``, and
    per tree its ``roots`` node and ``depth``.
:data:`Ranks`
    Per input column the sorted distinct split thresholds ``cuts``, column ``j``
    at ``cut_start[j]:cut_start[j + 1]``.
:data:`RankedTrees`
    The trees as packed nodes for :func:`forest_sum_ranked`: ``packed``,
    ``value``, ``roots``, ``depth``.
:data:`LeafMasks`
    The leaf masks of :func:`forest_sum_leafmask` (``mask_start``, ``masks``,
    ``leaf_value``) and its rank guesses (``grid_lo``, ``grid_inv``,
    ``grid_start``, ``grid_rank``).
"""

from __future__ import annotations

import math
from collections import namedtuple

import numpy as np
from numba import njit
from numba.cpython.unsafe.numbers import trailing_zeros

__all__ = ["Design", "LeafMasks", "Outputs", "RankedTrees", "Ranks", "Trees", "forest_sum",
           "forest_sum_leafmask", "forest_sum_ranked", "knn_mean_distance", "knn_within",
           "outside_ranges"]

Design = namedtuple("Design", ("mean", "scale", "col_cat", "col_index", "col_level"))
Outputs = namedtuple("Outputs", ("tree_output", "baseline"))
Trees = namedtuple("Trees", ("feature", "threshold", "child", "nan_right", "value", "roots",
                             "depth"))
Ranks = namedtuple("Ranks", ("cuts", "cut_start"))
RankedTrees = namedtuple("RankedTrees", ("packed", "value", "roots", "depth"))
LeafMasks = namedtuple("LeafMasks", ("mask_start", "masks", "leaf_value", "grid_lo", "grid_inv",
                                     "grid_start", "grid_rank"))


@njit(cache=True, nogil=True)
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


_BLOCK = 128  # rows walked down a tree level by level together


@njit(cache=True, nogil=True)
def _design_value(x_num: np.ndarray, x_cat: np.ndarray, mean: np.ndarray, scale: np.ndarray,
                  col_cat: np.ndarray, col_index: np.ndarray, col_level: np.ndarray,
                  r: int, j: int) -> float:
    """Input column ``j`` of row ``r`` as the design matrix builds it: the standardised
    numeric feature, or the one-hot level (1.0 or 0.0) of a categorical one."""
    c = col_index[j]
    if col_cat[j] == 0:
        return (x_num[r, c] - mean[c]) / scale[c]
    if x_cat[r, c] == col_level[j]:
        return 1.0
    return 0.0


@njit(cache=True, nogil=True)
def _rank(cuts: np.ndarray, lo: int, hi: int, v: float) -> int:
    """Index of the first of the sorted thresholds ``cuts[lo:hi]`` that is >= ``v``
    (``lo`` + the count of thresholds below ``v``)."""
    while lo < hi:
        mid = (lo + hi) >> 1
        if cuts[mid] < v:
            lo = mid + 1
        else:
            hi = mid
    return lo


@njit(cache=True, nogil=True)
def forest_sum(x_num: np.ndarray, x_cat: np.ndarray, design: Design, trees: Trees,
               outputs: Outputs, out: np.ndarray) -> None:
    """Sums of the leaf values of forests of binary regression trees, per row, into ``out``.

    The model's input column ``j`` is built per row as the gradient boosting's
    design matrix builds it: a standardised numeric feature
    ``(x_num[i, c] - mean[c]) / scale[c]`` with ``c = col_index[j]`` when
    ``col_cat[j] == 0``, else the one-hot level ``1.0`` if ``x_cat[i,
    col_index[j]] == col_level[j]`` (``0.0`` otherwise). A node sends a row to
    ``child[k, 1]`` when its input is ``> threshold[k]`` or NaN with
    ``nan_right[k]``, else to ``child[k, 0]``, as scikit-learn's histogram
    gradient boosting does on raw inputs; a leaf is its own child (threshold
    +inf), so ``depth[t]`` steps from ``roots[t]`` end on every row's leaf.

    Several models can share one pass (their inputs ranked or built once):
    tree ``t`` belongs to output ``tree_output[t]``, whose sum starts from
    ``baseline[o]``; ``out`` is (n, n_outputs).

    Rows go down each tree in blocks, one level at a time for the whole block:
    the steps of different rows do not wait on each other, and no branch
    depends on where a row goes (measured 2x the throughput of walking one row
    to its leaf after the other). Leaf values are added to their output's
    ``baseline`` tree by tree, in the model's order, so each sum is
    scikit-learn's float64 number for that model.
    """
    mean, scale, col_cat, col_index, col_level = design
    feature, threshold, child, nan_right, value, roots, depth = trees
    tree_output, baseline = outputs
    n = x_num.shape[0]
    n_cols = col_cat.shape[0]
    n_trees = roots.shape[0]
    n_out = baseline.shape[0]
    z = np.empty((_BLOCK, n_cols))
    acc = np.empty((n_out, _BLOCK))
    node = np.empty(_BLOCK, dtype=np.int64)
    for b in range(0, n, _BLOCK):
        m = min(_BLOCK, n - b)
        for i in range(m):
            for j in range(n_cols):
                z[i, j] = _design_value(x_num, x_cat, mean, scale, col_cat, col_index,
                                        col_level, b + i, j)
        for o in range(n_out):
            for i in range(m):
                acc[o, i] = baseline[o]
        for t in range(n_trees):
            o = tree_output[t]
            root = roots[t]
            for i in range(m):
                node[i] = root
            for _ in range(depth[t]):
                for i in range(m):
                    k = node[i]
                    v = z[i, feature[k]]
                    right = (v > threshold[k]) | (math.isnan(v) & nan_right[k])
                    node[i] = child[k, 1] if right else child[k, 0]
            for i in range(m):
                acc[o, i] += value[node[i]]
        for o in range(n_out):
            for i in range(m):
                out[b + i, o] = acc[o, i]


_LEAF = 0xFFFF  # rank "threshold" of a leaf: above every rank, so a leaf never goes right


@njit(cache=True, nogil=True)
def forest_sum_ranked(x_num: np.ndarray, x_cat: np.ndarray, design: Design, ranks: Ranks,
                      trees: RankedTrees, outputs: Outputs, out: np.ndarray) -> None:
    """:func:`forest_sum` on rows without NaN, with each input replaced by its rank.

    Input column ``j`` is built per row as in :func:`forest_sum`, then
    replaced by its rank: the number of the column's distinct split
    thresholds ``cuts[cut_start[j]:cut_start[j + 1]]`` (sorted, strictly
    increasing) that lie below it. With ``t_m`` the ``m``-th threshold,
    ``v > t_m`` exactly when ``rank(v) >= m + 1``, so comparing ranks
    sends every row where comparing the float64 values does. A node is one
    int64 ``packed[k] = left << 32 | column << 16 | (m + 1)`` whose right
    child is ``left + 1``; a leaf is its own left child with rank
    threshold ``0xFFFF``, above every rank. A step is then two loads (the
    node, the row's rank) instead of five, on one cache line per node.
    Leaf values are added to their output's ``baseline`` tree by tree in the
    model's order (``tree_output``, ``out`` as there): the sums are
    :func:`forest_sum`'s (and scikit-learn's) float64 numbers. A NaN input
    has no rank: such rows go to :func:`forest_sum`.
    """
    mean, scale, col_cat, col_index, col_level = design
    cuts, cut_start = ranks
    packed, value, roots, depth = trees
    tree_output, baseline = outputs
    n = x_num.shape[0]
    n_cols = col_cat.shape[0]
    n_trees = roots.shape[0]
    n_out = baseline.shape[0]
    rank = np.empty((_BLOCK, n_cols), dtype=np.int64)
    acc = np.empty((n_out, _BLOCK))
    node = np.empty(_BLOCK, dtype=np.int64)
    for b in range(0, n, _BLOCK):
        m = min(_BLOCK, n - b)
        for i in range(m):
            for j in range(n_cols):
                v = _design_value(x_num, x_cat, mean, scale, col_cat, col_index, col_level,
                                  b + i, j)
                rank[i, j] = _rank(cuts, cut_start[j], cut_start[j + 1], v) - cut_start[j]
        for o in range(n_out):
            for i in range(m):
                acc[o, i] = baseline[o]
        for t in range(n_trees):
            o = tree_output[t]
            root = roots[t]
            for i in range(m):
                node[i] = root
            for _ in range(depth[t]):
                for i in range(m):
                    w = packed[node[i]]
                    node[i] = (w >> 32) + (rank[i, (w >> 16) & 0xFFFF] >= (w & 0xFFFF))
            for i in range(m):
                acc[o, i] += value[node[i]]
        for o in range(n_out):
            for i in range(m):
                out[b + i, o] = acc[o, i]


_ROWS = 32  # rows whose ranks, leaf masks and sums are formed together


@njit(cache=True, nogil=True)
def _rank_near(cuts: np.ndarray, lo: int, hi: int, r: int, v: float) -> int:
    """:func:`_rank` found by steps from a guess ``r`` in ``[lo, hi]``: exact for any guess."""
    while r < hi and cuts[r] < v:
        r += 1
    while r > lo and cuts[r - 1] >= v:
        r -= 1
    return r


@njit(cache=True, nogil=True)
def forest_sum_leafmask(x_num: np.ndarray, x_cat: np.ndarray, design: Design, ranks: Ranks,
                        leafmasks: LeafMasks, outputs: Outputs, out: np.ndarray) -> None:
    """:func:`forest_sum` on rows without NaN, by leaf masks: no tree is walked.

    The leaves of each tree (at most 32 with uint32 ``masks``, 64 with
    uint64) are numbered left to right; a split that sends a row right
    rules out the leaves of its left subtree, and the leaf a row reaches is
    the leftmost leaf no split on its path rules out (QuickScorer, Lucchese
    et al., SIGIR 2015: a split off the path rules out only leaves left of
    the path's leaf, or ones its path already left). Which splits send a
    row right depends, per input column, only on the row's rank (the count
    of the column's thresholds below its value, as in
    :func:`forest_sum_ranked`): ``masks[mask_start[j] + rank, t]`` is the
    AND of the leaf masks of tree ``t``'s splits on column ``j`` whose
    threshold lies below the value. A row is then one AND per column and
    tree (contiguous over trees: vectorised), and the lowest set bit per
    tree picks ``leaf_value[t, leaf]``, added to its output's ``baseline``
    tree by tree in the model's order (``tree_output``, ``out`` as in
    :func:`forest_sum`: the models of one pass share the ranks and the
    per-row work): the sums are :func:`forest_sum`'s float64 numbers.

    Rows go in blocks of 32, column by column for the ranks (the column's
    constants loaded once), four columns' masks per pass over the trees,
    and tree by tree over the block for the sums (32 independent additions
    in flight instead of one chain). A numeric column's rank starts from a
    guess on a uniform grid of its threshold range (``grid_start[j + 1] -
    grid_start[j]`` cells from ``grid_lo[j]``, ``grid_inv[j]`` cells per
    unit; ``grid_rank`` holds the absolute rank at each cell's lower edge)
    and ends by steps (:func:`_rank_near`), so it is exact whatever the
    guess; a one-hot column has two ranks, that of 1.0 and of 0.0.
    """
    mean, scale, col_cat, col_index, col_level = design
    cuts, cut_start = ranks
    mask_start, masks, leaf_value, grid_lo, grid_inv, grid_start, grid_rank = leafmasks
    tree_output, baseline = outputs
    n = x_num.shape[0]
    n_cols = col_cat.shape[0]
    n_trees = masks.shape[1]
    active = np.empty(n_cols, dtype=np.int64)
    n_active = 0
    for j in range(n_cols):
        if cut_start[j + 1] > cut_start[j]:  # a column no split uses changes no mask
            active[n_active] = j
            n_active += 1
    n_out = baseline.shape[0]
    row = np.empty((_ROWS, max(n_active, 1)), dtype=np.int64)
    alive = np.empty((_ROWS, n_trees), dtype=masks.dtype)
    acc = np.empty((n_out, _ROWS))
    for b in range(0, n, _ROWS):
        m = min(_ROWS, n - b)
        for q in range(n_active):
            j = active[q]
            lo = cut_start[j]
            hi = cut_start[j + 1]
            c = col_index[j]
            shift = mask_start[j] - lo
            if col_cat[j] == 0:
                mu = mean[c]
                sc = scale[c]
                g0 = grid_lo[j]
                inv = grid_inv[j]
                gs = grid_start[j]
                cells = grid_start[j + 1] - gs
                for i in range(m):
                    v = (x_num[b + i, c] - mu) / sc
                    t = (v - g0) * inv
                    cell = 0
                    if t >= 0.0:  # also false for NaN (a zero-width grid times inf)
                        cell = int(t) if t < cells else cells - 1
                    row[i, q] = shift + _rank_near(cuts, lo, hi, grid_rank[gs + cell], v)
            else:
                level = col_level[j]
                r1 = shift + _rank(cuts, lo, hi, 1.0)
                r0 = shift + _rank(cuts, lo, hi, 0.0)
                for i in range(m):
                    row[i, q] = r1 if x_cat[b + i, c] == level else r0
        for i in range(m):
            if n_active == 0:
                for t in range(n_trees):
                    alive[i, t] = masks[0, t]
            q = n_active % 4
            if q > 0:
                r0 = row[i, 0]
                for t in range(n_trees):
                    alive[i, t] = masks[r0, t]
                for p in range(1, q):
                    rp = row[i, p]
                    for t in range(n_trees):
                        alive[i, t] &= masks[rp, t]
            elif n_active > 0:
                r0, r1, r2, r3 = row[i, 0], row[i, 1], row[i, 2], row[i, 3]
                for t in range(n_trees):
                    alive[i, t] = masks[r0, t] & masks[r1, t] & masks[r2, t] & masks[r3, t]
                q = 4
            while q < n_active:
                r0, r1, r2, r3 = row[i, q], row[i, q + 1], row[i, q + 2], row[i, q + 3]
                for t in range(n_trees):
                    alive[i, t] &= masks[r0, t] & masks[r1, t] & masks[r2, t] & masks[r3, t]
                q += 4
        for o in range(n_out):
            for i in range(m):
                acc[o, i] = baseline[o]
        for t in range(n_trees):
            o = tree_output[t]
            for i in range(m):
                # trailing_zeros is a numba intrinsic (cttz): mypy sees its typing-time signature
                acc[o, i] += leaf_value[t, trailing_zeros(alive[i, t])]  # type: ignore[call-arg, index]
        for o in range(n_out):
            for i in range(m):
                out[b + i, o] = acc[o, i]


@njit(cache=True, nogil=True)
def _insert(best: np.ndarray, s: float, times: int) -> None:
    """Insert ``s`` up to ``times`` times into the ascending ``best`` (dropping the largest)."""
    k = best.shape[0]
    for _ in range(times):
        if s >= best[k - 1]:
            return
        q = k - 1
        while q > 0 and best[q - 1] > s:
            best[q] = best[q - 1]
            q -= 1
        best[q] = s


@njit(cache=True, nogil=True)
def _scan_group(z: np.ndarray, n_key: int, base: float, rest: np.ndarray, count: np.ndarray,
                a: int, b: int, best: np.ndarray) -> None:
    """Offer rows ``a:b`` of ``rest`` (sorted by column 0) at key distance ``base`` to ``best``.

    Walks outward from the query's place in column 0, nearer side first:
    ``base + e0^2`` only grows on the way out, and once it reaches the k-th
    best no further row can enter.
    """
    k = best.shape[0]
    d_rest = rest.shape[1]
    if d_rest == 0:
        for r in range(a, b):
            _insert(best, base, count[r])
        return
    z0 = z[n_key]
    lo = a
    hi = b
    while lo < hi:
        mid = (lo + hi) >> 1
        if rest[mid, 0] < z0:
            lo = mid + 1
        else:
            hi = mid
    down = lo - 1
    up = lo
    while down >= a or up < b:
        if up >= b or (down >= a and z0 - rest[down, 0] <= rest[up, 0] - z0):
            r = down
            down -= 1
        else:
            r = up
            up += 1
        e = z0 - rest[r, 0]
        s = base + e * e
        if s >= best[k - 1]:
            return
        for j in range(1, d_rest):
            e = z[n_key + j] - rest[r, j]
            s += e * e
            if s >= best[k - 1]:
                break
        if s < best[k - 1]:
            _insert(best, s, count[r])


@njit(cache=True, nogil=True)
def _scan_rows(z: np.ndarray, n_key: int, base: float, rest_t: np.ndarray, count: np.ndarray,
               a: int, b: int, acc: np.ndarray, best: np.ndarray) -> None:
    """Offer reference rows ``a:b`` at key distance ``base`` to ``best``.

    The squared distances of the rows are summed one rest column at a time
    over all of them (a loop without branches, vectorised), ``base`` first,
    then the rest columns in order; a row below the k-th best enters
    ``count[r]`` times at most.
    """
    k = best.shape[0]
    m = b - a
    for r in range(m):
        acc[r] = base
    for j in range(rest_t.shape[0]):
        zj = z[n_key + j]
        for r in range(m):
            e = zj - rest_t[j, a + r]
            acc[r] += e * e
    for r in range(m):
        if acc[r] < best[k - 1]:
            _insert(best, acc[r], count[a + r])


@njit(cache=True, nogil=True)
def _mean_root(best: np.ndarray) -> float:
    """Mean of the square roots of ``best`` (ascending), summed in that order."""
    total = 0.0
    for q in range(best.shape[0]):
        total += math.sqrt(best[q])
    return total / best.shape[0]


@njit(cache=True, nogil=True)
def _argmin_open(v: np.ndarray, n: int) -> int:
    """Index of the least of ``v[:n]`` (the first on ties; 0 if none is less than ``v[0]``)."""
    m = 0
    least = v[0]
    for s in range(1, n):  # selects, no branch on the data
        w = v[s]
        better = w < least
        m = s if better else m
        least = w if better else least
    return m


@njit(cache=True, nogil=True)
def _group_bounds(z: np.ndarray, n_key: int, keys_t: np.ndarray, box_lo: np.ndarray,
                  box_hi: np.ndarray, a: int, m: int, kd: np.ndarray, lb: np.ndarray) -> None:
    """Key part ``kd[h]`` and lower bound ``lb[h]`` of the squared distance to groups ``a + h``.

    ``kd``: the squared key differences summed in column order; ``lb``: that
    plus the squared gaps to the group's rest box, in column order.
    """
    for h in range(m):
        kd[h] = 0.0
    for j in range(n_key):
        zj = z[j]
        for h in range(m):
            e = zj - keys_t[j, a + h]
            kd[h] += e * e
    for h in range(m):
        lb[h] = kd[h]
    for j in range(box_lo.shape[0]):
        zj = z[n_key + j]
        for h in range(m):  # gap below, above, or 0 inside (no branch)
            e = max(max(box_lo[j, a + h] - zj, zj - box_hi[j, a + h]), 0.0)
            lb[h] += e * e


@njit(cache=True, nogil=True)
def _group_bounds_rows(z: np.ndarray, n_key: int, group_lo: np.ndarray, group_hi: np.ndarray,
                       a: int, m: int, kd: np.ndarray, lb: np.ndarray) -> None:
    """:func:`_group_bounds` from the groups' boxes as rows (``group_lo[g]``, ``group_hi[g]``:
    all columns, a key column's bounds both its key), group by group: the same floats,
    for the few groups of one super-group (no short vector loop per column)."""
    d = group_lo.shape[1]
    for h in range(m):
        g = a + h
        s = 0.0
        for j in range(n_key):
            e = z[j] - group_lo[g, j]
            s += e * e
        kd[h] = s
        for j in range(n_key, d):
            e = max(max(group_lo[g, j] - z[j], z[j] - group_hi[g, j]), 0.0)
            s += e * e
        lb[h] = s


@njit(cache=True, nogil=True)
def knn_mean_distance(x: np.ndarray, mean: np.ndarray, scale: np.ndarray, perm: np.ndarray,
                      n_key: int, keys_t: np.ndarray, group_start: np.ndarray,
                      rest: np.ndarray, rest_t: np.ndarray, box_lo: np.ndarray,
                      box_hi: np.ndarray, count: np.ndarray, k: int, out: np.ndarray) -> None:
    """Mean Euclidean distance of each row to its ``k`` nearest reference rows, into ``out``.

    Exact k-nearest-neighbour search in standardised space over a reference
    stored as groups: the query row ``i`` is standardised
    ``(x[i, c] - mean[c]) / scale[c]`` and its columns reordered by ``perm``;
    the first ``n_key`` reordered columns are a group's key (``keys_t[:, g]``,
    shared by every row of group ``g``), the others are each distinct
    reference row's ``rest[r]`` (``rest_t`` is its transpose; rows
    ``group_start[g]`` to ``group_start[g + 1]`` belong to group ``g``,
    sorted by ``rest[:, 0]``), ``box_lo[:, g]``/``box_hi[:, g]`` bound the
    rest columns of group ``g``'s rows, and ``count[r]`` is how many
    reference rows equal row ``r``.

    A squared distance is summed key columns first, then the rest in column
    order. Each group's lower bound is its key part plus the squared gaps
    between the query and the group's bounding box. The group with the least
    bound is scanned first, row by row outward from the query's place in
    rest column 0 (a tight k-th best after a few rows for a query near the
    reference); then every other group whose bound is below the k-th best
    is scanned whole, one column at a time over its rows (vectorised).
    Rounding is monotone, so neither a bound nor a partial sum exceeds the
    float sum it bounds: a group or row ruled out by reaching the k-th best
    could not have entered. The ``k`` best squared distances are kept
    sorted by insertion (a row counted ``count[r]`` times enters up to that
    many times), no sort of all distances. The result is the brute-force
    mean of the ``k`` smallest distances, summed in another column order
    (equal to rounding).
    """
    n = x.shape[0]
    d = perm.shape[0]
    n_groups = keys_t.shape[1]
    z = np.empty(d)
    kd = np.empty(n_groups)
    lb = np.empty(n_groups)
    acc = np.empty(rest.shape[0])
    best = np.empty(k)
    for i in range(n):
        for j in range(d):
            c = perm[j]
            z[j] = (x[i, c] - mean[c]) / scale[c]
        _group_bounds(z, n_key, keys_t, box_lo, box_hi, 0, n_groups, kd, lb)
        g0 = 0
        for g in range(1, n_groups):
            if lb[g] < lb[g0]:
                g0 = g
        for q in range(k):
            best[q] = np.inf
        _scan_group(z, n_key, kd[g0], rest, count, group_start[g0], group_start[g0 + 1], best)
        for g in range(n_groups):
            if g == g0 or lb[g] >= best[k - 1]:
                continue
            _scan_rows(z, n_key, kd[g], rest_t, count, group_start[g], group_start[g + 1], acc,
                       best)
        out[i] = _mean_root(best)


@njit(cache=True, nogil=True)
def knn_within(x: np.ndarray, mean: np.ndarray, scale: np.ndarray, perm: np.ndarray,
               n_key: int, group_start: np.ndarray, rest_t: np.ndarray,
               group_lo: np.ndarray, group_hi: np.ndarray, count: np.ndarray,
               super_start: np.ndarray, super_lo: np.ndarray, super_hi: np.ndarray, k: int,
               threshold: float, out: np.ndarray) -> None:
    """:func:`knn_mean_distance` where it exceeds ``threshold``, NaN where it certainly does not.

    The reference is stored as in :func:`knn_mean_distance` (``rest_t`` the
    transpose of its ``rest``), with each group's box as a row of all
    columns in the search's order, ``group_lo[g]`` to ``group_hi[g]`` (a
    key column's bounds both its key), and the groups gathered into
    super-groups: groups ``super_start[s]`` to ``super_start[s + 1]``, whose
    columns lie in the box ``super_lo[:, s]`` to ``super_hi[:, s]``. A
    super-group's lower bound is the sum of the squared gaps between the
    query and its box, in column order.

    Super-groups are visited best first (least bound first) while their
    bound is below the current k-th best, and inside one its groups best
    first likewise (a group's bound: its key part plus the squared gaps to
    its rest box, :func:`_group_bounds_rows`), each group scanned whole
    (:func:`_scan_rows`). After
    each group the search stops if the ``k`` best so far have a mean
    ``<= threshold``: sorted ascending, the i-th nearest row is at most the
    i-th of any ``k`` rows, and square root, sum and division are monotone
    in floats, so the exact result (:func:`knn_mean_distance`'s float) is
    then ``<= threshold`` too; ``out`` is NaN. A row that does not stop
    has searched every super-group and group its bound did not rule out
    (no bound exceeds the float sum it bounds: a box contains what it
    bounds, the terms are added in the same order and rounding is
    monotone): ``out`` is :func:`knn_mean_distance`'s result, the same
    float (the mean of the roots of the same ``k`` least squared
    distances, summed in ascending order), kept if it exceeds
    ``threshold``, else NaN too. A NaN input stops nowhere and gives
    ``inf``, as there.
    """
    n = x.shape[0]
    d = perm.shape[0]
    n_super = super_start.shape[0] - 1
    width = 1
    for s in range(n_super):
        width = max(width, super_start[s + 1] - super_start[s])
    rows_max = 1
    for g in range(group_start.shape[0] - 1):
        rows_max = max(rows_max, group_start[g + 1] - group_start[g])
    z = np.empty(d)
    slb = np.empty(n_super)
    kd = np.empty(width)
    glb = np.empty(width)
    acc = np.empty(rows_max)
    best = np.empty(k)
    for i in range(n):
        for j in range(d):
            c = perm[j]
            z[j] = (x[i, c] - mean[c]) / scale[c]
        for s in range(n_super):
            slb[s] = 0.0
        for j in range(d):
            zj = z[j]
            for s in range(n_super):  # gap below, above, or 0 inside (no branch)
                e = max(max(super_lo[j, s] - zj, zj - super_hi[j, s]), 0.0)
                slb[s] += e * e
        for q in range(k):
            best[q] = np.inf
        stopped = False
        while not stopped:
            s = _argmin_open(slb, n_super)
            if not slb[s] < best[k - 1]:  # also NaN (a NaN input): ends the search
                break
            slb[s] = np.inf  # visited
            g0 = super_start[s]
            ng = super_start[s + 1] - g0
            _group_bounds_rows(z, n_key, group_lo, group_hi, g0, ng, kd, glb)
            while True:
                h = _argmin_open(glb, ng)
                if not glb[h] < best[k - 1]:
                    break
                glb[h] = np.inf  # scanned
                g = g0 + h
                _scan_rows(z, n_key, kd[h], rest_t, count, group_start[g], group_start[g + 1],
                           acc, best)
                if best[k - 1] < np.inf and _mean_root(best) <= threshold:
                    stopped = True
                    break
        dist = np.nan if stopped else _mean_root(best)
        out[i] = dist if dist > threshold else np.nan  # NaN > threshold is False
