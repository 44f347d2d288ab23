"""Out-of-domain flag: per-feature ranges and k-NN joint distance."""

from __future__ import annotations

import numpy as np
import torch
from hypothesis import given, settings
from hypothesis import strategies as st

from drillfatigue.config.surrogate import SurrogateConfig
from drillfatigue.errors import InputError
from drillfatigue.surrogate import make_synthetic_dataset
from drillfatigue.surrogate.kernels import knn_within
from drillfatigue.surrogate.ood import DomainChecker, KnnIndex, key_columns, knn_distance


def _fit() -> tuple[DomainChecker, np.ndarray]:
    # training design with an empty corner: x0 + x1 <= 1.2 on [0, 1]^2 (think:
    # no case combined high rpm with high WOB), plus a third feature
    rng = np.random.default_rng(0)
    x = rng.uniform(0, 1, (6000, 3))
    x = x[x[:, 0] + x[:, 1] <= 1.2]
    tr, cal = x[:3000], x[3000:]
    dc = DomainChecker(["rpm", "wob", "mu"], k=5, quantile=0.99, reference_rows=2000).fit(
        tr, cal, tr.mean(axis=0), tr.std(axis=0))
    return dc, x


def test_knn_distance_exact() -> None:
    ref = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 2.0]])
    d = knn_distance(np.array([[0.0, 0.0]]), ref, 2)
    np.testing.assert_allclose(d, [0.5], rtol=1e-6)  # mean of 0 and 1


def _brute(z: np.ndarray, ref: np.ndarray, k: int) -> np.ndarray:
    """Reference: every squared distance in float64, sorted, the k smallest."""
    d2 = ((z[:, None, :] - np.asarray(ref, dtype=np.float64)[None]) ** 2).sum(axis=2)
    return np.sqrt(np.sort(d2, axis=1)[:, :min(k, ref.shape[0])]).mean(axis=1)


def _gemm_float32(z: np.ndarray, ref: np.ndarray, k: int) -> np.ndarray:
    """A matrix-product k-NN: float32 |z|^2 - 2 z.r + |r|^2, k smallest, clamped at 0."""
    z = np.asarray(z, dtype=np.float32)
    ref = np.asarray(ref, dtype=np.float32)
    d2 = (z * z).sum(axis=1)[:, None] - 2.0 * z @ ref.T + (ref * ref).sum(axis=1)[None]
    part = np.partition(d2, k - 1, axis=1)[:, :k]
    return np.sqrt(np.maximum(part, 0.0)).mean(axis=1)


def _cases(rng: np.random.Generator, n_cases: int, rows: int, d_case: int, d_loc: int,
           ) -> np.ndarray:
    """Rows of simulated cases: ``d_case`` columns shared by a case's rows, then location ones."""
    case = np.repeat(rng.normal(size=(n_cases, d_case)), rows, axis=0)
    return np.hstack([case, rng.normal(size=(n_cases * rows, d_loc))])


@settings(max_examples=60, deadline=None)
@given(st.integers(0, 2**32 - 1), st.integers(1, 8), st.integers(1, 60), st.integers(1, 5),
       st.integers(0, 4), st.booleans())
def test_property_knn_equals_brute_force(seed: int, k: int, n_cases: int, d_case: int,
                                         d_loc: int, duplicates: bool) -> None:
    # case-structured references (grouped by the index), plain ones (d_loc = 0 or
    # one row per case: no key) and repeated rows (counted with multiplicity)
    rng = np.random.default_rng(seed)
    rows = int(rng.integers(1, 6))
    ref = _cases(rng, n_cases, rows, d_case, d_loc)
    if duplicates:
        ref = np.vstack([ref, ref[rng.integers(0, ref.shape[0], ref.shape[0])]])
    z = np.vstack([rng.normal(scale=2.0, size=(40, ref.shape[1])),  # anywhere
                   ref[rng.integers(0, ref.shape[0], 10)],  # on a reference row
                   ref[rng.integers(0, ref.shape[0], 10)] + 1e-3])  # next to one
    # the same squares summed in another column order: float64 rounding only
    np.testing.assert_allclose(knn_distance(z, ref, k), _brute(z, ref, k), rtol=1e-12,
                               atol=1e-12)


