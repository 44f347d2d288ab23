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


#: Fewest calibration rows of a Mondrian bin (:func:`mondrian_bins`): at 90 %
#: coverage the conformal quantile is the ceil(0.9 (n + 1))-th of n scores, so
#: 50 rows put it between the 46th and 47th order statistic of the bin, and the
#: realised coverage of a bin (Beta-distributed given the calibration set) has
#: a standard deviation of about 0.04 (Angelopoulos & Bates 2021, sec. 3.2).
MONDRIAN_MIN_ROWS = 50


def censored_residuals(mu: np.ndarray, y: np.ndarray, censor_below: float | None
                       ) -> np.ndarray:
    """Absolute residuals ``|y - mu|`` as the conformal calibration scores them: a row with
    ``y <= censor_below`` (censored, "at most the level") counts only the prediction's
    excess above the level."""
    scores = np.abs(y - mu)
    if censor_below is not None:
        cens = y <= censor_below
        scores[cens] = np.maximum(mu[cens] - censor_below, 0.0)
    return scores


def mondrian_bins(mu: np.ndarray, y: np.ndarray, coverage: float,
                  min_rows: int = MONDRIAN_MIN_ROWS, censor_below: float | None = None,
                  bin_width: float = 1.0, scale: np.ndarray | None = None
                  ) -> tuple[np.ndarray, np.ndarray]:
    """Mondrian split-conformal half-widths by bin of the predicted value.

    The calibration rows are binned by their *prediction* ``mu`` (unit-width
    bins: decades of a log10 target), neighbouring bins are merged until every
    bin holds at least ``min_rows`` rows (the smallest bin first, into its
    smaller neighbour), and each bin gets the conformal quantile of its own
    absolute residuals. Conditioning on the bin of the prediction (a
    function of the inputs only) keeps the exchangeability within a bin, so
    each bin has coverage >= ``coverage`` on its own (Vovk et al. 2005,
    ch. 4.5, Mondrian conformal predictors), where one global width covers
    the rows of small residuals too much and those of large ones too little.
    With ``censor_below``, predictions below the level share one bin with
    the global width (all calibration rows' quantile) and the bins start at
    the level; with fewer than ``min_rows`` predictions at or above the
    level, all rows form one bin.

    Parameters
    ----------
    mu, y : ndarray, shape (n,)
        Predictions and targets of the calibration rows.
    coverage : float
        Nominal coverage in (0, 1).
    min_rows : int
        Fewest rows of a bin; at least ``ceil(coverage / (1 - coverage))`` so
        that each bin's quantile is finite.
    censor_below : float, optional
        Rows with ``y <= censor_below`` are censored (scored as in
        :meth:`SplitConformal.fit`: covered when the interval reaches down to
        the level).
    bin_width : float
        Width of the initial bins in units of ``mu``.
    scale : ndarray, shape (n,), optional
        Positive scale of each row's residual (normalised conformal: the
        score is ``|y - mu| / scale``, Papadopoulos et al. 2002; Lei et al.
        2018, sec. 5.2); the returned half-widths are then multipliers of a
        query's own scale. Without it the score is ``|y - mu|``.

    Returns
    -------
    edges : ndarray, shape (k - 1,)
        Inner bin edges, increasing (empty: one bin).
    half_widths : ndarray, shape (k,)
        Half-width of the interval of each bin (with ``scale``: the multiplier
        of the query's scale); a prediction's bin is
        ``np.searchsorted(edges, mu, side="right")``, so predictions beyond
        the outer edges take the outer bins.
    """
    mu = np.asarray(mu, dtype=np.float64).reshape(-1)
    y = np.asarray(y, dtype=np.float64).reshape(-1)
    if mu.shape != y.shape or mu.size == 0 or not np.all(np.isfinite(mu)):
        raise InputError("calibration predictions", "empty, non-finite or not one per target",
                         "finite predictions, one per calibration row")
    if not 0.0 < coverage < 1.0:
        raise InputError("coverage", f"must be in (0, 1), got {coverage}", "0 < coverage < 1")
    need = math.ceil(coverage / (1.0 - coverage) - 1e-9)
    if min_rows < need:
        raise InputError("min_rows", f"{min_rows} rows give an unbounded {coverage:g} "
                         "conformal quantile", f">= {need}")
    if not bin_width > 0.0:
        raise InputError("bin_width", f"must be > 0, got {bin_width}", "> 0")
    scores = censored_residuals(mu, y, censor_below)
    if scale is not None:
        scale = np.asarray(scale, dtype=np.float64).reshape(-1)
        if scale.shape != mu.shape or not np.all(np.isfinite(scale) & (scale > 0.0)):
            raise InputError("calibration scale", "not one finite positive value per row",
                             "finite scales > 0, one per calibration row")
        scores = scores / scale
    below: list[float] = []
    binned = np.ones(mu.shape, dtype=bool)
    if censor_below is not None:
        # Predictions below the censoring level form one bin of the global
        # width: their calibration rows are mostly censored with score 0 (the
        # prediction already lies below the level), so a quantile of their own
        # would give a zero-width interval to an answer "longer than".
        binned = mu >= censor_below
        if binned.sum() < min_rows:
            # too few predictions within the level for a bin of their own: one bin
            return np.empty(0), np.array([conformal_quantile(scores, coverage)])
        if not binned.all():
            below = [float(censor_below)]
    lo = math.floor(mu[binned].min() / bin_width)
    hi = math.floor(mu[binned].max() / bin_width)
    # inner edges of the unit bins (above the censoring level) and their row counts
    edges = [(lo + i) * bin_width for i in range(1, hi - lo + 1)
             if not below or (lo + i) * bin_width > below[0]]
    counts = list(np.bincount(np.searchsorted(np.asarray(edges), mu[binned], side="right"),
                              minlength=len(edges) + 1))
    while len(counts) > 1 and min(counts) < min_rows:
        i = int(np.argmin(counts))
        if i == 0:
            j = 1
        elif i == len(counts) - 1:
            j = i - 1
        else:
            j = i - 1 if counts[i - 1] <= counts[i + 1] else i + 1
        a = min(i, j)
        counts[a:a + 2] = [counts[a] + counts[a + 1]]
        del edges[a]
    e = np.asarray(edges, dtype=np.float64)
    b = np.searchsorted(e, mu[binned], side="right")
    half = [conformal_quantile(scores[binned][b == k], coverage) for k in range(len(counts))]
    if below:
        e = np.concatenate((below, e))
        half = [conformal_quantile(scores, coverage)] + half
    return e, np.asarray(half, dtype=np.float64)


def mondrian_half_width(mu: np.ndarray, edges: np.ndarray,
                        half_widths: np.ndarray) -> np.ndarray:
    """Half-width of each prediction from :func:`mondrian_bins` (one searchsorted)."""
    return half_widths[np.searchsorted(edges, mu, side="right")]
