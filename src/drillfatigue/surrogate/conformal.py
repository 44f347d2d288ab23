"""Split conformal calibration of a predictive spread.

Normalised nonconformity score r_i = |y_i - mu_i| / sigma_i on a held-out
calibration set of size n; the interval mu -/+ q sigma with q the
ceil((n + 1) c)-th smallest score has marginal coverage >= c for an
exchangeable new point (finite-sample guarantee).

References
----------
Vovk, Gammerman & Shafer, *Algorithmic Learning in a Random World* (2005);
Lei, G'Sell, Rinaldo, Tibshirani & Wasserman, "Distribution-free predictive
inference for regression", JASA 113 (2018), sec. 2.2 and 5.2 (locally
weighted / normalised residuals); Angelopoulos & Bates, "A gentle
introduction to conformal prediction" (2021), eq. (1).
"""

from __future__ import annotations

import math

import numpy as np

from drillfatigue.errors import InputError


def conformal_quantile(scores: np.ndarray, coverage: float) -> float:
    """Finite-sample-corrected quantile of nonconformity scores.

    Parameters
    ----------
    scores : ndarray, shape (n,)
        Nonconformity scores of the calibration set (dimensionless).
    coverage : float
        Target coverage c in (0, 1).

    Returns
    -------
    float
        The ceil((n+1) c)-th smallest score; ``inf`` when (n+1) c > n (too few
        calibration points for that coverage: the interval is unbounded).
    """
    s = np.sort(np.asarray(scores, dtype=np.float64).reshape(-1))
    if s.size == 0 or not np.all(np.isfinite(s)):
        raise InputError("calibration scores", "empty or non-finite", "finite scores, n >= 1")
    if not 0.0 < coverage < 1.0:
        raise InputError("coverage", f"must be in (0, 1), got {coverage}", "0 < coverage < 1")
    k = math.ceil((s.size + 1) * coverage)
    if k > s.size:
        return math.inf
    return float(s[k - 1])


class SplitConformal:
    """Calibrate mu -/+ q sigma intervals on a held-out set.

    Parameters
    ----------
    coverage : float
        Nominal coverage (default 0.90).

    Attributes
    ----------
    quantile_ : float
        The calibrated multiplier q of sigma.
    n_calibration_ : int
    """

    def __init__(self, coverage: float = 0.90) -> None:
        self.coverage = coverage

    def fit(self, mu: np.ndarray, sigma: np.ndarray, y: np.ndarray,
            censor_below: float | None = None) -> SplitConformal:
        """Calibrate q; rows with ``y <= censor_below`` are censored ("at most c").

        A censored row is covered when the interval reaches down to its level
        (mu - q sigma <= c), so its score is max(mu - c, 0) / sigma, the
        smallest q that covers it. The coverage guarantee then reads: the
        interval contains Y, or Y is censored and the interval reaches down
        to c.
        """
        mu, sigma, y = (np.asarray(a, dtype=np.float64).reshape(-1) for a in (mu, sigma, y))
        if np.any(sigma <= 0):
            raise InputError("sigma", "non-positive spread", "sigma > 0")
        scores = np.abs(y - mu) / sigma
        if censor_below is not None:
            cens = y <= censor_below
            scores[cens] = np.maximum(mu[cens] - censor_below, 0.0) / sigma[cens]
        self.quantile_ = conformal_quantile(scores, self.coverage)
        self.n_calibration_ = int(scores.size)
        return self

    def interval(self, mu: np.ndarray, sigma: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Lower and upper bounds, each shape (n,)."""
        half = self.quantile_ * np.asarray(sigma, dtype=np.float64)
        return mu - half, mu + half