def test_index_groups_the_case_columns() -> None:
    rng = np.random.default_rng(2)
    ref = _cases(rng, 30, 8, 4, 3)[:, [4, 0, 5, 1, 2, 6, 3]]  # case columns shuffled in
    idx = KnnIndex(ref)
    assert idx.n_key == 4 and sorted(idx.perm[:4].tolist()) == [1, 3, 4, 6]
    assert idx.keys_t.shape == (4, 30) and idx.rest.shape == (240, 3)
    assert key_columns(rng.normal(size=(50, 3))) == []  # no shared columns: one group


def test_flags_equal_the_float32_gemm_distance() -> None:
    # a reference and calibration of whole synthetic cases, as the train stage builds
    # it; queries: the benchmark's kind of batch (rows of other synthetic cases) and a
    # designed out-of-domain set (uniform in the per-feature box: empty corners of a
    # 13-dimensional design, plus points past the ranges)
    cfg = SurrogateConfig()
    train = make_synthetic_dataset(60, seed=0)
    feats = list(cfg.features)
    x_tr = train[feats].to_numpy()
    mean, scale = x_tr.mean(axis=0), x_tr.std(axis=0)
    x_cal = make_synthetic_dataset(20, seed=5)[feats].to_numpy()
    dc = DomainChecker(feats, k=5, reference_rows=2000).fit(x_tr, x_cal, mean, scale)
    assert dc.index.n_key > 0  # the operating conditions group the reference
    rng = np.random.default_rng(7)
    batch = make_synthetic_dataset(400, seed=1)[feats].to_numpy()
    lo, hi = x_tr.min(axis=0), x_tr.max(axis=0)
    designed = rng.uniform(lo - 0.1 * (hi - lo), hi + 0.1 * (hi - lo), (3000, len(feats)))
    for x in (batch, designed):
        flag, dist = dc.check(x, distances=True)
        z = (x - dc.mean_) / dc.scale_
        old = _gemm_float32(z, dc.reference_, 5)
        # the float32 expansion loses ~eps32 * |z|^2 to cancellation: up to
        # sqrt(1e-5) = 3e-3 on a distance near 0, ~1e-6 relative near the threshold
        np.testing.assert_allclose(dist, old, rtol=1e-4, atol=5e-3)
        range_flag, _ = dc.check(x, knn=False)
        np.testing.assert_array_equal(flag, range_flag | (old > dc.threshold_))
        # the served check (distances only beyond the threshold): the same flags
        served, far = dc.check(x)
        np.testing.assert_array_equal(served, flag)
        beyond = dist > dc.threshold_
        np.testing.assert_array_equal(far[beyond], dist[beyond])
        assert np.isnan(far[~beyond]).all()
    assert 0.0 < dc.check(batch)[0].mean() < 0.5
    assert dc.check(designed)[0].mean() > 0.9


def test_pooled_check_equals_row_by_row() -> None:
    dc, x = _fit()
    x = np.vstack([x, x[::-1]])
    assert x.shape[0] > 4096  # more than one chunk of 4096 rows, on two threads
    before = torch.get_num_threads()
    try:
        torch.set_num_threads(2)
        flag, dist = dc.check(x)
    finally:
        torch.set_num_threads(before)
    one = [dc.check(x[i:i + 1]) for i in range(0, x.shape[0], 97)]
    np.testing.assert_array_equal(flag[::97], [f[0] for f, _ in one])
    np.testing.assert_array_equal(dist[::97], [d[0] for _, d in one])


def test_inside_points_not_flagged() -> None:
    dc, _ = _fit()
    rng = np.random.default_rng(1)
    x = rng.uniform(0.05, 0.95, (4000, 3))
    x = x[x[:, 0] + x[:, 1] <= 1.1][:1000]
    flag, _ = dc.check(x)
    # threshold = 99th percentile of held-out in-domain points: about 1 %
    # flagged; 3 % allows for sampling (binomial std of 1 % at n=1000 is 0.3 %)
    assert flag.mean() <= 0.03


def test_outside_range_flagged_with_reason() -> None:
    dc, _ = _fit()
    x = np.array([[1.5, 0.1, 0.5], [0.5, 0.2, -0.3]])
    flag, dist = dc.check(x)
    assert flag.all()
    reasons = dc.reasons(x, dist, flag)
    assert "rpm=1.5 above the range of the training data" in reasons[0]
    assert "mu=-0.3 below the range of the training data" in reasons[1]


