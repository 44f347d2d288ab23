"""The :class:`Surrogate` facade: a fitted ensemble + conformal intervals + domain check.

``Surrogate.load(path).predict(frame)`` is the public query API. A saved model
is a folder::

    metadata.json     feature lists, category levels, scaler, ranges, conformal
                      quantile (and the served gbm's calibration, bins,
                      half-widths and training cases), OOD threshold, target,
                      versions, training summary
    ensemble.pt       torch state dict of the EnsembleModule (weights only)
    gbm.pkl           the gradient-boosting model when it is the served one
                      (``surrogate.served_model: gbm``; pickled scikit-learn,
                      SHA-256 in metadata.json)
    ood_reference.npy standardised reference rows of the k-NN domain test
    model.ts          TorchScript export, scaler and conformal quantile baked in
    model.onnx        the same as ONNX (onnxruntime servers)
"""

from __future__ import annotations

import hashlib
import json
import math
import pickle
import platform
import warnings
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd
import torch

from drillfatigue import __version__
from drillfatigue.config.surrogate import SurrogateConfig
from drillfatigue.errors import InputError
from drillfatigue.files import OutputFolder, atomic_output
from drillfatigue.surrogate.conformal import SplitConformal
from drillfatigue.surrogate.data import case_folds, check_columns, gbm_rows, log10_target, split_by_case
from drillfatigue.surrogate.export import export_onnx, export_torchscript
from drillfatigue.surrogate.gbm import FlatForest, design_matrix, monotone_constraints
from drillfatigue.surrogate.model import (DeepEnsembleRegressor, EnsembleModule, Preprocessor,
                                          TrainingSettings)
from drillfatigue.surrogate.ood import DomainChecker
from drillfatigue.surrogate.parallel import map_chunks
from drillfatigue.surrogate.served_gbm import fit_served_gbm, half_width, interval_bins, scale_model

FORMAT_VERSION = 1
#: Kind of the ownership marker of a model folder (:class:`drillfatigue.files.OutputFolder`).
MODEL_KIND = "model"
#: Files a model folder may hold (the exports only when saved with ``export=True``).
MODEL_FILES = ("metadata.json", "ensemble.pt", "ood_reference.npy", "model.ts", "model.onnx",
               "gbm.pkl")
_CHUNK_ROWS = 1024  # rows per forward pass in predict_array: the fastest measured of 512-4096
_ONE_THREAD_ROWS = 256  # up to this many rows, predict on one torch thread

#: output columns of :meth:`Surrogate.predict`
PREDICTION_COLUMNS = (
    "log10_damage_rate_per_h", "log10_damage_rate_per_h_lower", "log10_damage_rate_per_h_upper",
    "sigma_log10", "damage_rate_per_h", "damage_rate_per_h_lower", "damage_rate_per_h_upper",
    "life_h", "life_h_lower", "life_h_upper", "beyond_horizon", "ood", "ood_reason",
)


def regressor_from_config(cfg: SurrogateConfig) -> DeepEnsembleRegressor:
    """The ensemble estimator with the hyper-parameters of the ``surrogate`` section."""
    training = TrainingSettings(
        learning_rate=cfg.learning_rate, weight_decay=cfg.weight_decay,
        batch_size=cfg.batch_size, max_epochs=cfg.max_epochs, patience=cfg.patience,
        validation_fraction=cfg.validation_fraction, nll_beta=cfg.nll_beta,
        stop_on=cfg.stop_on, random_state=cfg.split_seed, n_threads=cfg.n_threads)
    return DeepEnsembleRegressor(
        numeric_features=list(cfg.features), categorical_features=list(cfg.categorical),
        seeds=list(cfg.seeds), hidden_layers=list(cfg.hidden_layers),
        activation=cfg.activation, loss=cfg.loss, censor_below=censor_level(cfg),
        training=training)


def censor_level(cfg: SurrogateConfig) -> float | None:
    """log10 damage rate per hour at the horizon (-log10 horizon_h); None without censoring."""
    return -math.log10(cfg.horizon_h) if cfg.censoring == "likelihood" else None


