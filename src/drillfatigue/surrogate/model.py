"""Deep ensemble of MLPs with Gaussian heads (torch, CPU).

The ensemble follows Lakshminarayanan, Pritzel & Blundell, "Simple and
scalable predictive uncertainty estimation using deep ensembles", NeurIPS
2017: M independently initialised MLPs, each with a mean and a log-variance
head trained on the Gaussian negative log-likelihood; the ensemble predicts
the mixture mean mu = mean_m mu_m and variance
sigma^2 = mean_m sigma_m^2 + var_m mu_m (their eq. 3, Gaussian approximation
of the mixture). With ``loss="mse"`` the heads give the mean only and sigma is
the ensemble spread (std of the member means).

All members live in one set of stacked weight tensors of shape
(M, n_in, n_out) and are evaluated with one batched matrix product per layer
(``torch.baddbmm``). Adam is element-wise and the loss is a sum over members,
so stacked training is exactly M independent trainings; each member draws its
own initial weights and minibatch order from its own seed.

Feature scaling (standardisation) and one-hot encoding of the categorical
columns are fitted in :meth:`DeepEnsembleRegressor.fit` (:class:`Preprocessor`)
and baked into the torch module (:class:`EnsembleModule`), so the TorchScript
export takes raw SI features.
"""

from __future__ import annotations

import copy
import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import pandas as pd
import torch
from sklearn.base import BaseEstimator, RegressorMixin
from sklearn.exceptions import NotFittedError
from torch import Tensor, nn

from drillfatigue.errors import InputError

LOGVAR_MIN = -14.0  # clamp of the log-variance head (scaled target units)
LOGVAR_MAX = 6.0
SPREAD_FLOOR = 1e-6  # minimal sigma (scaled target units) for the MSE variant
# hidden-layer activations; hardswish (x * relu6(x + 3) / 6, a piecewise-quadratic
# SiLU look-alike) costs what ReLU costs on this CPU, SiLU about 6x more (one exp
# per unit): 57 / 51 / 320 ns per row of 320 units, one thread, 4096 rows
ACTIVATIONS: tuple[str, ...] = ("silu", "hardswish", "relu", "tanh", "gelu")

EpochCallback = Callable[[int, np.ndarray, np.ndarray, np.ndarray], None]


# ---------------------------------------------------------------------------
# preprocessing
# ---------------------------------------------------------------------------
def column_arrays(frame: pd.DataFrame, columns: Sequence[str]) -> list[np.ndarray]:
    """The values of ``columns`` of ``frame`` as arrays, shape (n,) each.

    ``frame[c]`` builds a Series per column (about 17 us each with pandas 3),
    which dominates a single-row query; with unique column labels the arrays
    are read directly (``DataFrame._get_column_array``, 1-2 us), falling back
    to the public path if that private accessor is missing or the labels are
    not unique.
    """
    cols = frame.columns
    getter = getattr(frame, "_get_column_array", None)
    if getter is not None and cols.is_unique:
        try:
            return [np.asarray(getter(cols.get_loc(c))) for c in columns]
        except (TypeError, KeyError, IndexError):
            pass
    return [frame[c].to_numpy() for c in columns]


