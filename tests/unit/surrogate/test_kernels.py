"""The compiled tree evaluator of the served gradient boosting against scikit-learn's predict.

Reference: ``HistGradientBoostingRegressor.predict`` on the design matrix.
Tolerance: none (``array_equal``): the evaluator does the same float64
operations in the same order (standardise, one-hot, threshold ``<=``, leaf
values added to the baseline tree by tree), so any difference is a bug.
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from sklearn.ensemble import HistGradientBoostingRegressor

from drillfatigue.config.surrogate import SurrogateConfig
from drillfatigue.errors import InputError
from drillfatigue.surrogate import make_synthetic_dataset
from drillfatigue.surrogate.data import log10_target
from drillfatigue.surrogate.gbm import FlatForest, design_matrix, fit_gbm, monotone_constraints
from drillfatigue.surrogate.kernels import _rank, _rank_near
from drillfatigue.surrogate.model import Preprocessor

CFG = SurrogateConfig(hgb_max_iter=40)


@pytest.fixture(scope="module")
def fitted():
    data = make_synthetic_dataset(16, seed=4)
    pre = Preprocessor(CFG.features, CFG.categorical).fit(data)
    x = design_matrix(pre, pre.numeric_array(data), pre.category_codes(data))
    y = log10_target(data[CFG.target_column].to_numpy(), CFG.rate_floor_per_h)
    model, _ = fit_gbm(x, y, data[CFG.group_column].astype(str).to_numpy(), CFG,
                       monotone_constraints(pre))
    return model, pre, data, FlatForest(model, pre)


def test_equals_sklearn_on_the_data_and_far_outside_it(fitted):
    model, pre, data, forest = fitted
    assert forest.n_trees == model.n_iter_
    x_num, x_cat = pre.numeric_array(data), pre.category_codes(data)
    ref = model.predict(design_matrix(pre, x_num, x_cat))
    # one thread (small batch) and chunked over threads (large batch)
    assert np.array_equal(forest.predict(x_num[:100], x_cat[:100]), ref[:100])
    big_num = np.tile(x_num, (max(1, 20_000 // len(x_num) + 1), 1))
    big_cat = np.tile(x_cat, (max(1, 20_000 // len(x_num) + 1), 1))
    assert big_num.shape[0] > 16_384
    assert np.array_equal(forest.predict(big_num, big_cat),
                          model.predict(design_matrix(pre, big_num, big_cat)))
    # far outside the training ranges (every split falls one way)
    far = x_num * 10.0 - 5.0
    assert np.array_equal(forest.predict(far, x_cat), model.predict(design_matrix(pre, far, x_cat)))


def test_missing_values_follow_the_trained_side():
    rng = np.random.default_rng(0)
    x = rng.normal(size=(400, 3))
    x[rng.random((400, 3)) < 0.2] = np.nan
    y = np.nan_to_num(x[:, 0], nan=2.0) + 0.1 * rng.normal(size=400)
    model = HistGradientBoostingRegressor(max_iter=30, random_state=0).fit(x, y)
    pre = Preprocessor(["a", "b", "c"])
    pre.mean_, pre.scale_, pre.categories_ = np.zeros(3), np.ones(3), {}
    forest = FlatForest(model, pre)
    assert np.array_equal(forest.predict(x, np.zeros((400, 0), dtype=np.int64)), model.predict(x))


@settings(max_examples=25, deadline=None)
@given(st.lists(st.floats(-1e6, 1e6, allow_nan=False), min_size=13, max_size=13),
       st.lists(st.integers(0, 100), min_size=3, max_size=3))
def test_property_any_query_equals_sklearn(fitted, values, codes):
    model, pre, _, forest = fitted
    x_num = np.asarray([values[:len(pre.numeric)]], dtype=np.float64)
    levels = [len(pre.categories_[c]) for c in pre.categorical]
    x_cat = np.asarray([[c % k for c, k in zip(codes[:len(levels)], levels, strict=True)]],
                       dtype=np.int64)
    assert np.array_equal(forest.predict(x_num, x_cat),
                          model.predict(design_matrix(pre, x_num, x_cat)))


def test_refuses_a_model_it_cannot_evaluate(fitted):
    model, pre, _, _ = fitted
    with pytest.raises(InputError) as err:
        FlatForest(model, Preprocessor(pre.numeric[:3]).fit(make_synthetic_dataset(3, seed=1)))
    assert err.value.field == "gbm"
    rng = np.random.default_rng(1)
    other = HistGradientBoostingRegressor(max_iter=5, loss="absolute_error").fit(
        rng.random((50, 3)), rng.random(50))
    pre3 = Preprocessor(["a", "b", "c"])
    pre3.mean_, pre3.scale_, pre3.categories_ = np.zeros(3), np.ones(3), {}
    with pytest.raises(InputError):
        FlatForest(other, pre3)


def test_a_batch_with_a_missing_value_equals_sklearn(fitted):
    # rows go through the rank walk, except a chunk holding a NaN (NaN has no rank):
    # that chunk takes the float walk; either way scikit-learn's numbers
    model, pre, data, forest = fitted
    reps = 17_000 // len(data) + 1  # more than two chunks of 8192 rows
    x_num = np.tile(pre.numeric_array(data), (reps, 1))
    x_cat = np.tile(pre.category_codes(data), (reps, 1))
    x_num[7, 3] = np.nan
    x_num[-1, 0] = 1e300
    assert np.array_equal(forest.predict(x_num, x_cat),
                          model.predict(design_matrix(pre, x_num, x_cat)))


def test_rank_form_is_one_word_per_node(fitted):
    model, _, _, forest = fitted
    n_nodes = sum(tree.nodes.shape[0] for (tree,) in model._predictors)
    assert forest.packed.shape == (n_nodes,) and forest.leaf_value.shape == (n_nodes,)
    rank_threshold = forest.packed & 0xFFFF
    leaf = rank_threshold == 0xFFFF
    node = np.arange(n_nodes)
    # a leaf is its own left child; a split's children are side by side after it
    assert np.array_equal((forest.packed >> 32)[leaf], node[leaf])
    assert np.all((forest.packed >> 32)[~leaf] > node[~leaf])
    # a split's rank threshold names one of its column's distinct cuts
    col = (forest.packed >> 16) & 0xFFFF
    width = np.diff(forest.cut_start)
    assert np.all((rank_threshold[~leaf] >= 1) & (rank_threshold[~leaf] <= width[col[~leaf]]))


def test_trees_of_more_than_64_leaves_take_the_rank_walk():
    # leaf masks are 64-bit: a bigger tree is walked on ranks, with the same numbers
    rng = np.random.default_rng(5)
    x = rng.normal(size=(3000, 4))
    y = np.sin(3 * x[:, 0]) + x[:, 1] * x[:, 2] + 0.1 * rng.normal(size=3000)
    pre = Preprocessor(["a", "b", "c", "d"])
    pre.mean_, pre.scale_, pre.categories_ = np.zeros(4), np.ones(4), {}
    none = np.zeros((3000, 0), dtype=np.int64)
    big = HistGradientBoostingRegressor(max_iter=5, max_leaf_nodes=100, min_samples_leaf=5,
                                        random_state=0).fit(x, y)
    forest = FlatForest(big, pre)
    assert max(t.nodes["is_leaf"].sum() for (t,) in big._predictors) > 64
    assert forest.masks is None
    assert np.array_equal(forest.predict(x, none), big.predict(x))
    small = HistGradientBoostingRegressor(max_iter=5, max_leaf_nodes=64, min_samples_leaf=5,
                                          random_state=0).fit(x, y)
    forest = FlatForest(small, pre)
    assert max(t.nodes["is_leaf"].sum() for (t,) in small._predictors) == 64
    assert forest.masks is not None  # 64 leaves: the last bit of the mask in use
    assert forest.masks.dtype == np.uint64
    assert np.array_equal(forest.predict(x, none), small.predict(x))
    # 32-bit masks up to 32 leaves (the last bit in use), 64-bit from 33
    for leaves, dtype in ((32, np.uint32), (33, np.uint64)):
        model = HistGradientBoostingRegressor(max_iter=5, max_leaf_nodes=leaves,
                                              min_samples_leaf=5, random_state=0).fit(x, y)
        forest = FlatForest(model, pre)
        assert max(t.nodes["is_leaf"].sum() for (t,) in model._predictors) == leaves
        assert forest.masks.dtype == dtype
        assert np.array_equal(forest.predict(x, none), model.predict(x))


def test_queries_on_and_next_to_every_threshold_equal_sklearn(fitted):
    # the rank of a value starts from a grid guess and steps to the exact count:
    # values on each threshold and one float either side of it decide each
    # split as the float comparison does, also where thresholds crowd
    model, pre, data, forest = fitted
    assert forest.masks.dtype == np.uint32  # scikit-learn's default: 31 leaves
    x_num, x_cat = pre.numeric_array(data), pre.category_codes(data)
    rows = []
    for j in range(len(pre.numeric)):
        cuts = forest.cuts[forest.cut_start[j]:forest.cut_start[j + 1]]
        for v in np.concatenate([cuts, np.nextafter(cuts, -np.inf), np.nextafter(cuts, np.inf)]):
            row = x_num[len(rows) % len(x_num)].copy()
            row[j] = v * pre.scale_[j] + pre.mean_[j]  # about the threshold in raw units
            rows.append(row)
    q = np.asarray(rows)
    qc = x_cat[np.arange(len(q)) % len(x_cat)]
    assert np.array_equal(forest.predict(q, qc), model.predict(design_matrix(pre, q, qc)))


def test_thresholds_one_float_apart_equal_sklearn():
    # values 1 ulp apart (as computed geometry gives, e.g. a dogleg of 0 or of
    # 1e-16): scikit-learn splits between them, so thresholds crowd in one cell
    # of the rank grid and the rank takes several steps from its guess
    rng = np.random.default_rng(0)
    base = 1.0 + np.arange(12) * np.spacing(1.0)
    x = np.column_stack([np.concatenate([rng.choice(base, 1500), rng.uniform(-3, 3, 1500)]),
                         rng.normal(size=3000)])
    y = np.where(np.isin(x[:, 0], base), (x[:, 0] - 1.0) / np.spacing(1.0), np.sin(x[:, 0]))
    model = HistGradientBoostingRegressor(max_iter=20, random_state=0).fit(x, y)
    pre = Preprocessor(["a", "b"])
    pre.mean_, pre.scale_, pre.categories_ = np.zeros(2), np.ones(2), {}
    forest = FlatForest(model, pre)
    cuts = forest.cuts[forest.cut_start[0]:forest.cut_start[1]]
    assert (np.diff(cuts) < 1e-12).sum() >= 5
    q = np.vstack([x, np.column_stack([np.nextafter(base, 0.0), np.zeros(12)])])
    assert np.array_equal(forest.predict(q, np.zeros((len(q), 0), dtype=np.int64)),
                          model.predict(q))


@settings(max_examples=200, deadline=None)
@given(st.lists(st.floats(-1e3, 1e3), min_size=0, max_size=12, unique=True),
       st.floats(-2e3, 2e3, allow_nan=False), st.integers(0, 12))
def test_property_rank_from_any_guess_is_exact(cuts, v, guess):
    c = np.sort(np.asarray(cuts, dtype=np.float64))
    padded = np.concatenate([[-7.0], c, [7.0]])  # the column's thresholds sit inside cuts
    lo, hi = 1, 1 + c.size
    r = _rank_near(padded, lo, hi, lo + min(guess, c.size), v)
    assert r - lo == np.searchsorted(c, v, side="left")
    assert r - lo == _rank(padded, lo, hi, v) - lo


def _sharing_models(leaves: int, second_leaves: int = 7
                    ) -> tuple[Preprocessor, np.ndarray, np.ndarray, list]:
    # a regressor and a second model (the served interval's scale model is one) on the
    # same design matrix; the second is fitted on a third of the rows, so its histogram
    # bins, and thresholds, are its own
    rng = np.random.default_rng(11)
    x = rng.normal(size=(3000, 4))
    y = np.sin(3 * x[:, 0]) + x[:, 1] * x[:, 2] + 0.1 * rng.normal(size=3000)
    pre = Preprocessor(["a", "b", "c", "d"])
    pre.mean_, pre.scale_, pre.categories_ = np.zeros(4), np.ones(4), {}
    first = HistGradientBoostingRegressor(max_iter=25, max_leaf_nodes=leaves,
                                          min_samples_leaf=5, random_state=0).fit(x, y)
    second = HistGradientBoostingRegressor(
        max_iter=7, max_leaf_nodes=second_leaves, min_samples_leaf=5, random_state=1,
    ).fit(x[::3], np.abs(y - first.predict(x))[::3])
    return pre, x, np.zeros((3000, 0), dtype=np.int64), [first, second]


@pytest.mark.parametrize("leaves, second_leaves, path", [
    (31, 7, "leaf masks"), (100, 7, "rank walk"),
    (31, 50, "leaf masks"),  # the extra model's 50 leaves widen every mask to 64 bits
    (31, 100, "rank walk"),  # the extra model's trees of > 64 leaves: the whole pass walks
])
def test_models_sharing_one_pass_give_each_models_own_numbers(leaves, second_leaves, path):
    pre, x, none, (first, second) = _sharing_models(leaves, second_leaves)
    both = FlatForest(first, pre, extra=(second,))
    assert both.n_outputs == 2 and both.n_trees == first.n_iter_ + second.n_iter_
    assert (both.masks is None) == (path == "rank walk")
    if both.masks is not None:
        widest = max(max(t.nodes["is_leaf"].sum() for (t,) in m._predictors)
                     for m in (first, second))
        assert both.masks.dtype == (np.uint32 if widest <= 32 else np.uint64)
    # the union of thresholds holds some of the second model's that the first lacks
    own = FlatForest(first, pre)
    assert both.cuts.size > own.cuts.size
    big = np.tile(x, (6, 1))  # chunked over threads as well as one thread
    big_none = np.zeros((big.shape[0], 0), dtype=np.int64)
    nan = big.copy()
    nan[5, 2] = np.nan  # that chunk takes the float walk
    for q, c in ((x[:500], none[:500]), (big, big_none), (nan, big_none)):
        out = both.predict(q, c)
        assert out.shape == (q.shape[0], 2)
        # bit for bit: each column is that model's own evaluator's and scikit-learn's number
        assert np.array_equal(out[:, 0], FlatForest(first, pre).predict(q, c))
        assert np.array_equal(out[:, 1], FlatForest(second, pre).predict(q, c))
        assert np.array_equal(out[:, 0], first.predict(q))
        assert np.array_equal(out[:, 1], second.predict(q))
    # a forest of one model keeps its (n,) answer
    assert FlatForest(first, pre).predict(x, none).shape == (3000,)


def test_models_sharing_one_pass_must_share_the_design_matrix():
    pre, x, _, (first, _) = _sharing_models(31)
    other = HistGradientBoostingRegressor(max_iter=3).fit(x[:, :3], x[:, 0])
    with pytest.raises(InputError) as err:
        FlatForest(first, pre, extra=(other,))
    assert err.value.field == "gbm"