def test_empty_corner_flagged_although_inside_ranges() -> None:
    dc, _ = _fit()
    x = np.array([[0.97, 0.97, 0.5]])  # each feature within its range, jointly unseen
    flag_r, _ = dc.check(x, knn=False)
    assert not flag_r.any()
    flag, dist = dc.check(x)
    assert flag.all()
    assert "far from training data" in dc.reasons(x, dist, flag)[0]


def test_roundtrip_dict() -> None:
    dc, x = _fit()
    again = DomainChecker.from_dict(dc.to_dict(), dc.reference_)
    a, da = dc.check(x[:200])
    b, db = again.check(x[:200])
    np.testing.assert_array_equal(a, b)
    np.testing.assert_allclose(da, db)


def test_design_bounds_replace_the_training_range() -> None:
    # the sweep designed rpm on [0, 2] but the training rows only reached [0, 1]:
    # 1.5 is inside the design (range test passes), 2.5 is outside it
    rng = np.random.default_rng(0)
    x = rng.uniform(0, 1, (3000, 3))
    tr, cal = x[:2000], x[2000:]
    dc = DomainChecker(["operation.rpm", "wob", "mu"]).fit(tr, cal, tr.mean(axis=0), tr.std(axis=0),
                                                 design_bounds={"operation.rpm": (0.0, 2.0)})
    flag, _ = dc.check(np.array([[1.5, 0.5, 0.5], [2.5, 0.5, 0.5], [0.5, 1.2, 0.5]]), knn=False)
    assert flag.tolist() == [False, True, True]
    again = DomainChecker.from_dict(dc.to_dict(), dc.reference_)
    assert again.source_ == ["design", "training", "training"]
    err = again.refusal(np.array([2.5, 0.5, 0.5]), 0.0)
    assert isinstance(err, InputError)
    assert err.field == "operation.rpm" and "design range" in err.problem
    assert err.allowed == "0 <= operation.rpm <= 2"
    err = again.refusal(np.array([0.5, 1.2, 0.5]), 0.0)
    assert err.field == "wob" and "training data" in err.problem


def test_refusal_of_a_far_point_names_the_distance() -> None:
    dc, _ = _fit()
    x = np.array([[0.97, 0.97, 0.5]])
    _, dist = dc.check(x)
    err = dc.refusal(x[0], float(dist[0]), field_prefix="rows[0].")
    assert err.field == "rows[0].query" and "far from the training data" in err.problem


def _beyond(idx: KnnIndex, z: np.ndarray, k: int, threshold: float) -> np.ndarray:
    # the best-first kernel itself (the index takes it up to 24 rows per group)
    d = z.shape[1]
    out = np.empty(z.shape[0])
    knn_within(np.ascontiguousarray(z), np.zeros(d), np.ones(d), idx.perm, idx.n_key,
               idx.group_start, idx.rest_t, idx.group_lo, idx.group_hi, idx.count,
               idx.super_start, idx.super_lo, idx.super_hi, min(k, idx.n_rows), threshold, out)
    return out


@settings(max_examples=60, deadline=None)
@given(st.integers(0, 2**32 - 1), st.integers(1, 8), st.integers(1, 80), st.integers(0, 5),
       st.integers(0, 4), st.booleans(), st.floats(0.0, 1.0))
