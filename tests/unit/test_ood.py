"""Out-of-domain flag: per-feature ranges and k-NN joint distance."""

from __future__ import annotations

import numpy as np

from drillfatigue.errors import InputError
from drillfatigue.surrogate.ood import DomainChecker, knn_distance


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


def test_batched_knn_distance_equals_brute_force() -> None:
    import torch

    rng = np.random.default_rng(3)
    ref = rng.normal(size=(300, 4)).astype(np.float32)
    z = rng.normal(size=(2500, 4))  # > 2 chunks: the pooled path
    before = torch.get_num_threads()
    try:
        torch.set_num_threads(2)
        d = knn_distance(z, ref, 5)
        assert torch.get_num_threads() == 2
    finally:
        torch.set_num_threads(before)
    d2 = ((z[:, None, :] - ref.astype(np.float64)[None]) ** 2).sum(axis=2)
    brute = np.sqrt(np.sort(d2, axis=1)[:, :5]).mean(axis=1)
    # float32 GEMM expansion |z|^2 - 2 z.r + |r|^2: ~1e-6 relative on O(1) distances
    np.testing.assert_allclose(d, brute, rtol=1e-4, atol=1e-4)


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
    dc = DomainChecker(["rpm", "wob", "mu"]).fit(tr, cal, tr.mean(axis=0), tr.std(axis=0),
                                                 design_bounds={"rpm": (0.0, 2.0)})
    flag, _ = dc.check(np.array([[1.5, 0.5, 0.5], [2.5, 0.5, 0.5], [0.5, 1.2, 0.5]]), knn=False)
    assert flag.tolist() == [False, True, True]
    again = DomainChecker.from_dict(dc.to_dict(), dc.reference_)
    assert again.source_ == ["design", "training", "training"]
    err = again.refusal(np.array([2.5, 0.5, 0.5]), 0.0)
    assert isinstance(err, InputError)
    assert err.field == "rpm" and "design range" in err.problem and err.allowed == "0 <= rpm <= 2"
    err = again.refusal(np.array([0.5, 1.2, 0.5]), 0.0)
    assert err.field == "wob" and "training data" in err.problem


def test_refusal_of_a_far_point_names_the_distance() -> None:
    dc, _ = _fit()
    x = np.array([[0.97, 0.97, 0.5]])
    _, dist = dc.check(x)
    err = dc.refusal(x[0], float(dist[0]), field_prefix="rows[0].")
    assert err.field == "rows[0].query" and "far from the training data" in err.problem