class Preprocessor:
    """Standardise numeric columns and integer-code categorical columns.

    Parameters
    ----------
    numeric : sequence of str
        Numeric feature columns, in model order.
    categorical : sequence of str
        Categorical feature columns; levels seen in ``fit`` are sorted and
        coded 0..n-1.
    """

    def __init__(self, numeric: Sequence[str], categorical: Sequence[str] = ()) -> None:
        self.numeric = list(numeric)
        self.categorical = list(categorical)

    def fit(self, frame: pd.DataFrame) -> Preprocessor:
        x = self.numeric_array(frame)
        self.mean_ = x.mean(axis=0)
        std = x.std(axis=0)
        self.scale_ = np.where(std > 0.0, std, 1.0)
        self.min_ = x.min(axis=0)
        self.max_ = x.max(axis=0)
        self.categories_ = {}
        for col in self.categorical:
            self._require(frame, col)
            self.categories_[col] = sorted({str(v) for v in frame[col].to_numpy()})
        return self

    @staticmethod
    def _require(frame: pd.DataFrame, col: str) -> None:
        if col not in frame.columns:
            raise InputError(col, "missing column", "the model's feature columns")

    def numeric_array(self, frame: pd.DataFrame) -> np.ndarray:
        """Numeric features as float64 array, shape (n, n_numeric); NaN/non-numeric raise."""
        for col in self.numeric:
            self._require(frame, col)
        if not self.numeric:
            return np.zeros((len(frame), 0))
        try:  # fast path (selecting a column block of a mixed frame is slow in pandas)
            x = np.array(column_arrays(frame, self.numeric), dtype=np.float64).T
        except (ValueError, TypeError):
            x = None
        if x is None or not np.all(np.isfinite(x)):
            for col in self.numeric:  # slow path only to name the offending column
                try:
                    v = pd.to_numeric(frame[col], errors="raise").to_numpy(dtype=np.float64)
                except (ValueError, TypeError):
                    raise InputError(col, "non-numeric value", "finite numbers") from None
                if not np.all(np.isfinite(v)):
                    raise InputError(col, "NaN or infinite value", "finite numbers")
        return x

    def category_codes(self, frame: pd.DataFrame) -> np.ndarray:
        """Categorical codes, int64 array shape (n, n_categorical); unseen levels raise."""
        out = np.zeros((len(frame), len(self.categorical)), dtype=np.int64)
        for col in self.categorical:
            self._require(frame, col)
        for j, (col, values) in enumerate(zip(self.categorical,
                                              column_arrays(frame, self.categorical), strict=False)):
            out[:, j] = self.codes_for(col, values)
        return out

    def codes_for(self, col: str, values: Any) -> np.ndarray:
        """Level codes of one categorical column, int64 shape (n,); unseen levels raise."""
        levels = self.categories_[col]
        lookup = {v: i for i, v in enumerate(levels)}
        vals = np.asarray(values, dtype=object).astype(str)
        if len(vals) > 64:  # batches: look up each distinct value once
            uniq, inv = np.unique(vals, return_inverse=True)
            codes = np.array([lookup.get(v, -1) for v in uniq], dtype=np.int64)[inv.ravel()]
        else:
            codes = np.fromiter((lookup.get(v, -1) for v in vals), dtype=np.int64,
                                count=len(vals))
        if np.any(codes < 0):
            bad = str(vals[np.argmax(codes < 0)])
            raise InputError(col, f"value {bad!r} not seen in training", ", ".join(levels))
        return codes

    def to_dict(self) -> dict[str, Any]:
        return {
            "numeric": self.numeric, "categorical": self.categorical,
            "mean": self.mean_.tolist(), "scale": self.scale_.tolist(),
            "min": self.min_.tolist(), "max": self.max_.tolist(),
            "categories": self.categories_,
        }

    @classmethod
    def from_dict(cls, d: dict[str, Any]) -> Preprocessor:
        p = cls(d["numeric"], d["categorical"])
        p.mean_ = np.asarray(d["mean"], dtype=np.float64)
        p.scale_ = np.asarray(d["scale"], dtype=np.float64)
        p.min_ = np.asarray(d["min"], dtype=np.float64)
        p.max_ = np.asarray(d["max"], dtype=np.float64)
        p.categories_ = {k: list(v) for k, v in d["categories"].items()}
        return p


