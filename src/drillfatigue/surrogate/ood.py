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
``reference_rows``) to bound memory and query cost. Distances are computed in
chunks as one matrix product each (exact brute force).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np
import torch

from drillfatigue.errors import InputError
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
            scale: np.ndarray,
            design_bounds: Mapping[str, tuple[float, float]] | None = None) -> DomainChecker:
        """Ranges and threshold (raw SI arrays (n, d)).

        ``design_bounds``: per feature name the design range (low, high) of
        the sweep; a feature not in it takes the [min, max] of ``x_train``.
        The k-NN threshold comes from ``x_cal``.
        """
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
                "threshold": self.threshold_}

    @classmethod
    def from_dict(cls, d: dict, reference: np.ndarray) -> DomainChecker:
        c = cls(d["names"], d["k"], d["quantile"], d["reference_rows"], d["seed"])
        c.min_ = np.asarray(d["min"])
        c.max_ = np.asarray(d["max"])
        c.source_ = list(d.get("source", ["training"] * len(c.names)))
        c.mean_ = np.asarray(d["mean"])
        c.scale_ = np.asarray(d["scale"])
        c.threshold_ = float(d["threshold"])
        c.reference_ = np.asarray(reference, dtype=np.float32)
        return c