def test_property_distance_beyond_equals_brute_force(seed: int, k: int, n_cases: int,
                                                     d_case: int, d_loc: int, duplicates: bool,
                                                     level: float) -> None:
    # the served search stops once a row is certainly within the threshold: its
    # flag must equal the brute force's on every row, and a row beyond the
    # threshold must get the exact search's distance, bit for bit
    rng = np.random.default_rng(seed)
    rows = int(rng.integers(1, 6))
    if d_case + d_loc == 0:
        d_loc = 1
    ref = _cases(rng, n_cases, rows, d_case, d_loc)
    if duplicates:
        ref = np.vstack([ref, ref[rng.integers(0, ref.shape[0], ref.shape[0])]])
    z = np.vstack([rng.normal(scale=2.0, size=(40, ref.shape[1])),  # anywhere
                   ref[rng.integers(0, ref.shape[0], 10)],  # on a reference row
                   ref[rng.integers(0, ref.shape[0], 10)] + 1e-3,  # next to one
                   50.0 * rng.normal(size=(5, ref.shape[1]))])  # far outliers
    z = np.vstack([z, z[:5]])  # repeated queries
    exact = knn_distance(z, ref, k)
    brute = _brute(z, ref, k)
    np.testing.assert_allclose(exact, brute, rtol=1e-12, atol=1e-12)
    # a threshold among the distances (a row exactly at it is within) or below all
    threshold = float(np.quantile(exact, level)) if level > 0.05 else 0.0
    idx = KnnIndex(ref)
    got = _beyond(idx, z, k, threshold)
    beyond = exact > threshold
    np.testing.assert_array_equal(got > threshold, beyond)
    np.testing.assert_array_equal(got[beyond], exact[beyond])  # bit for bit
    assert np.isnan(got[~beyond]).all()
    # the brute force's flags too, away from float ties at the threshold
    clear = np.abs(brute - threshold) > 1e-9
    np.testing.assert_array_equal(beyond[clear], (brute > threshold)[clear])


def test_distance_beyond_with_fewer_groups_or_rows_than_k() -> None:
    # 2 cases of 2 rows: fewer groups and fewer rows than k = 5 (k falls to 4)
    ref = np.array([[0.0, 0.0, 0.0], [0.0, 0.0, 1.0], [3.0, 1.0, 0.0], [3.0, 1.0, 2.0]])
    idx = KnnIndex(ref)
    assert idx.n_key == 2 and idx.keys_t.shape[1] == 2 and idx.super_start.tolist() == [0, 2]
    z = np.array([[0.0, 0.0, 0.0], [3.0, 1.0, 2.0], [100.0, 0.0, 0.0], [np.nan, 0.0, 0.0]])
    exact = knn_distance(z, ref, 5)
    np.testing.assert_allclose(exact[:3], _brute(z[:3], ref, 5), rtol=1e-12)
    for threshold in (0.0, float(exact[0]), 10.0):
        got = _beyond(idx, z, 5, threshold)
        beyond = exact > threshold
        np.testing.assert_array_equal(got[beyond], exact[beyond])
        assert np.isnan(got[~beyond]).all()
    assert np.isinf(exact[3]) and np.isinf(_beyond(idx, z[3:], 5, 10.0)[0])  # NaN: far


def test_super_groups_partition_the_groups_and_bound_them() -> None:
    rng = np.random.default_rng(3)
    ref = _cases(rng, 150, 6, 5, 4)
    idx = KnnIndex(ref)
    n_groups = idx.keys_t.shape[1]
    sizes = np.diff(idx.super_start)
    assert idx.super_start[0] == 0 and idx.super_start[-1] == n_groups == 150
    assert sizes.min() >= 1 and sizes.max() <= 13  # about sqrt(150) groups each
    lo = np.vstack([idx.keys_t, idx.box_lo])
    hi = np.vstack([idx.keys_t, idx.box_hi])
    np.testing.assert_array_equal(idx.group_lo, lo.T)
    np.testing.assert_array_equal(idx.group_hi, hi.T)
    for s in range(sizes.size):
        a, b = idx.super_start[s], idx.super_start[s + 1]
        assert np.all(idx.super_lo[:, [s]] <= lo[:, a:b])
        assert np.all(idx.super_hi[:, [s]] >= hi[:, a:b])
    # every reference row lies in its group's box
    for g in range(n_groups):
        rows = idx.rest[idx.group_start[g]:idx.group_start[g + 1]]
        assert np.all(rows >= idx.box_lo[:, g]) and np.all(rows <= idx.box_hi[:, g])