# ---------------------------------------------------------------------------
# torch module
# ---------------------------------------------------------------------------
class EnsembleModule(nn.Module):
    """Stacked MLP ensemble with the scaler and one-hot encoder baked in.

    ``forward(x_num, x_cat)`` takes raw features: ``x_num`` float32, shape
    (n, n_numeric), SI units as in the dataset; ``x_cat`` int64, shape
    (n, n_categorical), level codes (see ``metadata.json``). It returns a
    float32 tensor (n, 4): mean, sigma, lower and upper interval bound of the
    target (log10 damage rate per hour), the interval being
    mean -/+ ``conformal_q`` * sigma.
    """

    def __init__(self, n_numeric: int, n_levels: Sequence[int], n_members: int,
                 hidden: Sequence[int], activation: str = "hardswish",
                 gaussian: bool = True) -> None:
        super().__init__()
        self.n_numeric = int(n_numeric)
        self.n_levels = [int(v) for v in n_levels]
        self.n_members = int(n_members)
        self.hidden = [int(h) for h in hidden]
        self.activation = str(activation)
        self.gaussian = bool(gaussian)
        self.logvar_min = float(LOGVAR_MIN)
        self.logvar_max = float(LOGVAR_MAX)
        self.spread_floor = float(SPREAD_FLOOR)
        cat_col = [j for j, n in enumerate(self.n_levels) for _ in range(n)]
        cat_code = [c for n in self.n_levels for c in range(n)]
        self.register_buffer("cat_col", torch.tensor(cat_col, dtype=torch.long))
        self.register_buffer("cat_code", torch.tensor(cat_code, dtype=torch.long))
        self.register_buffer("x_mean", torch.zeros(self.n_numeric))
        self.register_buffer("x_scale", torch.ones(self.n_numeric))
        self.register_buffer("y_mean", torch.zeros(()))
        self.register_buffer("y_scale", torch.ones(()))
        self.register_buffer("conformal_q", torch.zeros(()))
        sizes = [self.n_numeric + len(cat_col), *self.hidden, 2 if self.gaussian else 1]
        self.n_layers = len(sizes) - 1
        self.weights = nn.ParameterList(
            [nn.Parameter(torch.zeros(self.n_members, a, b))
             for a, b in zip(sizes[:-1], sizes[1:], strict=True)])
        self.biases = nn.ParameterList(
            [nn.Parameter(torch.zeros(self.n_members, 1, b)) for b in sizes[1:]])

    def init_members(self, seeds: Sequence[int]) -> None:
        """Initialise member m from ``seeds[m]`` as ``nn.Linear`` does (U(+-1/sqrt(fan_in)))."""
        with torch.no_grad():
            for m, seed in enumerate(seeds):
                gen = torch.Generator().manual_seed(int(seed))
                for w, b in zip(self.weights, self.biases, strict=False):
                    bound = 1.0 / math.sqrt(w.shape[1])
                    w[m].copy_(torch.rand(w.shape[1:], generator=gen) * 2 * bound - bound)
                    b[m].copy_(torch.rand(b.shape[1:], generator=gen) * 2 * bound - bound)

    def _act(self, h: Tensor) -> Tensor:
        if self.activation == "relu":
            return torch.relu(h)
        if self.activation == "tanh":
            return torch.tanh(h)
        if self.activation == "gelu":
            return nn.functional.gelu(h)
        if self.activation == "hardswish":
            return nn.functional.hardswish(h)
        return nn.functional.silu(h)

    def encode(self, x_num: Tensor, x_cat: Tensor) -> Tensor:
        """Scaled numeric features and one-hot levels, shape (n, n_in)."""
        z = (x_num - self.x_mean) / self.x_scale
        if self.cat_col.shape[0] > 0:
            onehot = (x_cat[:, self.cat_col] == self.cat_code).to(z.dtype)
            z = torch.cat([z, onehot], dim=1)
        return z

    def members(self, z: Tensor) -> tuple[Tensor, Tensor]:
        """Per-member mean and log-variance in scaled target units.

        ``z``: (M, n, n_in) (each member its own rows, training) or (n, n_in)
        (shared rows, inference). Returns two tensors of shape (M, n).

        Shared rows run feature-major, h^T = W^T h^T, so that the row count is
        the long dimension of every GEMM: the first layer of all members is one
        (M*width, n_in) x (n_in, n) product, and the 2-wide output layer costs
        67 ns per row instead of 422 ns as (n, 64) x (64, 2) products (one
        thread, 2048 rows, 5 x 64 x 64 members, best of 400 interleaved runs:
        1.07 us per row against 1.36 us).
        """
        if z.dim() == 2:
            return self._members_shared(z)
        h = z
        for i, (w, b) in enumerate(zip(self.weights, self.biases)):  # noqa: B905 - TorchScript: no strict=
            h = torch.baddbmm(b, h, w)
            if i < self.n_layers - 1:
                h = self._act(h)
        return self._heads(h[:, :, 0], h[:, :, 1] if self.gaussian else h[:, :, 0])

    def _members_shared(self, z: Tensor) -> tuple[Tensor, Tensor]:
        n = z.shape[0]
        h = z.t()
        for i, (w, b) in enumerate(zip(self.weights, self.biases)):  # noqa: B905 - TorchScript: no strict=
            if i == 0:
                width = w.shape[2]
                rows = self.n_members * width
                h = torch.addmm(b.permute(0, 2, 1).reshape(rows, 1),
                                w.permute(0, 2, 1).reshape(rows, w.shape[1]), h)
                h = h.view(self.n_members, width, n)
            else:
                h = torch.baddbmm(b.transpose(1, 2), w.transpose(1, 2), h)
            if i < self.n_layers - 1:
                h = self._act(h)
        return self._heads(h[:, 0, :], h[:, 1, :] if self.gaussian else h[:, 0, :])

    def _heads(self, mu: Tensor, raw_logvar: Tensor) -> tuple[Tensor, Tensor]:
        if self.gaussian:
            logvar = torch.clamp(raw_logvar, self.logvar_min, self.logvar_max)
        else:
            logvar = torch.zeros_like(mu)
        return mu, logvar

    def forward(self, x_num: Tensor, x_cat: Tensor) -> Tensor:
        mu_m, logvar_m = self.members(self.encode(x_num, x_cat))
        mu = mu_m.mean(dim=0)
        spread = ((mu_m - mu) ** 2).mean(dim=0)
        if self.gaussian:
            var = torch.exp(logvar_m).mean(dim=0) + spread
        else:
            var = spread + self.spread_floor**2
        mean_y = mu * self.y_scale + self.y_mean
        sigma_y = torch.sqrt(var) * self.y_scale
        half = self.conformal_q * sigma_y
        return torch.stack([mean_y, sigma_y, mean_y - half, mean_y + half], dim=1)

    @torch.jit.export
    def forward_chunked(self, x_num: Tensor, x_cat: Tensor, chunk: int) -> Tensor:
        """:meth:`forward` over consecutive blocks of ``chunk`` rows (same result).

        Blocks keep the activations in cache; the loop runs inside the module,
        so a TorchScript-compiled module walks a whole share of a batch
        without returning to Python (no per-block interpreter overhead).
        """
        n = x_num.shape[0]
        out = torch.empty((n, 4), dtype=x_num.dtype, device=x_num.device)
        for a in range(0, n, chunk):
            b = min(a + chunk, n)
            out[a:b] = self.forward(x_num[a:b], x_cat[a:b])
        return out


