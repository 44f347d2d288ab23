"""Gradient boosting on the surrogate's inputs: stopped on whole cases, monotone in dogleg.

Used as a baseline by the evaluation and, with ``surrogate.served_model: gbm``,
as the served model behind the same :class:`~drillfatigue.surrogate.Surrogate`
interface. Inputs are the ensemble's encoding (:func:`design_matrix`):
standardised numeric features and one-hot categorical levels.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

import numpy as np
import pandas as pd
from sklearn.ensemble import HistGradientBoostingRegressor
from sklearn.model_selection import GroupShuffleSplit

from drillfatigue.config.surrogate import SurrogateConfig
from drillfatigue.errors import InputError
from drillfatigue.surrogate.kernels import (Design, LeafMasks, Outputs, RankedTrees, Ranks, Trees,
                                            forest_sum, forest_sum_leafmask, forest_sum_ranked)
from drillfatigue.surrogate.model import Preprocessor
from drillfatigue.surrogate.parallel import map_chunks

_CHUNK_ROWS = 8192  # rows per worker call of the tree evaluator
_ONE_THREAD_ROWS = 2048  # up to this many rows, evaluate on the calling thread

#: inputs in which damage may not decrease (docs/surrogate.md, "Monotone in dogleg")
MONOTONE_FEATURES = ("local_dls_deg_per_30m", "local_max_dls_deg_per_30m")


def design_matrix(pre: Preprocessor, x_num: np.ndarray, x_cat: np.ndarray) -> np.ndarray:
    """Standardised numeric features then one-hot levels, shape (n, d)."""
    blocks = [(np.asarray(x_num, dtype=np.float64) - pre.mean_) / pre.scale_]
    for j, col in enumerate(pre.categorical):
        blocks.append((x_cat[:, j:j + 1] == np.arange(len(pre.categories_[col]))).astype(float))
    return np.hstack(blocks)


def monotone_constraints(pre: Preprocessor, features: Sequence[str] = MONOTONE_FEATURES
                         ) -> np.ndarray:
    """scikit-learn ``monotonic_cst`` over :func:`design_matrix` columns (1: non-decreasing)."""
    n = len(pre.numeric) + sum(len(pre.categories_[c]) for c in pre.categorical)
    cst = np.zeros(n, dtype=np.int64)
    for f in features:
        if f in pre.numeric:
            cst[pre.numeric.index(f)] = 1
    return cst


def _loss(y: np.ndarray, mu: np.ndarray, censor_below: float | None) -> float:
    """Mean squared error; a censored row (y <= level) only counts mu above the level."""
    if censor_below is None:
        return float(np.mean((mu - y) ** 2))
    err = np.where(y <= censor_below, np.maximum(mu - censor_below, 0.0), mu - y)
    return float(np.mean(err**2))


def fit_gbm(x: np.ndarray, y: np.ndarray, groups: np.ndarray, cfg: SurrogateConfig,
            monotone: np.ndarray | None = None) -> tuple[HistGradientBoostingRegressor,
                                                          dict[str, Any]]:
    """Gradient boosting with early stopping on whole cases.

    scikit-learn's own early stopping holds out random rows, so rows of one
    case land on both sides and the stopping point is set by near-copies of
    training rows. Here a seeded fraction ``cfg.validation_fraction`` of the
    training *cases* is held out (``GroupShuffleSplit`` on ``groups``); the
    model is grown to ``cfg.hgb_max_iter`` trees on the rest, the number of
    trees with the least validation loss (squared error; a censored row, life
    beyond ``cfg.horizon_h``, counts only a prediction above its level, as in
    the ensemble's validation) is kept, and the model is refitted with that
    many trees on all training rows.

    Parameters
    ----------
    x : ndarray, shape (n, d)
        Encoded inputs (:func:`design_matrix`).
    y : ndarray, shape (n,)
        log10 damage rate per hour.
    groups : ndarray, shape (n,)
        Case id per row.
    cfg : SurrogateConfig
    monotone : ndarray of int, shape (d,), optional
        scikit-learn ``monotonic_cst`` (1: non-decreasing in that input).

    Returns
    -------
    model, info
        The refitted ``HistGradientBoostingRegressor``; ``info`` with
        ``n_iter`` (trees kept), ``val_loss`` (its validation loss) and
        ``n_val_cases``.
    """
    censor = -math.log10(cfg.horizon_h) if cfg.censoring == "likelihood" else None
    kw = {"random_state": cfg.split_seed, "early_stopping": False,
          "monotonic_cst": None if monotone is None else list(map(int, monotone))}
    split = GroupShuffleSplit(n_splits=1, test_size=cfg.validation_fraction,
                              random_state=cfg.split_seed)
    fit_i, val_i = next(split.split(x, y, groups))
    probe = HistGradientBoostingRegressor(max_iter=cfg.hgb_max_iter, **kw).fit(x[fit_i], y[fit_i])
    losses = [_loss(y[val_i], mu, censor) for mu in probe.staged_predict(x[val_i])]
    best = int(np.argmin(losses)) + 1
    model = HistGradientBoostingRegressor(max_iter=best, **kw).fit(x, y)
    return model, {"n_iter": best, "val_loss": float(losses[best - 1]),
                   "n_val_cases": int(pd.unique(groups[val_i]).size)}


class FlatForest:
    """The fitted trees of a gradient boosting as flat arrays, evaluated by a compiled kernel.

    scikit-learn's ``predict`` builds the design matrix (:func:`design_matrix`)
    and walks each tree with OpenMP threads; on a loaded machine the thread
    barriers dominate (measured: ~8e3 rows/s and 80 ms per single query at
    load 7 on 2 cores). Here the design matrix is never built: a compiled
    kernel standardises and one-hot encodes each row on the fly and replaces
    each input by its rank among the thresholds the trees use on it, which
    decides every split as the float value does. With at most 64 leaves per
    tree (scikit-learn's default is 31), no tree is walked:
    :func:`~drillfatigue.surrogate.kernels.forest_sum_leafmask` ANDs one
    precomputed leaf mask per input and tree and takes the leftmost leaf
    left (docs/surrogate.md, "Speed of the served model"); else
    :func:`~drillfatigue.surrogate.kernels.forest_sum_ranked` walks the
    trees on the ranks, and a chunk with a NaN input takes the float walk
    :func:`~drillfatigue.surrogate.kernels.forest_sum` (NaN has no rank).
    Chunks of rows run on the thread pool (numba releases the GIL); up to
    2048 rows on the calling thread. The result equals scikit-learn's
    prediction bit for bit (the same leaf values added in the same order to
    the same baseline; tested).

    Models fitted on the same design matrix can share one evaluator
    (``extra``: e.g. the served interval's scale model beside the
    regressor): their trees follow the first model's, each row's inputs are
    ranked once against the union of their thresholds, and :meth:`predict`
    returns one column per model, each the number that model's own
    evaluator (and scikit-learn) gives.

    Parameters
    ----------
    model : HistGradientBoostingRegressor
        Fitted, squared-error loss (identity link), one tree per iteration,
        no categorical splits.
    pre : Preprocessor
        The preprocessor whose :func:`design_matrix` the model was fitted on.
    extra : sequence of HistGradientBoostingRegressor
        Further models of the same kind on the same design matrix.
    """

    def __init__(self, model: HistGradientBoostingRegressor, pre: Preprocessor,
                 extra: Sequence[HistGradientBoostingRegressor] = ()) -> None:
        models = (model, *extra)
        nodes, roots, depth, output, offset = [], [], [], [], 0
        for o, m in enumerate(models):
            loss = getattr(m, "loss", "squared_error")
            if loss != "squared_error" or m.n_trees_per_iteration_ != 1:
                raise InputError("gbm", f"loss {loss!r} with {m.n_trees_per_iteration_} trees "
                                 "per iteration", "a squared-error regressor")
            for (tree,) in m._predictors:
                t = tree.nodes
                if np.any(t["is_categorical"]):
                    raise InputError("gbm", "categorical splits",
                                     "numeric inputs (one-hot levels)")
                roots.append(offset)
                depth.append(int(t["depth"].max()))
                output.append(o)
                nodes.append((t, offset))
                offset += t.shape[0]
        self.n_outputs = len(models)
        self.tree_output = np.asarray(output, dtype=np.int64)
        self.roots = np.asarray(roots, dtype=np.int64)
        self.depth = np.asarray(depth, dtype=np.int64)
        leaf = np.concatenate([t["is_leaf"] for t, _ in nodes]).astype(bool)
        own = np.arange(leaf.size, dtype=np.int64)
        left = np.concatenate([t["left"].astype(np.int64) + o for t, o in nodes])
        right = np.concatenate([t["right"].astype(np.int64) + o for t, o in nodes])
        # a leaf is its own child: any further step stays on it
        self.child = np.ascontiguousarray(np.stack([np.where(leaf, own, left),
                                                    np.where(leaf, own, right)], axis=1))
        self.feature = np.where(leaf, 0, np.concatenate([t["feature_idx"] for t, _ in nodes])
                                ).astype(np.int64)
        self.threshold = np.where(leaf, np.inf, np.concatenate(
            [t["num_threshold"] for t, _ in nodes])).astype(np.float64)
        self.nan_right = (~leaf) & (np.concatenate([t["missing_go_to_left"] for t, _ in nodes])
                                    == 0)
        self.value = np.concatenate([t["value"] for t, _ in nodes]).astype(np.float64)
        self.baselines = np.asarray([float(np.asarray(m._baseline_prediction).ravel()[0])
                                     for m in models], dtype=np.float64)
        self.baseline = float(self.baselines[0])
        col_cat, col_index, col_level = [], [], []
        for c in range(len(pre.numeric)):
            col_cat.append(0)
            col_index.append(c)
            col_level.append(0)
        for c, name in enumerate(pre.categorical):
            for level in range(len(pre.categories_[name])):
                col_cat.append(1)
                col_index.append(c)
                col_level.append(level)
        for m in models:
            if len(col_cat) != m.n_features_in_:
                raise InputError("gbm", f"fitted on {m.n_features_in_} inputs, the preprocessor "
                                 f"gives {len(col_cat)}",
                                 "the preprocessor the model was fitted with")
        self.col_cat = np.asarray(col_cat, dtype=np.int64)
        self.col_index = np.asarray(col_index, dtype=np.int64)
        self.col_level = np.asarray(col_level, dtype=np.int64)
        self.mean = np.asarray(pre.mean_, dtype=np.float64)
        self.scale = np.asarray(pre.scale_, dtype=np.float64)
        self._rank_form()
        self._leafmask_form()

    def _rank_form(self) -> None:
        """The trees for :func:`~drillfatigue.surrogate.kernels.forest_sum_ranked`.

        Per input column the sorted distinct thresholds of its splits
        (``cuts``, column ``j`` at ``cut_start[j]:cut_start[j + 1]``); per
        node one int64 ``left << 32 | column << 16 | (m + 1)`` (``m``: the
        index of its threshold among its column's), nodes renumbered tree by
        tree in breadth-first order with the two children of a split side
        by side (right = left + 1); a leaf points to itself with rank
        threshold ``0xFFFF``.
        """
        n_cols = self.col_cat.size
        leaf = self.child[:, 0] == np.arange(self.child.shape[0])
        split = ~leaf
        cuts, starts = [], [0]
        for j in range(n_cols):
            c = np.unique(self.threshold[split & (self.feature == j)])
            cuts.append(c)
            starts.append(starts[-1] + c.size)
        if max(c.size for c in cuts) >= 0xFFFF or n_cols > 0xFFFF:
            raise InputError("gbm", "more than 65534 thresholds on one input or 65535 inputs",
                             "a histogram gradient boosting (at most 255 bins per input)")
        self.cuts = np.concatenate(cuts).astype(np.float64)
        self.cut_start = np.asarray(starts, dtype=np.int64)
        packed = np.empty(self.child.shape[0], dtype=np.int64)
        value = np.empty(self.child.shape[0], dtype=np.float64)
        roots = np.empty_like(self.roots)
        new = 0
        for t, root in enumerate(self.roots):
            roots[t] = new
            queue, place = [int(root)], {int(root): new}
            new += 1
            while queue:
                old = queue.pop(0)
                me = place[old]
                value[me] = self.value[old]
                if leaf[old]:
                    packed[me] = (me << 32) | 0xFFFF
                    continue
                j = int(self.feature[old])
                m = int(np.searchsorted(cuts[j], self.threshold[old]))
                left, right = int(self.child[old, 0]), int(self.child[old, 1])
                place[left], place[right] = new, new + 1
                packed[me] = (new << 32) | (j << 16) | (m + 1)
                new += 2
                queue += [left, right]
        self.packed = packed[:new]
        self.leaf_value = value[:new]
        self.ranked_roots = roots

    def _leafmask_form(self) -> None:
        """The trees for :func:`~drillfatigue.surrogate.kernels.forest_sum_leafmask`.

        Leaves numbered left to right per tree; for each column ``j`` and rank
        ``r`` (0 to the column's number of thresholds) the row
        ``masks[mask_start[j] + r]`` holds per tree the AND of the leaf masks
        (all bits but the left subtree's leaves) of its splits on ``j`` whose
        threshold index is below ``r``: uint32 words when no tree has more
        than 32 leaves (scikit-learn's default grows at most 31; half the
        bytes read per row), else uint64. None (``masks`` is None) when a
        tree has more than 64 leaves: the rank walk evaluates it. Also the
        rank guesses of :meth:`_rank_grid`.
        """
        leaf = self.child[:, 0] == np.arange(self.child.shape[0])
        widths = np.diff(self.cut_start)
        self.mask_start = np.concatenate([[0], np.cumsum(widths + 1)]).astype(np.int64)
        masks = np.full((int(self.mask_start[-1]), self.n_trees), np.uint64(2**64 - 1),
                        dtype=np.uint64)
        leaf_value = np.zeros((self.n_trees, 64))
        most = 0
        for t, root in enumerate(self.roots):
            # in-order walk: the leaves of a subtree are a run [first, end) of numbers
            first: dict[int, int] = {}
            end: dict[int, int] = {}
            stack, count = [(int(root), False)], 0
            while stack:
                k, done = stack.pop()
                if leaf[k]:
                    if count == 64:
                        self.masks = None
                        return
                    first[k], end[k] = count, count + 1
                    leaf_value[t, count] = self.value[k]
                    count += 1
                elif done:
                    first[k] = first[int(self.child[k, 0])]
                    end[k] = end[int(self.child[k, 1])]
                else:
                    stack += [(k, True), (int(self.child[k, 1]), False),
                              (int(self.child[k, 0]), False)]
            most = max(most, count)
            for k in first:
                if leaf[k]:
                    continue
                left = int(self.child[k, 0])
                bits = ((1 << (end[left] - first[left])) - 1) << first[left]
                j = int(self.feature[k])
                m = int(np.searchsorted(self.cuts[self.cut_start[j]:self.cut_start[j + 1]],
                                        self.threshold[k]))
                masks[self.mask_start[j] + m + 1, t] &= np.uint64(~bits & (2**64 - 1))
        for j in range(widths.size):
            a, b = self.mask_start[j], self.mask_start[j + 1]
            masks[a:b] = np.bitwise_and.accumulate(masks[a:b], axis=0)
        words: np.ndarray = masks
        if most <= 32:  # the upper 32 bits name no leaf
            words = np.ascontiguousarray(masks & np.uint64(2**32 - 1), dtype=np.uint32)
            leaf_value = np.ascontiguousarray(leaf_value[:, :32])
        self.masks = words
        self.leaf_mask_value = leaf_value
        self._rank_grid()

    def _rank_grid(self, cells_per_threshold: int = 4) -> None:
        """Rank guesses: per input column a uniform grid over its threshold range.

        Column ``j`` with ``m >= 2`` distinct thresholds spanning a positive
        width gets ``4 m`` cells from its first threshold (``grid_lo[j]``,
        ``grid_inv[j]`` cells per unit), others one cell; ``grid_rank`` holds,
        from ``grid_start[j]``, the rank (absolute index into ``cuts``) of each
        cell's lower edge. The kernel steps from that guess to the exact rank,
        a few steps where thresholds crowd (scikit-learn bins split values
        1e-16 apart, so no grid isolates them all).
        """
        n_cols = self.cut_start.size - 1
        self.grid_lo = np.zeros(n_cols)
        self.grid_inv = np.zeros(n_cols)
        starts, ranks = [0], []
        for j in range(n_cols):
            a, b = int(self.cut_start[j]), int(self.cut_start[j + 1])
            c = self.cuts[a:b]
            cells = 1
            if b - a >= 2 and c[-1] > c[0]:
                cells = cells_per_threshold * (b - a)
                self.grid_lo[j] = c[0]
                self.grid_inv[j] = cells / (c[-1] - c[0])
                edges = c[0] + np.arange(cells) * ((c[-1] - c[0]) / cells)
                ranks.append(a + np.searchsorted(c, edges, side="left"))
            else:
                ranks.append(np.array([a]))
            starts.append(starts[-1] + cells)
        self.grid_start = np.asarray(starts, dtype=np.int64)
        self.grid_rank = np.concatenate(ranks).astype(np.int64)

    @property
    def n_trees(self) -> int:
        return int(self.roots.size)

    def _run(self, x_num: np.ndarray, x_cat: np.ndarray, out: np.ndarray) -> None:
        design = Design(self.mean, self.scale, self.col_cat, self.col_index, self.col_level)
        outputs = Outputs(self.tree_output, self.baselines)
        if np.isnan(x_num).any():  # NaN has no rank: the float walk, which knows its side
            trees = Trees(self.feature, self.threshold, self.child, self.nan_right, self.value,
                          self.roots, self.depth)
            forest_sum(x_num, x_cat, design, trees, outputs, out)
            return
        ranks = Ranks(self.cuts, self.cut_start)
        if self.masks is not None:
            leafmasks = LeafMasks(self.mask_start, self.masks, self.leaf_mask_value,
                                  self.grid_lo, self.grid_inv, self.grid_start, self.grid_rank)
            forest_sum_leafmask(x_num, x_cat, design, ranks, leafmasks, outputs, out)
            return
        ranked = RankedTrees(self.packed, self.leaf_value, self.ranked_roots, self.depth)
        forest_sum_ranked(x_num, x_cat, design, ranks, ranked, outputs, out)

    def predict(self, x_num: np.ndarray, x_cat: np.ndarray) -> np.ndarray:
        """Prediction from raw numeric features (n, n_numeric) and level codes.

        Shape (n,) for a forest of one model, (n, n_models) with ``extra``
        models (column 0 the first model's).
        """
        x_num = np.ascontiguousarray(x_num, dtype=np.float64)
        x_cat = np.ascontiguousarray(x_cat, dtype=np.int64).reshape(x_num.shape[0], -1)
        n = x_num.shape[0]
        out2 = np.empty((n, self.n_outputs))
        out = out2[:, 0] if self.n_outputs == 1 else out2
        if n <= _ONE_THREAD_ROWS:
            self._run(x_num, x_cat, out2)
            return out

        def run(a: int) -> None:
            b = a + _CHUNK_ROWS
            self._run(x_num[a:b], x_cat[a:b], out2[a:b])

        map_chunks(run, range(0, n, _CHUNK_ROWS))
        return out