def test_served_flags_equal_the_exact_ones_on_a_large_batch() -> None:
    # 300 synthetic cases (about two reference rows each), 20 000 queries of
    # other cases and of a box around the design: the served check's flags equal
    # those of the exact distance on every row
    cfg = SurrogateConfig()
    feats = list(cfg.features)
    train = make_synthetic_dataset(300, seed=0)[feats].to_numpy()
    cal = make_synthetic_dataset(60, seed=5)[feats].to_numpy()
    dc = DomainChecker(feats, reference_rows=2000).fit(train, cal, train.mean(axis=0),
                                                        train.std(axis=0))
    assert dc.index.rest.shape[0] <= 24 * dc.index.keys_t.shape[1]  # searched best first
    rng = np.random.default_rng(11)
    lo, hi = train.min(axis=0), train.max(axis=0)
    x = np.vstack([make_synthetic_dataset(1000, seed=1)[feats].to_numpy()[:16_000],
                   rng.uniform(lo - 0.05 * (hi - lo), hi + 0.05 * (hi - lo), (4000, len(feats)))])
    flag, dist = dc.check(x)
    exact_flag, exact = dc.check(x, distances=True)
    assert 0.01 < exact_flag.mean() < 0.5
    np.testing.assert_array_equal(flag, exact_flag)
    far = exact > dc.threshold_
    np.testing.assert_array_equal(dist[far], exact[far])
    assert np.isnan(dist[~far]).all()


def _corner_cases(n_cases: int, seed: int) -> tuple[np.ndarray, np.ndarray]:
    # rows grouped by case: 2 case-level columns (the empty corner x0 + x1 > 1.2
    # of the design) and one location column with 12 rows per case
    rng = np.random.default_rng(seed)
    c = rng.uniform(0, 1, (4 * n_cases, 2))
    c = c[c[:, 0] + c[:, 1] <= 1.2][:n_cases]
    loc = np.linspace(0.0, 1.0, 12)
    x = np.column_stack([np.repeat(c, loc.size, axis=0), np.tile(loc, len(c))])
    return x, np.repeat(np.arange(len(c)), loc.size)


def test_cross_fitted_threshold_equals_the_brute_force_out_of_fold_quantile() -> None:
    x, case = _corner_cases(200, 2)
    folds = case % 5
    mean, scale = x.mean(axis=0), x.std(axis=0)
    dc = DomainChecker(["rpm", "wob", "md"], k=5, quantile=0.99, reference_rows=1500,
                       seed=3).fit_cross(x, folds, mean, scale)
    # the served reference: the same seeded subsample as fit, drawn from every case
    keep = np.sort(np.random.default_rng(3).choice(len(x), 1500, replace=False))
    np.testing.assert_array_equal(dc.reference_, ((x[keep] - mean) / scale).astype(np.float32))
    z = (x - mean) / scale
    d = np.empty(len(x))
    for f in range(5):
        other = dc.reference_[folds[keep] != f].astype(np.float64)
        diff = z[folds == f][:, None, :] - other[None, :, :]
        dist = np.sort(np.sqrt((diff ** 2).sum(axis=2)), axis=1)[:, :5]
        d[folds == f] = dist.mean(axis=1)
    assert dc.threshold_ == float(np.quantile(d, 0.99))
    assert dc.to_dict()["threshold_source"] == "cross-fitted, 5 folds of whole cases"
    again = DomainChecker.from_dict(dc.to_dict(), dc.reference_)
    assert again.threshold_ == dc.threshold_ and again.threshold_source_ == dc.threshold_source_


def test_cross_fitted_domain_answers_new_cases_and_refuses_the_empty_corner() -> None:
    # new cases of the same design are flagged about 1 - quantile of the time
    # (the out-of-fold distance is a new case's distance to cases it is not part
    # of); 5 % allows for 600 rows in 50 correlated groups of 12 (the
    # binomial std of 1 % over 50 independent cases is 1.4 %)
    x, case = _corner_cases(200, 2)
    dc = DomainChecker(["operation.rpm", "operation.wob", "md"], k=5, quantile=0.99, reference_rows=1500,
                       seed=3).fit_cross(x, case % 5, x.mean(axis=0), x.std(axis=0),
                                         design_bounds={"operation.rpm": (0.0, 1.0),
                                                        "operation.wob": (0.0, 1.0)})
    new, _ = _corner_cases(50, 9)
    flag, _ = dc.check(new)
    assert flag.mean() <= 0.05
    corner = np.array([[0.97, 0.97, 0.5]])
    assert not dc.check(corner, knn=False)[0].any()
    assert dc.check(corner)[0].all()


def test_cross_fit_needs_two_folds() -> None:
    x, case = _corner_cases(20, 2)
    try:
        DomainChecker(["a", "b", "c"]).fit_cross(x, np.zeros(len(x), int), x.mean(axis=0),
                                                 x.std(axis=0))
    except ValueError as exc:
        assert "two folds" in str(exc)
    else:
        raise AssertionError("one fold accepted")