# ---------------------------------------------------------------------------
# estimator
# ---------------------------------------------------------------------------
@dataclass(frozen=True)
class TrainingSettings:
    """How :class:`DeepEnsembleRegressor` trains its members (one hyper-parameter of it).

    Parameters
    ----------
    learning_rate, weight_decay : float
        Adam settings.
    batch_size, max_epochs, patience : int
        Minibatch size; epochs at most; early stopping when the validation loss
        of a member has not improved for ``patience`` epochs (its best state is
        kept).
    nll_beta : float
        beta of the beta-NLL training loss (Seitzer et al., "On the pitfalls of
        heteroscedastic uncertainty estimation with probabilistic neural
        networks", ICLR 2022): the per-row NLL is weighted by sigma^(2 beta)
        (no gradient through the weight). beta = 0 is the plain Gaussian NLL;
        0.5 keeps the mean fit from being starved where the variance is large.
    stop_on : {"mse", "nll"}
        Validation metric of early stopping: the member's mean squared error
        (default: the mean is what matters, sigma is recalibrated by split
        conformal prediction afterwards) or its plain Gaussian NLL.
    validation_fraction : float
        Fraction of rows (of groups, if ``groups`` is given to ``fit``) held
        out for early stopping.
    random_state : int
        Seed of the validation split (shared by all members, so a member's
        result does not depend on the other members).
    n_threads : int
        ``torch.set_num_threads`` during fit.
    """

    learning_rate: float = 2e-3
    weight_decay: float = 0.0
    batch_size: int = 256
    max_epochs: int = 300
    patience: int = 30
    validation_fraction: float = 0.15
    nll_beta: float = 0.5
    stop_on: str = "mse"
    random_state: int = 0
    n_threads: int = 2


