"""Out-of-domain detection for surrogate queries.

A query is flagged (never silently extrapolated) when

1. **range**: any numeric feature lies outside the [min, max] seen in
   training (per feature), or
2. **joint distance**: the mean Euclidean distance to its k nearest training
   points, in standardised numeric-feature space, exceeds the ``quantile``
   (default 99th percentile) of the same distance for the held-out
   calibration rows (which are not in the reference set). A point inside all
   per-feature ranges but in an empty corner of the design (e.g. high rpm
   combined with low WOB if no case had both) is thereby flagged.

Categorical levels unseen in training are rejected earlier, as input errors.
The reference set is a seeded subsample of the training rows (at most
``reference_rows``) to bound memory and query cost. Distances are computed in
chunks as one matrix product each (exact brute force).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import torch

from drillfatigue.surrogate.kernels import outside_ranges
from drillfatigue.surrogate.parallel import map_chunks

_CHUNK = 1024
_SMALL = 16


def knn_distance(z: np.ndarray, reference: np.ndarray, k: int) -> np.ndarray:
    """Mean distance of each row of ``z`` to its ``k`` nearest rows of ``reference``.

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
    ref = np.asarray(reference, dtype=np.float32)
    kk = min(int(k), ref.shape[0])
    z = np.asarray(z, dtype=np.float32)
    out = np.empty(z.shape[0])
    if z.shape[0] <= _SMALL:  # single queries: plain numpy, no torch dispatch
        d2 = ((ref[None, :, :] - z[:, None, :]) ** 2).sum(axis=2)
        part = np.partition(d2, kk - 1, axis=1)[:, :kk]
        return np.sqrt(np.maximum(part, 0.0)).mean(axis=1).astype(np.float64)
    # batches: |z|^2 - 2 z.r + |r|^2 as one GEMM per chunk (torch.cdist is far slower here)
    rt = torch.from_numpy(ref)
    r2 = (rt * rt).sum(dim=1)
    zt = torch.from_numpy(z)

    def run(a: int) -> None:
        with torch.inference_mode():
            zc = zt[a:a + _CHUNK]
            d2 = torch.addmm(r2.unsqueeze(0), zc, rt.t(), alpha=-2.0)
            d2 += (zc * zc).sum(dim=1, keepdim=True)
            small = torch.topk(d2, kk, dim=1, largest=False).values
            out[a:a + _CHUNK] = small.clamp_min(0.0).sqrt().mean(dim=1).numpy()

    map_chunks(run, range(0, z.shape[0], _CHUNK))
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
            scale: np.ndarray) -> DomainChecker:
        """Ranges from ``x_train``; threshold from ``x_cal`` (raw SI arrays (n, d))."""
        self.min_ = x_train.min(axis=0)
        self.max_ = x_train.max(axis=0)
        self.mean_ = np.asarray(mean, dtype=np.float64)
        self.scale_ = np.asarray(scale, dtype=np.float64)
        z = (x_train - self.mean_) / self.scale_
        rng = np.random.default_rng(self.seed)
        if z.shape[0] > self.reference_rows:
            z = z[np.sort(rng.choice(z.shape[0], self.reference_rows, replace=False))]
        self.reference_ = z.astype(np.float32)
        d_cal = knn_distance((x_cal - self.mean_) / self.scale_, self.reference_, self.k)
        self.threshold_ = float(np.quantile(d_cal, self.quantile))
        return self

    def check(self, x: np.ndarray, knn: bool = True) -> tuple[np.ndarray, np.ndarray]:
        """Flag rows of ``x`` (raw SI, shape (n, d)).

        Returns
        -------
        flag : ndarray of bool, shape (n,)
        distance : ndarray, shape (n,)
            k-NN distance (NaN when ``knn`` is False).
        """
        span = self.max_ - self.min_
        tol = 1e-9 * np.where(span > 0, span, np.abs(self.max_) + 1.0)
        out_range = outside_ranges(np.ascontiguousarray(x, dtype=np.float64),
                                   np.asarray(self.min_ - tol, dtype=np.float64),
                                   np.asarray(self.max_ + tol, dtype=np.float64))
        if knn:
            dist = knn_distance((x - self.mean_) / self.scale_, self.reference_, self.k)
            flag = out_range | (dist > self.threshold_)
        else:
            dist = np.full(x.shape[0], np.nan)
            flag = out_range
        return flag, dist

    def reasons(self, x: np.ndarray, dist: np.ndarray, flag: np.ndarray) -> np.ndarray:
        """One text per row: why it is out of domain ('' when in domain)."""
        out = np.full(x.shape[0], "", dtype=object)
        span = self.max_ - self.min_
        tol = 1e-9 * np.where(span > 0, span, np.abs(self.max_) + 1.0)
        for i in np.flatnonzero(flag):
            bits = []
            for j, name in enumerate(self.names):
                if x[i, j] < self.min_[j] - tol[j]:
                    bits.append(f"{name}={x[i, j]:.6g} below training min {self.min_[j]:.6g}")
                elif x[i, j] > self.max_[j] + tol[j]:
                    bits.append(f"{name}={x[i, j]:.6g} above training max {self.max_[j]:.6g}")
            if np.isfinite(dist[i]) and dist[i] > self.threshold_:
                bits.append(f"far from training data (kNN distance {dist[i]:.3g} "
                            f"> {self.threshold_:.3g})")
            out[i] = "; ".join(bits)
        return out

    def to_dict(self) -> dict:
        return {"names": self.names, "k": self.k, "quantile": self.quantile,
                "reference_rows": self.reference_rows, "seed": self.seed,
                "min": self.min_.tolist(), "max": self.max_.tolist(),
                "mean": self.mean_.tolist(), "scale": self.scale_.tolist(),
                "threshold": self.threshold_}

    @classmethod
    def from_dict(cls, d: dict, reference: np.ndarray) -> DomainChecker:
        c = cls(d["names"], d["k"], d["quantile"], d["reference_rows"], d["seed"])
        c.min_ = np.asarray(d["min"])
        c.max_ = np.asarray(d["max"])
        c.mean_ = np.asarray(d["mean"])
        c.scale_ = np.asarray(d["scale"])
        c.threshold_ = float(d["threshold"])
        c.reference_ = np.asarray(reference, dtype=np.float32)
        return c