class Surrogate:
    """Fitted estimator of log10 damage rate per hour with intervals and OOD flag.

    Build with :meth:`fit` (or :func:`fit_surrogate`) or :meth:`load`.
    """

    def __init__(self, module: EnsembleModule, preprocessor: Preprocessor,
                 domain: DomainChecker, metadata: dict[str, Any], gbm: Any = None) -> None:
        self.module = module.eval()
        # served gradient boosting (None: the ensemble answers)
        self.gbm = gbm
        # the served gbm's trees, and its scale model's (gbm_interval: scaled), as one flat forest
        self._forest: FlatForest | None = None
        # the served gbm's interval bins as arrays (edges, half-widths), built with the forest
        self._bins: tuple[np.ndarray, np.ndarray] | None = None
        self._scripted: torch.jit.ScriptModule | None = None
        self.preprocessor = preprocessor
        self.domain = domain
        self.metadata = metadata

    # -- properties ---------------------------------------------------------
    @property
    def features(self) -> list[str]:
        """Numeric feature columns (SI), model order."""
        return list(self.preprocessor.numeric)

    @property
    def categorical(self) -> list[str]:
        return list(self.preprocessor.categorical)

    @property
    def categories(self) -> dict[str, list[str]]:
        return dict(self.preprocessor.categories_)

    @property
    def coverage(self) -> float:
        return float(self.metadata["coverage"])

    @property
    def conformal_quantile(self) -> float:
        return float(self.module.conformal_q.item())

    # -- fit ----------------------------------------------------------------
    @property
    def horizon_h(self) -> float | None:
        """Life horizon (h) beyond which an answer is "longer than"; None for older models."""
        h = self.metadata.get("horizon_h")
        return None if h is None else float(h)

    @classmethod
    def fit(cls, frame: pd.DataFrame, cfg: SurrogateConfig,
            callback: Callable[[int, np.ndarray, np.ndarray, np.ndarray], None] | None = None,
            design_bounds: dict[str, tuple[float, float]] | None = None) -> Surrogate:
        """Split by case, fit the ensemble, calibrate intervals and the domain test.

        Parameters
        ----------
        frame : DataFrame
            Dataset with the configured feature, categorical, group and target
            columns.
        cfg : SurrogateConfig
        callback : callable, optional
            Per-epoch hook of :meth:`DeepEnsembleRegressor.fit`.
        design_bounds : dict, optional
            Design range (low, high) per numeric feature that the sweep varied
            (or derived from it); the domain test refuses queries outside
            it. Features not in it are bounded by the training rows
            (:func:`drillfatigue.surrogate.bounds.domain_bounds`).
        """
        check_columns(frame, cfg)
        y = log10_target(frame[cfg.target_column].to_numpy(), cfg.rate_floor_per_h)
        groups = frame[cfg.group_column].to_numpy()
        split = split_by_case(groups, cfg)
        reg = regressor_from_config(cfg)
        tr = frame.loc[split.train]
        reg.fit(tr, y[split.train], groups=groups[split.train], callback=callback)
        cal = frame.loc[split.calibration]
        mu_c, sd_c = reg.predict_dist(cal)
        conf = SplitConformal(cfg.coverage).fit(mu_c, sd_c, y[split.calibration],
                                                censor_below=censor_level(cfg))
        if not np.isfinite(conf.quantile_):
            raise InputError("surrogate.calibration_fraction",
                             "too few calibration rows for the coverage", "a larger fraction")
        module = reg.module_
        with torch.no_grad():
            module.conformal_q.fill_(conf.quantile_)
        p = reg.preprocessor_
        domain = DomainChecker(p.numeric, cfg.ood_k, cfg.ood_quantile, cfg.ood_reference_rows,
                               cfg.split_seed)
        gbm = None
        gbm_meta: dict[str, Any] | None = None
        fit_rows: np.ndarray | None = None
        cal_rows: np.ndarray | None = None
        if cfg.served_model == "gbm":
            # the gradient boosting trains on every case the evaluation does not
            # score (the held-out design when heldout_path is set) and is
            # calibrated as the evaluation's baseline is (one procedure)
            fit_rows, cal_rows = gbm_rows(split, cfg, heldout=cfg.heldout_path is not None)
            x_all = design_matrix(p, *reg._encode(frame))
            gbm, gbm_meta = fit_served_gbm(x_all, y, groups, fit_rows, cal_rows, cfg,
                                           monotone_constraints(p))
        if fit_rows is not None and cal_rows is None:
            # the served model's domain is every case it trains on; with no
            # calibration cases apart, the threshold is cross-fitted on the
            # cross-conformal folds of those cases
            fit_frame = frame.loc[fit_rows]
            domain.fit_cross(p.numeric_array(fit_frame),
                             case_folds(groups[fit_rows],
                                        min(cfg.conformal_folds,
                                            int(np.unique(groups[fit_rows]).size)),
                                        cfg.split_seed),
                             p.mean_, p.scale_, design_bounds,
                             cat=p.category_codes(fit_frame), categories=p.categories_)
        else:
            domain.fit(p.numeric_array(tr), p.numeric_array(cal), p.mean_, p.scale_,
                       design_bounds, cat_train=p.category_codes(tr),
                       cat_cal=p.category_codes(cal), categories=p.categories_)
        hist = reg.history_
        meta = {
            "format_version": FORMAT_VERSION,
            "target": "log10_damage_rate_per_h",
            "target_column": cfg.target_column,
            "criterion": cfg.criterion,
            "rate_floor_per_h": cfg.rate_floor_per_h,
            "horizon_h": cfg.horizon_h,
            "censoring": cfg.censoring,
            "coverage": cfg.coverage,
            "n_calibration": conf.n_calibration_,
            "architecture": {"n_numeric": module.n_numeric, "n_levels": module.n_levels,
                             "n_members": module.n_members, "hidden": module.hidden,
                             "activation": module.activation, "gaussian": module.gaussian},
            "config": cfg.model_dump(mode="json"),
            "split": {"train_cases": sorted(map(str, np.unique(groups[split.train]))),
                      "calibration_cases": sorted(map(str, np.unique(groups[split.calibration]))),
                      "test_cases": sorted(map(str, np.unique(groups[split.test])))},
            "training": {"epochs": int(hist["train_loss"].shape[0]),
                         "best_epoch": hist["best_epoch"].tolist(),
                         "best_val_loss": hist["best_val_loss"].tolist(),
                         "n_train_rows": int(split.train.sum())},
            "served_model": cfg.served_model,
            "gbm": gbm_meta,
        }
        return cls(module, p, domain, meta, gbm)

    # -- encode -------------------------------------------------------------
    def encode(self, frame: pd.DataFrame) -> tuple[np.ndarray, np.ndarray]:
        """Raw numeric array (n, n_numeric) float64 and category codes (n, n_cat) int64.

        Raises InputError for a missing column, a NaN or non-numeric value, or
        an unseen category level.
        """
        return self.preprocessor.numeric_array(frame), self.preprocessor.category_codes(frame)

    # -- predict ------------------------------------------------------------
    def batch_module(self) -> torch.jit.ScriptModule:
        """The network compiled by TorchScript, for batches (built on first use).

        It shares the parameters and buffers of :attr:`module` (so in-place
        updates show through) and runs its operator graph without the Python
        interpreter, so chunk workers do not queue for the GIL between
        operators: measured +25 % median throughput on 1e5-row batches over
        2 workers, against the eager module in the same process. Single
        queries stay eager: the TorchScript profiling executor runs the first
        two calls unoptimised (slower than eager), so a served model should
        warm up with two batches.
        """
        if self._scripted is None:
            with warnings.catch_warnings():
                # torch 2.13 marks TorchScript deprecated; it is pinned and tested here
                warnings.simplefilter("ignore", DeprecationWarning)
                self._scripted = torch.jit.script(self.module)
        return self._scripted

    def predict_array(self, x_num: np.ndarray, x_cat: np.ndarray | None = None,
                      ood: bool = True, knn: bool = True,
                      distances: bool = False) -> dict[str, np.ndarray]:
        """Fast path on encoded arrays (no DataFrame round trip, no input checks).

        Parameters
        ----------
        x_num : ndarray, shape (n, n_numeric)
            Numeric features in SI, columns in :attr:`features` order.
        x_cat : ndarray of int, shape (n, n_categorical)
            Level codes (index into :attr:`categories`).
        ood : bool
            Compute the out-of-domain flag (``ood`` key; False everywhere if not).
        knn : bool
            Include the k-NN joint-distance test (else per-feature ranges only).
        distances : bool
            The k-NN distance of every row in ``knn_distance``; by default
            only that of the rows beyond the threshold (the number a refusal
            names), NaN for the others, whose search stops once they are
            certainly within it (the flags are the same either way).

        Returns
        -------
        dict of ndarray, shape (n,)
            ``log10``, ``sigma``, ``lower``, ``upper`` (log10 damage rate per
            hour and its interval, also for out-of-domain rows: the caller
            decides to refuse them), ``beyond_horizon`` (bool: predicted life
            longer than :attr:`horizon_h`), ``ood`` (bool), ``knn_distance``
            (see ``distances``).
        """
        x_num = np.asarray(x_num, dtype=np.float64)
        if x_cat is None:
            x_cat = np.zeros((x_num.shape[0], len(self.categorical)), dtype=np.int64)
        if self.gbm is not None:
            return self._predict_gbm(x_num, x_cat, ood, knn, distances)
        xt = torch.from_numpy(x_num.astype(np.float32))
        ct = torch.from_numpy(np.ascontiguousarray(x_cat, dtype=np.int64))
        out = np.empty((x_num.shape[0], 4), dtype=np.float32)
        n = x_num.shape[0]

        if n <= _ONE_THREAD_ROWS:
            # few rows: one eager pass on the calling thread (waking a pool costs more)
            with torch.inference_mode():
                out[:] = self.module(xt, ct).numpy()
        else:
            # many rows: 2 shares per worker (a preempted worker delays one share,
            # not half the batch), each walked in cache-sized blocks inside the
            # TorchScript network (one Python call per block is slower:
            # docs/performance.md)
            net = self.batch_module()
            parts = 2 * max(1, torch.get_num_threads())
            share = -(-n // (parts * _CHUNK_ROWS)) * _CHUNK_ROWS

            def run(a: int) -> None:
                with torch.inference_mode():
                    out[a:a + share] = net.forward_chunked(xt[a:a + share], ct[a:a + share],
                                                           _CHUNK_ROWS).numpy()

            map_chunks(run, range(0, n, share))
        res = {"log10": out[:, 0].astype(np.float64), "sigma": out[:, 1].astype(np.float64),
               "lower": out[:, 2].astype(np.float64), "upper": out[:, 3].astype(np.float64)}
        return self._finish(res, x_num, x_cat, ood, knn, distances)

    def _predict_gbm(self, x_num: np.ndarray, x_cat: np.ndarray, ood: bool,
                     knn: bool, distances: bool) -> dict[str, np.ndarray]:
        """:meth:`predict_array` of the served gradient boosting.

        The trees are evaluated by :class:`~drillfatigue.surrogate.gbm.FlatForest`
        (built on first use; the same numbers as ``self.gbm.predict`` on the
        design matrix), the scale model's in the same pass. The interval's
        half-width is that of the prediction's bin of log10 rate (Mondrian conformal,
        :func:`~drillfatigue.surrogate.conformal.mondrian_bins`) when the
        model has bins, times the row's scale from the scale model for a
        ``scaled`` interval (:mod:`~drillfatigue.surrogate.served_gbm`), else
        the one global conformal quantile (models saved with
        ``gbm_interval: constant`` or before the bins existed).
        """
        g = self.metadata["gbm"]
        if self._forest is None:
            # the scale model's trees share the regressor's pass (inputs ranked once)
            sm = scale_model(self.gbm)
            self._forest = FlatForest(self.gbm, self.preprocessor,
                                      extra=() if sm is None else (sm,))
            self._bins = interval_bins(g)
        out = self._forest.predict(x_num, x_cat)
        if self._forest.n_outputs == 1:
            mu, scale = out, None
        else:
            mu, scale = np.ascontiguousarray(out[:, 0]), np.exp(out[:, 1])
        half = half_width(mu, g, self._bins, scale)
        res = {"log10": mu, "sigma": np.full(mu.shape, float(g["sigma_log10"])),
               "lower": mu - half, "upper": mu + half}
        return self._finish(res, x_num, x_cat, ood, knn, distances)

    def _finish(self, res: dict[str, np.ndarray], x_num: np.ndarray, x_cat: np.ndarray,
                ood: bool, knn: bool, distances: bool) -> dict[str, np.ndarray]:
        """Add ``beyond_horizon``, ``ood`` and ``knn_distance`` to a prediction."""
        h = self.horizon_h
        res["beyond_horizon"] = (res["log10"] < -math.log10(h) if h is not None
                                 else np.zeros(x_num.shape[0], dtype=bool))
        if ood:
            flag, dist = self.domain.check(x_num, x_cat, knn=knn, distances=distances)
        else:
            flag, dist = np.zeros(x_num.shape[0], dtype=bool), np.full(x_num.shape[0], np.nan)
        res["ood"] = flag
        res["knn_distance"] = dist
        return res

    def predict(self, frame: pd.DataFrame, refuse: bool = True) -> pd.DataFrame:
        """Damage rate per hour, life in hours, interval and OOD flag per row.

        Parameters
        ----------
        frame : DataFrame
            One row per query with the model's feature columns (SI units,
            names as in the dataset; extra columns are ignored).

        Returns
        -------
        DataFrame, same index, columns :data:`PREDICTION_COLUMNS`. Rates are per
        hour of operation (Miner damage), lives in hours (1 / rate); the
        interval has the calibrated coverage :attr:`coverage`;
        ``beyond_horizon`` marks a predicted life longer than
        :attr:`horizon_h` (read it as "longer than the horizon": the model
        was trained on such lives as censored, not as numbers). With
        ``refuse`` (default) an out-of-domain row (``ood``, the reason in
        ``ood_reason``) has no number: NaN in every numeric column.
        """
        x_num, x_cat = self.encode(frame)
        r = self.predict_array(x_num, x_cat)
        reasons = self.domain.reasons(x_num, r["knn_distance"], r["ood"], x_cat)
        return prediction_frame(r, reasons, frame.index, refuse=refuse)

    # -- persistence --------------------------------------------------------
    def save(self, path: str | Path, export: bool = True, *, option: str = "--out") -> Path:
        """Write the model folder ``path``.

        The folder carries the ``model`` ownership marker
        (:class:`drillfatigue.files.OutputFolder`): a new or empty folder, or
        one an earlier save wrote, is accepted; any other is refused with
        :class:`InputError` (field ``option``) before anything is written,
        and a file of someone else's in it is never touched. Each file is
        written under a temporary name and renamed onto its final name;
        ``metadata.json``, which records the SHA-256 of the others, comes
        last, so :meth:`load` recognises a folder left half-rewritten. Model
        files of an earlier save that this one does not write (the exports
        when ``export`` is false) are removed.
        """
        folder = OutputFolder(path, MODEL_KIND, option)
        digests: dict[str, str] = {}

        def put(name: str, write: Callable[[Path], Any]) -> None:
            with atomic_output(folder.file(name)) as tmp:
                write(tmp)
                digests[name] = _sha256(tmp)

        put("ensemble.pt", lambda t: torch.save(self.module.state_dict(), t))
        put("ood_reference.npy", lambda t: np.save(t, self.domain.reference_))
        if self.gbm is not None:
            put("gbm.pkl", lambda t: t.write_bytes(pickle.dumps(self.gbm)))
        # the exports are the ensemble's network: written only when it is the served model
        if export and self.gbm is None:
            put("model.ts", lambda t: export_torchscript(self, t))
            put("model.onnx", lambda t: export_onnx(self, t))
        meta = dict(self.metadata)
        meta["preprocessor"] = self.preprocessor.to_dict()
        meta["domain"] = self.domain.to_dict()
        meta["conformal_quantile"] = self.conformal_quantile
        meta["versions"] = {"drillfatigue": __version__, "torch": torch.__version__,
                            "numpy": np.__version__, "python": platform.python_version()}
        meta["files_sha256"] = digests
        with atomic_output(folder.file("metadata.json")) as tmp:
            tmp.write_text(json.dumps(meta, indent=2), encoding="utf-8")
        folder.remove(n for n in MODEL_FILES if n not in digests and n != "metadata.json")
        return folder.path

    @classmethod
    def load(cls, path: str | Path) -> Surrogate:
        """Load a model folder written by :meth:`save`.

        A missing, truncated or malformed file raises :class:`InputError`
        naming the file (never a traceback from json, torch or numpy).
        """
        p = Path(path)
        allowed = "a complete model folder written by the train stage"
        meta_path = p / "metadata.json"
        if not meta_path.is_file():
            raise InputError(str(p), "not a surrogate model folder (no metadata.json)",
                             "a folder written by the train stage")
        try:
            meta = json.loads(meta_path.read_text(encoding="utf-8"))
            if not isinstance(meta, dict):
                raise TypeError("not a JSON object")
        except (ValueError, TypeError) as exc:  # JSON and UTF-8 errors are ValueErrors
            raise InputError(str(meta_path), f"malformed ({type(exc).__name__}: "
                             f"{str(exc)[:80]})", allowed) from None
        if meta.get("format_version") != FORMAT_VERSION:
            raise InputError(str(p), f"model format {meta.get('format_version')!r}",
                             f"format {FORMAT_VERSION}")
        for name, digest in (meta.get("files_sha256") or {}).items():
            f = p / str(name)
            if not f.is_file():
                raise InputError(str(f), "missing from the model folder", allowed)
            if _sha256(f) != digest:
                raise InputError(str(f), "does not match metadata.json (truncated, changed or "
                                 "left from another save)", allowed)
        what = str(meta_path)
        try:
            a = meta["architecture"]
            module = EnsembleModule(a["n_numeric"], a["n_levels"], a["n_members"], a["hidden"],
                                    a["activation"], a["gaussian"])
            pre = Preprocessor.from_dict(meta.pop("preprocessor"))
            what = str(p / "ensemble.pt")
            module.load_state_dict(torch.load(p / "ensemble.pt", weights_only=True))
            what = str(p / "ood_reference.npy")
            domain = DomainChecker.from_dict(meta.pop("domain"), np.load(p / "ood_reference.npy"))
            gbm = None
            if meta.get("served_model") == "gbm":
                what = str(p / "gbm.pkl")
                # our own file, its SHA-256 checked against metadata.json above
                gbm = pickle.loads((p / "gbm.pkl").read_bytes())  # noqa: S301
        except FileNotFoundError:
            raise InputError(what, "missing from the model folder", allowed) from None
        except (KeyError, TypeError, ValueError, RuntimeError, EOFError, OSError,
                pickle.UnpicklingError) as exc:
            raise InputError(what, f"truncated or malformed ({type(exc).__name__})",
                             allowed) from None
        meta.pop("conformal_quantile", None)
        meta.pop("versions", None)
        meta.pop("files_sha256", None)
        return cls(module, pre, domain, meta, gbm)


def _sha256(path: Path) -> str:
    h = hashlib.sha256()
    with open(path, "rb") as fh:
        for block in iter(lambda: fh.read(1 << 20), b""):
            h.update(block)
    return h.hexdigest()


def prediction_columns(r: dict[str, np.ndarray], reasons: np.ndarray,
                       refuse: bool = False) -> dict[str, np.ndarray]:
    """The :data:`PREDICTION_COLUMNS` as arrays from :meth:`Surrogate.predict_array` output.

    ``refuse``: out-of-domain rows get NaN in every number (no answer).
    """
    if refuse and np.any(r["ood"]):
        r = dict(r)
        for k in ("log10", "lower", "upper", "sigma"):
            r[k] = np.where(r["ood"], np.nan, r[k])
        r["beyond_horizon"] = r["beyond_horizon"] & ~r["ood"]
    rate = 10.0 ** r["log10"]
    lo = 10.0 ** r["lower"]
    hi = 10.0 ** r["upper"]
    return {
        "log10_damage_rate_per_h": r["log10"],
        "log10_damage_rate_per_h_lower": r["lower"],
        "log10_damage_rate_per_h_upper": r["upper"],
        "sigma_log10": r["sigma"],
        "damage_rate_per_h": rate, "damage_rate_per_h_lower": lo, "damage_rate_per_h_upper": hi,
        "life_h": 1.0 / rate, "life_h_lower": 1.0 / hi, "life_h_upper": 1.0 / lo,
        "beyond_horizon": r["beyond_horizon"], "ood": r["ood"], "ood_reason": reasons,
    }


def prediction_frame(r: dict[str, np.ndarray], reasons: np.ndarray,
                     index: Any = None, refuse: bool = False) -> pd.DataFrame:
    """Assemble the :data:`PREDICTION_COLUMNS` frame from :meth:`Surrogate.predict_array` output."""
    return pd.DataFrame(prediction_columns(r, reasons, refuse), index=index)


def _open_live(live_dir: str | Path) -> Any:
    """``dvclive.Live`` for a stage folder, also in a git repository without a commit.

    dvclive 3.x asks git for the baseline revision and raises SCMError ("Empty
    git repo") before the first commit (``git init; dvc init; dvc repro``);
    the curves do not need a revision, so retry as outside a repository.
    """
    import dvclive.live as dl  # optional extra [pipeline]: only to log training curves for DVC

    kwargs = {"dir": str(live_dir), "dvcyaml": None, "save_dvc_exp": False, "report": None}
    try:
        return dl.Live(**kwargs)
    except Exception as exc:  # scmrepo.exceptions.SCMError
        if type(exc).__name__ != "SCMError":
            raise
        original = dl.get_dvc_repo
        dl.get_dvc_repo = lambda: None
        try:
            return dl.Live(**kwargs)
        finally:
            dl.get_dvc_repo = original


def fit_surrogate(frame: pd.DataFrame, cfg: SurrogateConfig,
                  live_dir: str | Path | None = None,
                  bounds: dict[str, tuple[float, float]] | None = None) -> Surrogate:
    """Fit a :class:`Surrogate`; log per-member train/val loss per epoch with dvclive.

    ``live_dir``: dvclive folder (``Live(dir=..., dvcyaml=None,
    save_dvc_exp=False)``, for use inside a DVC stage); None: no logging.
    ``bounds``: ranges of the domain test
    (:func:`drillfatigue.surrogate.bounds.domain_bounds`).
    """
    if live_dir is None:
        return Surrogate.fit(frame, cfg, design_bounds=bounds)
    with _open_live(live_dir) as live:
        def log_epoch(epoch: int, tr: np.ndarray, va: np.ndarray, active: np.ndarray) -> None:
            for m in range(tr.shape[0]):
                live.log_metric(f"train/loss/member{m}", float(tr[m]), plot=True)
                live.log_metric(f"val/loss/member{m}", float(va[m]), plot=True)
            live.log_metric("active_members", int(active.sum()), plot=True)
            live.next_step()

        model = Surrogate.fit(frame, cfg, callback=log_epoch, design_bounds=bounds)
        live.summary["best_epoch"] = model.metadata["training"]["best_epoch"]
    return model