class DeepEnsembleRegressor(RegressorMixin, BaseEstimator):
    """Deep ensemble regressor with the scikit-learn estimator contract.

    Parameters
    ----------
    numeric_features : sequence of str or None
        Numeric columns of ``X`` (a DataFrame). ``None``: every column not in
        ``categorical_features`` (and all columns of a plain array).
    categorical_features : sequence of str
        Categorical columns, one-hot encoded inside.
    seeds : sequence of int
        One seed per member (>= 5 members recommended).
    hidden_layers : sequence of int
        Widths of the hidden layers of each member.
    activation : {"silu", "hardswish", "relu", "tanh", "gelu"}
    loss : {"gaussian_nll", "mse"}
        Gaussian NLL with a log-variance head, or MSE with the ensemble spread
        as sigma.
    censor_below : float or None
        Censoring level of the target (e.g. log10 of 1 / horizon): a row with
        ``y <= censor_below`` only says "the target is at most this" (a life
        beyond the horizon). Its likelihood is the Gaussian's probability
        mass below the level, P(Y <= c) = Phi((c - mu) / sigma), so the loss
        is -log Phi((c - mu) / sigma) (Tobit-type censored likelihood) instead
        of the density at the recorded value; with ``loss="mse"`` and in the
        validation metric it is the squared excess max(mu - c, 0)^2. None: no
        row is censored.
    training : TrainingSettings, optional
        Optimiser, early stopping, validation split and threads (default:
        :class:`TrainingSettings`' defaults).

    Attributes
    ----------
    preprocessor_ : Preprocessor
    module_ : EnsembleModule
    history_ : dict with "train_loss", "val_loss" (n_epochs, M) arrays and "best_epoch"
    n_features_in_ : int
    """

    def __init__(self, numeric_features: Sequence[str] | None = None,
                 categorical_features: Sequence[str] = (),
                 seeds: Sequence[int] = (0, 1, 2, 3, 4),
                 hidden_layers: Sequence[int] = (64, 64), activation: str = "hardswish",
                 loss: str = "gaussian_nll", censor_below: float | None = None,
                 training: TrainingSettings | None = None) -> None:
        self.numeric_features = numeric_features
        self.categorical_features = categorical_features
        self.seeds = seeds
        self.hidden_layers = hidden_layers
        self.activation = activation
        self.loss = loss
        self.censor_below = censor_below
        self.training = training

    @property
    def _settings(self) -> TrainingSettings:
        """The training settings in force (``training``, or the defaults)."""
        return self.training if self.training is not None else TrainingSettings()

    # -- data ---------------------------------------------------------------
    def _as_frame(self, X: Any) -> pd.DataFrame:
        if isinstance(X, pd.DataFrame):
            return X
        arr = np.asarray(X, dtype=np.float64)
        if arr.ndim != 2:
            raise InputError("X", f"must be 2-D, got shape {arr.shape}", "(n_rows, n_features)")
        return pd.DataFrame(arr, columns=[f"x{i}" for i in range(arr.shape[1])])

    def _encode(self, X: Any) -> tuple[np.ndarray, np.ndarray]:
        frame = self._as_frame(X)
        p = self.preprocessor_
        return p.numeric_array(frame), p.category_codes(frame)

    # -- fit ----------------------------------------------------------------
    def fit(self, X: Any, y: Any, groups: Any = None,
            callback: EpochCallback | None = None) -> DeepEnsembleRegressor:
        """Fit all members; ``groups`` (e.g. case ids) keeps the validation split by group.

        ``callback(epoch, train_loss (M,), val_loss (M,), active (M,) bool)``
        is called after every epoch (used for dvclive logging).
        """
        if self.loss not in ("gaussian_nll", "mse"):
            raise InputError("loss", f"unknown loss {self.loss!r}", "gaussian_nll, mse")
        stop_on = self._settings.stop_on
        if stop_on not in ("mse", "nll"):
            raise InputError("stop_on", f"unknown metric {stop_on!r}", "mse, nll")
        if self.activation not in ACTIVATIONS:
            raise InputError("activation", f"unknown activation {self.activation!r}",
                             ", ".join(ACTIVATIONS))
        frame = self._as_frame(X)
        cats = list(self.categorical_features)
        nums = (list(self.numeric_features) if self.numeric_features is not None
                else [c for c in frame.columns if c not in cats])
        yv = np.asarray(y, dtype=np.float64).reshape(-1)
        if yv.shape[0] != len(frame):
            raise InputError("y", f"has {yv.shape[0]} rows, X has {len(frame)}", "equal lengths")
        if not np.all(np.isfinite(yv)):
            raise InputError("y", "NaN or infinite target", "finite numbers")
        self.preprocessor_ = Preprocessor(nums, cats).fit(frame)
        x_num, x_cat = self._encode(frame)
        self.n_features_in_ = x_num.shape[1] + x_cat.shape[1]
        self.feature_names_in_ = np.asarray(nums + cats, dtype=object)

        seeds = [int(s) for s in self.seeds]
        rng = np.random.default_rng(int(self._settings.random_state))
        n = len(yv)
        if groups is not None:
            g = np.asarray(groups)
            ug = np.unique(g)
            n_val_g = max(1, int(round(self._settings.validation_fraction * len(ug))))
            val_groups = rng.choice(ug, size=n_val_g, replace=False)
            is_val = np.isin(g, val_groups)
        else:
            n_val = max(1, int(round(self._settings.validation_fraction * n)))
            is_val = np.zeros(n, dtype=bool)
            is_val[rng.choice(n, size=n_val, replace=False)] = True
        if is_val.all() or not is_val.any():
            raise InputError("X", "too few rows/groups for a validation split",
                             ">= 2 groups (rows)")

        module = EnsembleModule(x_num.shape[1], [len(self.preprocessor_.categories_[c]) for c in cats],
                                len(seeds), self.hidden_layers, self.activation,
                                self.loss == "gaussian_nll")
        module.init_members(seeds)
        y_mean = float(yv[~is_val].mean())
        y_std = float(yv[~is_val].std()) or 1.0
        # censoring level in scaled target units (-inf: no row is censored)
        self.censor_scaled_ = (-math.inf if self.censor_below is None
                               else (float(self.censor_below) - y_mean) / y_std)
        with torch.no_grad():
            module.x_mean.copy_(torch.as_tensor(self.preprocessor_.mean_, dtype=torch.float32))
            module.x_scale.copy_(torch.as_tensor(self.preprocessor_.scale_, dtype=torch.float32))
            module.y_mean.fill_(y_mean)
            module.y_scale.fill_(y_std)

        old_threads = torch.get_num_threads()
        torch.set_num_threads(int(self._settings.n_threads))
        try:
            self.history_ = self._train(module, x_num, x_cat, (yv - y_mean) / y_std,
                                        is_val, seeds, callback)
        finally:
            torch.set_num_threads(old_threads)
        module.eval()
        self.module_ = module
        return self

    def _member_loss(self, module: EnsembleModule, z: Tensor, y: Tensor,
                     beta: float = 0.0) -> Tensor:
        mu, logvar = module.members(z)
        c = self.censor_scaled_
        cens = y <= c
        if module.gaussian:
            per = 0.5 * (logvar + (y - mu) ** 2 * torch.exp(-logvar))
            if math.isfinite(c):  # censored rows: -log P(Y <= c)
                zc = (c - mu) * torch.exp(-0.5 * logvar)
                per = torch.where(cens, -torch.special.log_ndtr(zc), per)
            if beta > 0.0:  # beta-NLL weight sigma^(2 beta), no gradient through it
                per = per * torch.exp(beta * logvar.detach())
        else:
            per = self._squared_error(mu, y, cens, c)
        return per.mean(dim=1)  # (M,)

    @staticmethod
    def _squared_error(mu: Tensor, y: Tensor, cens: Tensor, c: float) -> Tensor:
        """(mu - y)^2, and max(mu - c, 0)^2 on censored rows (any mu <= c is right there)."""
        if not math.isfinite(c):
            return (mu - y) ** 2
        return torch.where(cens, torch.relu(mu - c) ** 2, (mu - y) ** 2)

    def _train(self, module: EnsembleModule, x_num: np.ndarray, x_cat: np.ndarray,
               ys: np.ndarray, is_val: np.ndarray, seeds: list[int],
               callback: EpochCallback | None) -> dict[str, Any]:
        with torch.no_grad():
            z_all = module.encode(torch.as_tensor(x_num, dtype=torch.float32),
                                  torch.as_tensor(x_cat, dtype=torch.long))
        y_all = torch.as_tensor(ys, dtype=torch.float32)
        z_tr, y_tr = z_all[~torch.as_tensor(is_val)], y_all[~torch.as_tensor(is_val)]
        z_va, y_va = z_all[torch.as_tensor(is_val)], y_all[torch.as_tensor(is_val)]
        n_tr = z_tr.shape[0]
        M = len(seeds)
        rngs = [np.random.default_rng(s + 7919) for s in seeds]
        opt = torch.optim.Adam(module.parameters(), lr=float(self._settings.learning_rate),
                               weight_decay=float(self._settings.weight_decay))
        best = np.full(M, np.inf)
        best_epoch = np.zeros(M, dtype=np.int64)
        best_state = [copy.deepcopy([p.detach()[m].clone() for p in module.parameters()])
                      for m in range(M)]
        active = np.ones(M, dtype=bool)
        bs = min(int(self._settings.batch_size), n_tr)
        train_hist, val_hist = [], []
        for epoch in range(int(self._settings.max_epochs)):
            perms = np.stack([r.permutation(n_tr) for r in rngs])  # (M, n_tr)
            module.train()
            tot = torch.zeros(M)
            for start in range(0, n_tr, bs):
                idx = torch.as_tensor(perms[:, start:start + bs])
                zb = z_tr[idx]  # (M, b, n_in)
                yb = y_tr[idx]  # (M, b)
                loss_m = self._member_loss(module, zb, yb, float(self._settings.nll_beta))
                opt.zero_grad(set_to_none=True)
                loss_m.sum().backward()
                opt.step()
                tot += loss_m.detach() * idx.shape[1]
            module.eval()
            with torch.no_grad():
                if self._settings.stop_on == "mse":
                    mu_va, _ = module.members(z_va)
                    c = self.censor_scaled_
                    val = self._squared_error(mu_va, y_va, y_va <= c, c).mean(dim=1)
                    val = val.numpy().astype(np.float64)
                else:
                    val = self._member_loss(module, z_va, y_va).numpy().astype(np.float64)
            tr = (tot / n_tr).numpy().astype(np.float64)
            train_hist.append(tr)
            val_hist.append(val)
            for m in np.flatnonzero(active):
                if val[m] < best[m]:
                    best[m] = val[m]
                    best_epoch[m] = epoch
                    best_state[m] = [p.detach()[m].clone() for p in module.parameters()]
                elif epoch - best_epoch[m] >= int(self._settings.patience):
                    active[m] = False
            if callback is not None:
                callback(epoch, tr, val, active.copy())
            if not active.any():
                break
        with torch.no_grad():
            for m in range(M):
                for p, s in zip(module.parameters(), best_state[m], strict=False):
                    p[m].copy_(s)
        return {"train_loss": np.asarray(train_hist), "val_loss": np.asarray(val_hist),
                "best_epoch": best_epoch, "best_val_loss": best}

    # -- predict ------------------------------------------------------------
    def _check_fitted(self) -> None:
        if not hasattr(self, "module_"):
            raise NotFittedError("DeepEnsembleRegressor is not fitted yet; call fit first")

    def predict_raw(self, x_num: np.ndarray, x_cat: np.ndarray | None = None) -> np.ndarray:
        """Module output for encoded arrays: float64 (n, 4) mean, sigma, lower, upper."""
        self._check_fitted()
        if x_cat is None:
            x_cat = np.zeros((x_num.shape[0], 0), dtype=np.int64)
        with torch.inference_mode():
            out = self.module_(torch.as_tensor(x_num, dtype=torch.float32),
                               torch.as_tensor(x_cat, dtype=torch.long))
        return out.numpy().astype(np.float64)

    def predict_dist(self, X: Any) -> tuple[np.ndarray, np.ndarray]:
        """Predictive mean and standard deviation, each shape (n,)."""
        self._check_fitted()
        out = self.predict_raw(*self._encode(X))
        return out[:, 0], out[:, 1]

    def predict(self, X: Any) -> np.ndarray:
        """Predictive mean, shape (n,)."""
        return self.predict_dist(X)[0]
