"""Dataset access for the surrogate: target extraction, case-wise split, synthetic data.

The training table (``data/dataset/damage.parquet``) has one row per (case,
component location); its column names come from
:class:`drillfatigue.config.SurrogateConfig`, never from this module.

:func:`make_synthetic_dataset` builds a table with the same schema from a
documented analytic function (see its docstring), for tests and benchmarks
while the simulated dataset does not exist.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pandas as pd

from drillfatigue.config.surrogate import SurrogateConfig
from drillfatigue.errors import InputError

CRITERIA = ("matake", "findley", "uniaxial", "rp7g")


def read_dataset(path: str | Path) -> pd.DataFrame:
    """Read the damage table (parquet, or CSV by suffix); InputError if the file is missing."""
    p = Path(path)
    if not p.is_file():
        raise InputError(str(p), "dataset file not found", "run the dataset stage first")
    return pd.read_csv(p) if p.suffix.lower() == ".csv" else pd.read_parquet(p)


def log10_target(rate_per_h: np.ndarray, floor_per_h: float) -> np.ndarray:
    """``log10(max(rate, floor))`` of a damage rate per hour (zero rates are censored).

    Parameters
    ----------
    rate_per_h : ndarray, shape (n,)
        Miner damage per hour of operation, >= 0.
    floor_per_h : float
        Censoring floor, > 0 (1e-12 per hour = 1e12 h life by default).
    """
    r = np.asarray(rate_per_h, dtype=np.float64)
    if np.any(~np.isfinite(r)) or np.any(r < 0):
        raise InputError("damage rate", "negative, NaN or infinite value", "finite rates >= 0")
    return np.log10(np.maximum(r, floor_per_h))


def check_columns(frame: pd.DataFrame, cfg: SurrogateConfig, target: bool = True) -> None:
    """Raise InputError naming the first configured column missing from ``frame``."""
    need = list(cfg.features) + list(cfg.categorical) + [cfg.group_column]
    if target:
        need.append(cfg.target_column)
    present = set(frame.columns)
    for col in need:
        if col not in present:
            raise InputError(col, "column missing from the dataset",
                             "columns listed in params.yaml surrogate.features/categorical")


@dataclass(frozen=True)
class Split:
    """Row masks of the case-wise split (each shape (n,), disjoint, covering all rows)."""

    train: np.ndarray
    calibration: np.ndarray
    test: np.ndarray


def split_by_case(groups: np.ndarray, cfg: SurrogateConfig) -> Split:
    """Split rows into train / calibration / test by case id (seeded, reproducible).

    All rows of one case fall into one part, so the test and calibration
    scores are for unseen operating conditions, not for other locations of a
    case seen in training. The validation set for early stopping is carved out
    of ``train`` inside the regressor's ``fit``.
    """
    g = np.asarray(groups)
    cases = np.unique(g)
    if len(cases) < 5:
        raise InputError(cfg.group_column, f"only {len(cases)} distinct cases", ">= 5 cases")
    rng = np.random.default_rng(cfg.split_seed)
    order = rng.permutation(cases)
    n_test = max(1, int(round(cfg.test_fraction * len(cases))))
    n_cal = max(1, int(round(cfg.calibration_fraction * len(cases))))
    test_c, cal_c = order[:n_test], order[n_test:n_test + n_cal]
    test = np.isin(g, test_c)
    cal = np.isin(g, cal_c)
    return Split(train=~(test | cal), calibration=cal, test=test)


def gbm_rows(split: Split, cfg: SurrogateConfig, heldout: bool) -> tuple[np.ndarray,
                                                                          np.ndarray | None]:
    """Rows the served gradient boosting trains on, and the rows it calibrates on.

    The ensemble keeps its split (its conformal quantile needs calibration
    cases it did not train on); the gradient boosting trains on every case
    the evaluation does not score (``cfg.gbm_cases == "free"``): with
    cross-conformal calibration (``cfg.gbm_calibration == "cross"``) the
    calibration cases are training cases, and when the evaluation scores a
    held-out design of its own (``heldout``) the test cases are too. With
    ``gbm_cases: train`` it trains on the split's train cases only.

    Parameters
    ----------
    split : Split
    cfg : SurrogateConfig
    heldout : bool
        The evaluation scores a held-out dataset, not the split's test cases.

    Returns
    -------
    fit : ndarray of bool, shape (n,)
        Training rows of the gradient boosting.
    calibration : ndarray of bool, shape (n,), or None
        Its split-conformal calibration rows; None with cross-conformal
        calibration (the out-of-fold residuals of the training rows).
    """
    cross = cfg.gbm_calibration == "cross"
    fit = split.train.copy()
    if cfg.gbm_cases == "free":
        if cross:
            fit |= split.calibration
        if heldout:
            fit |= split.test
    return fit, (None if cross else split.calibration.copy())


def case_folds(groups: np.ndarray, n_folds: int, seed: int) -> np.ndarray:
    """Fold index (0 .. n_folds - 1) per row, whole cases per fold (seeded).

    The cases are shuffled by ``seed`` and dealt round-robin, so the folds'
    case counts differ by at most one and every row of a case has its fold.

    Parameters
    ----------
    groups : ndarray, shape (n,)
        Case id per row.
    n_folds : int
        Number of folds, 2 <= n_folds <= number of cases.
    seed : int

    Returns
    -------
    ndarray of int64, shape (n,)
    """
    cases, inverse = np.unique(np.asarray(groups), return_inverse=True)
    if not 2 <= n_folds <= len(cases):
        raise InputError("surrogate.conformal_folds", f"{n_folds} folds of {len(cases)} cases",
                         f"2 <= folds <= number of cases ({len(cases)})")
    fold_of_case = np.empty(len(cases), dtype=np.int64)
    fold_of_case[np.random.default_rng(seed).permutation(len(cases))] = (
        np.arange(len(cases)) % n_folds)
    return fold_of_case[inverse.reshape(-1)]


# ---------------------------------------------------------------------------
# synthetic data
# ---------------------------------------------------------------------------
_TYPE_OFFSET = {"collar": 0.3, "hwdp": 0.15, "drill_pipe": 0.0, "stabilizer": 0.5}
_PROFILE_OFFSET = {"build_hold": 0.0, "late_kickoff": 0.25, "double_bend": 0.45}
#: component positions (m behind the bit) and types of the synthetic string
SYNTHETIC_POSITIONS = ((2.0, "stabilizer"), (8.0, "collar"), (20.0, "collar"), (40.0, "collar"),
                       (80.0, "hwdp"), (120.0, "hwdp"), (200.0, "drill_pipe"),
                       (350.0, "drill_pipe"))


def synthetic_log10_rate(frame: pd.DataFrame) -> np.ndarray:
    """The analytic 'true' log10 damage rate per hour of the synthetic data.

    log10 D = -7 + 1.6 u_rpm + 0.9 u_wob + 0.25 u_rop + 0.6 u_mu
              + 0.8 log1p(dls_loc) (1 + 0.3 u_rpm) + 1.4 exp(-s/60)
              + 0.2 u_mud + 0.3 (amp / 1 mm) + 0.1 lobes
              + 0.7 [connection] + type offset + profile offset,
    with u_rpm = (rpm - 120)/60, u_wob = (wob_N - 1e5)/5e4,
    u_rop = sin(pi (rop_m_per_s - 0.001)/0.02), u_mu = (mu_dynamic - 0.25)/0.1,
    u_mud = (rho - 1300)/300, dls_loc in deg/30 m, s = distance from bit (m).
    It mimics damage physics qualitatively (more damage with speed, weight,
    friction, local dogleg and near the bit; connections worse than bodies);
    it is not a fatigue model.
    """
    rpm = frame["operation.rpm"].to_numpy()
    wob = frame["operation.wob_N"].to_numpy()
    rop = frame["operation.rop_m_per_s"].to_numpy()
    mu = frame["friction.mu_dynamic"].to_numpy()
    rho = frame["operation.mud_density_kg_per_m3"].to_numpy()
    amp = frame["bit.amplitude_m"].to_numpy()
    lobes = frame["bit.lobes"].to_numpy()
    s = frame["s_from_bit_m"].to_numpy()
    dls = frame["local_dls_deg_per_30m"].to_numpy()
    u_rpm = (rpm - 120.0) / 60.0
    y = (-7.0 + 1.6 * u_rpm + 0.9 * (wob - 1e5) / 5e4
         + 0.25 * np.sin(np.pi * (rop - 0.001) / 0.02) + 0.6 * (mu - 0.25) / 0.1
         + 0.8 * np.log1p(dls) * (1.0 + 0.3 * u_rpm) + 1.4 * np.exp(-s / 60.0)
         + 0.2 * (rho - 1300.0) / 300.0 + 0.3 * amp / 1e-3 + 0.1 * lobes
         + 0.7 * (frame["location"].to_numpy() == "connection")
         + frame["component_type"].map(_TYPE_OFFSET).to_numpy(dtype=np.float64)
         + frame["well.profile"].map(_PROFILE_OFFSET).to_numpy(dtype=np.float64))
    return y


def synthetic_noise_sigma(frame: pd.DataFrame) -> np.ndarray:
    """Heteroscedastic noise std of the synthetic log10 rate: 0.04 + 0.08 exp(-s/60)."""
    return 0.04 + 0.08 * np.exp(-frame["s_from_bit_m"].to_numpy() / 60.0)


def make_synthetic_dataset(n_cases: int = 100, seed: int = 0,
                           components: tuple[tuple[float, str], ...] = SYNTHETIC_POSITIONS) -> pd.DataFrame:
    """Synthetic damage table with the dataset schema, for tests, benchmarks and smoke runs.

    Each case draws operating conditions uniformly (rpm 40-200, WOB 20-200 kN,
    ROP 1-21 mm/s, mu_static 0.2-0.5 with mu_dynamic 0.6-0.95 of it, mud
    1000-1600 kg/m^3, bit amplitude 0.5-2 mm, 1-3 lobes, KOP 300-800 m, DLS
    2-8 deg/30 m, bit depth 300-1500 m beyond the KOP, profile of three);
    every component of ``components`` gives a body and a connection row. The
    local dogleg is the build rate while the component is in the build
    section (KOP to KOP + 90 deg of build), else 0. Targets: 10 ** (the
    analytic :func:`synthetic_log10_rate` + Gaussian noise of std
    :func:`synthetic_noise_sigma`) for matake; the other criteria are fixed
    offsets (findley +0.1, uniaxial -0.2, rp7g -0.5 decades); rates whose true
    log10 is below -10 are set to exactly 0 (censored, as a simulation with no
    damaging cycle would give).
    """
    rng = np.random.default_rng(seed)
    profiles = np.array(sorted(_PROFILE_OFFSET))
    case = pd.DataFrame({
        "case_id": [f"case{i:05d}" for i in range(n_cases)],
        "operation.rpm": rng.uniform(40.0, 200.0, n_cases),
        "operation.wob_N": rng.uniform(2e4, 2e5, n_cases),
        "operation.rop_m_per_s": rng.uniform(0.001, 0.021, n_cases),
        "friction.mu_static": rng.uniform(0.2, 0.5, n_cases),
        "operation.mud_density_kg_per_m3": rng.uniform(1000.0, 1600.0, n_cases),
        "bit.amplitude_m": rng.uniform(0.5e-3, 2e-3, n_cases),
        "bit.lobes": rng.integers(1, 4, n_cases),
        "well.kop_m": rng.uniform(300.0, 800.0, n_cases),
        "well.dls_deg_per_30m": rng.uniform(2.0, 8.0, n_cases),
        "well.profile": profiles[rng.integers(0, len(profiles), n_cases)],
    })
    case["friction.mu_dynamic"] = case["friction.mu_static"] * rng.uniform(0.6, 0.95, n_cases)
    bit_md = case["well.kop_m"].to_numpy() + rng.uniform(300.0, 1500.0, n_cases)
    rows = []
    for s, ctype in components:
        for loc in ("body", "connection"):
            part = case.copy()
            part["s_from_bit_m"] = s
            part["md_m"] = bit_md - s
            part["component_type"] = ctype
            part["location"] = loc
            rows.append(part)
    df = pd.concat(rows, ignore_index=True)
    build_len = 90.0 / df["well.dls_deg_per_30m"] * 30.0
    in_build = (df["md_m"] >= df["well.kop_m"]) & (df["md_m"] <= df["well.kop_m"] + build_len)
    df["local_dls_deg_per_30m"] = np.where(in_build, df["well.dls_deg_per_30m"], 0.0)
    y_true = synthetic_log10_rate(df)
    y = y_true + rng.normal(0.0, 1.0, len(df)) * synthetic_noise_sigma(df)
    for crit, off in zip(CRITERIA, (0.0, 0.1, -0.2, -0.5), strict=False):
        df[f"damage_rate_per_h_{crit}"] = np.where(y_true + off < -10.0, 0.0, 10.0 ** (y + off))
    return df.sort_values(["case_id", "s_from_bit_m", "location"], ignore_index=True)
