"""The torsional state the string settles in, and what it costs the served model, at research scale.

Reads a research-scale run (read-only: ``params.yaml``, the training and
held-out datasets and designs, the held-out draws of ``heldout_draws``) and
measures:

1. **Is the state a draw or a function of the inputs?** The stick-slip
   severity ((max - min) / mean bit speed) of every held-out case and of its
   draws at rpm x (1 +- k ``heldout.draw_rel_step``): the share of its
   variance that lies within a case, and the cases whose draws settle in
   different states. A case is in *full* stick-slip when its severity is at
   least ``--full-threshold`` (the bit stops: a severity about 2 or more; the
   training cases' severities are bimodal, with few between 1.7 and 2.1).
2. **Where the two states lie**: the share of full stick-slip per band of rpm.
3. **Can the inputs tell the state?** A case-level classifier (logistic
   regression on the standardised design inputs and the profile; gradient
   boosting beside it), out of fold over ``surrogate.conformal_folds`` folds of
   whole training cases and on the held-out cases; with and without the
   physics estimates of the inputs (:func:`case_physics`).
4. **What the state costs**: the served gradient boosting
   (:func:`drillfatigue.surrogate.gbm.fit_gbm` on the served encoding) out of
   fold and on the held-out design, scored on the deciding rows
   (:func:`drillfatigue.surrogate.evaluation.deciding_metrics`), with extra
   case-level inputs: none (served), the physics estimates, the classifier's
   probability of full stick-slip (stacked: out of fold for the training
   cases), the true state and the simulated severity (post-run outputs that
   leak the answer: the most knowing the state could give).
5. **Where the misses are**: the served model's held-out deciding rows by
   true state, by band of rpm and by the classifier's confidence.

Physics estimates per case (:func:`case_physics`), from the inputs alone:
the steady WOB the autodriller holds (its set-point unless the ROP limit
binds first: ROP = c1 WOB sqrt(Omega) of the bit law), the bit's torque and
its negative damping -dTOB/dOmega at the set speed (Yigit-Christoforou: the
velocity weakening that feeds stick-slip), the wall-friction torque of the
soft-string model at that WOB and torque on bit
(:func:`drillfatigue.softstring.torque_drag.torque_drag_for_case`), and the
stick-slip number Pi = (Delta T_bit + Delta T_wall) / (Z Omega) (the torque
drop from the bit's peak friction and from static to dynamic wall friction,
over the drill pipe's torsional impedance Z = J_p sqrt(G rho) times the set
speed: Kyllingstad & Nessjoen 2009).

Usage: ``python benchmarks/stick_slip_state.py --research /work/research
[--out benchmarks/results/stick_slip_state.json]``
"""

from __future__ import annotations

import argparse
import json
import math
import platform
import time
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd
from scipy.stats import spearmanr
from sklearn.ensemble import HistGradientBoostingClassifier
from sklearn.linear_model import LogisticRegression
from sklearn.pipeline import make_pipeline
from sklearn.preprocessing import StandardScaler

from drillfatigue.config import case_from_dict, load_params
from drillfatigue.dynamics.bit.laws import MODEL_IDS, bit_response, pack_bit_params
from drillfatigue.softstring.torque_drag import torque_drag_for_case
from drillfatigue.sweep.dataset import summary_dynamics
from drillfatigue.surrogate.data import case_folds, log10_target
from drillfatigue.surrogate.evaluation import deciding_metrics
from drillfatigue.surrogate.gbm import design_matrix, fit_gbm, monotone_constraints
from drillfatigue.surrogate.io import write_json
from drillfatigue.surrogate.model import Preprocessor

RESULT = Path(__file__).parent / "results" / "stick_slip_state.json"
SEVERITY = "stick_slip_severity"
INPUTS = ("operation.rpm", "operation.rop_m_per_s", "operation.bit_md_m",
          "operation.lobe_amplitude_m", "operation.mud_density_kg_per_m3", "friction.mu_dynamic")
PHYSICS = ("ph_wob_N", "ph_tob_Nm", "ph_bit_negative_damping_Nm_s", "ph_wall_torque_Nm",
           "ph_pi")
RPM_BANDS = (80.0, 110.0, 140.0, 160.0, 180.0)
LOG10_2 = math.log10(2.0)


def _mu_b(om: np.ndarray | float, b1: float, b2: float, b3: float) -> Any:
    return np.tanh(b1 * om) + b2 * om / (1.0 + b3 * om * om)


def case_physics(case_json: str) -> dict[str, float]:
    """Steady-drilling estimates of one case from its inputs (module doc), SI."""
    case = case_from_dict(json.loads(case_json))
    bit, ad = case.bit, case.rig.autodriller
    om = case.operation.rpm * 2.0 * math.pi / 60.0
    wob = min(ad.wob_set_N, ad.rop_limit_m_per_s / (bit.rop_c1_m_per_N_sqrt_s * math.sqrt(om)))
    _, p = pack_bit_params(bit, 0.0)
    out = np.zeros(2)
    bit_response(MODEL_IDS[bit.model], p, wob, om, out)
    tob = float(out[0])
    b0 = bit.bit_radius_m * bit.mu0
    b1, b2, b3 = bit.tob_b1_s_per_rad, bit.tob_b2_s_per_rad, bit.tob_b3_s2_per_rad2
    slope = b1 / math.cosh(b1 * om) ** 2 + b2 * (1.0 - b3 * om**2) / (1.0 + b3 * om**2) ** 2
    peak = float(np.max(_mu_b(np.linspace(1e-3, om, 4000), b1, b2, b3)))
    td = torque_drag_for_case(case, wob_N=wob, tob_Nm=tob)
    wall = float(td.torque_drilling_Nm[0]) - tob
    dp = next(c for c in case.string.components if c.type == "drill_pipe")
    g = dp.material.youngs_modulus_Pa / (2.0 * (1.0 + dp.material.poisson_ratio))
    jp = math.pi / 32.0 * (dp.od_m**4 - dp.id_m**4)
    z = jp * math.sqrt(g * dp.material.density_kg_per_m3)
    d_bit = wob * b0 * peak - tob
    d_wall = (case.friction.mu_static / case.friction.mu_dynamic - 1.0) * wall
    return {"ph_wob_N": wob, "ph_tob_Nm": tob, "ph_bit_negative_damping_Nm_s": -wob * b0 * slope,
            "ph_wall_torque_Nm": wall, "ph_pi": (d_bit + d_wall) / (z * om)}


def case_table(rows: pd.DataFrame, design: pd.DataFrame, threshold: float) -> pd.DataFrame:
    """One row per case: inputs, profile dummies, severity, state and physics estimates."""
    c = rows.groupby("case_id", sort=False).first().reset_index()
    ph = pd.DataFrame([{"case_id": r.case_id, **case_physics(r.case_json)}
                       for r in design.itertuples() if r.case_id in set(c["case_id"])])
    c = c.merge(ph, on="case_id", how="left")
    for k in ("profile_2", "profile_3"):
        c[f"is_{k}"] = (c["well.profile"].astype(str) == k).astype(float)
    c["full"] = (c[SEVERITY] >= threshold).astype(int)
    return c


def classifiers() -> dict[str, Any]:
    return {"logistic": lambda: make_pipeline(StandardScaler(),
                                              LogisticRegression(C=10.0, max_iter=5000)),
            "gbm": lambda: HistGradientBoostingClassifier(max_iter=200, learning_rate=0.05,
                                                          random_state=0)}


def classify(ctr: pd.DataFrame, cte: pd.DataFrame, cols: list[str], make: Any,
             folds: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Out-of-fold probabilities of full stick-slip (training cases) and held-out ones."""
    x, y = ctr[cols].to_numpy(float), ctr["full"].to_numpy()
    oof = np.empty(len(ctr))
    for k in np.unique(folds):
        t = folds != k
        oof[~t] = make().fit(x[t], y[t]).predict_proba(x[~t])[:, 1]
    return oof, make().fit(x, y).predict_proba(cte[cols].to_numpy(float))[:, 1]


def _acc(p: np.ndarray, y: np.ndarray) -> dict[str, float]:
    q = np.clip(p, 1e-9, 1 - 1e-9)
    return {"accuracy": round(float(np.mean((p >= 0.5) == y)), 4),
            "log_loss": round(float(-np.mean(y * np.log(q) + (1 - y) * np.log(1 - q))), 4)}


def _score(frame: pd.DataFrame, y: np.ndarray, mu: np.ndarray, horizon_h: float
           ) -> dict[str, float]:
    pred = pd.DataFrame({"case_id": frame["case_id"].to_numpy(), "y_true": y, "m": mu,
                         "m_lower": mu - 1.0, "m_upper": mu + 1.0,
                         "component_type": frame["component_type"].to_numpy(),
                         "location": frame["location"].to_numpy(),
                         "s_from_bit_m": frame["s_from_bit_m"].to_numpy()})
    m = deciding_metrics(pred, ("m",), horizon_h)["m"]
    return {"factor2": round(m["rows"]["factor2_fraction"], 4),
            "rmse": round(m["rows"]["rmse"], 4), "n": m["rows"]["n"],
            "beyond_precision": round(m["beyond_horizon"]["precision"], 4)}


def row_model(tr: pd.DataFrame, te: pd.DataFrame, ytr: np.ndarray, yte: np.ndarray,
              extra: list[str], cfg: Any) -> tuple[dict[str, Any], np.ndarray]:
    """Served gbm with ``extra`` numeric inputs: out of fold (whole cases) and held out."""
    pre = Preprocessor([*cfg.features, *extra], cfg.categorical).fit(tr)
    x = design_matrix(pre, pre.numeric_array(tr), pre.category_codes(tr))
    xt = design_matrix(pre, pre.numeric_array(te), pre.category_codes(te))
    mono = monotone_constraints(pre)
    g = tr["case_id"].to_numpy()
    folds = case_folds(g, cfg.conformal_folds, cfg.split_seed)
    oof = np.empty(len(ytr))
    for k in np.unique(folds):
        t = folds != k
        oof[~t] = fit_gbm(x[t], ytr[t], g[t], cfg, mono)[0].predict(x[~t])
    mu = fit_gbm(x, ytr, g, cfg, mono)[0].predict(xt)
    return ({"out_of_fold": _score(tr, ytr, oof, cfg.horizon_h),
             "heldout": _score(te, yte, mu, cfg.horizon_h)}, mu)


def _misses(d: pd.DataFrame, key: str) -> dict[str, Any]:
    out = {}
    total = int(d["miss"].sum())
    for k, g in d.groupby(key, observed=True):
        out[str(k)] = {"rows": len(g), "cases": int(g["case_id"].nunique()),
                       "factor2": round(1.0 - float(g["miss"].mean()), 4),
                       "share_of_misses": round(float(g["miss"].sum()) / max(total, 1), 4)}
    return out


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--research", required=True, help="a research-scale run's folder")
    ap.add_argument("--full-threshold", type=float, default=1.9)
    ap.add_argument("--out", default=str(RESULT))
    args = ap.parse_args(argv)
    t0 = time.perf_counter()
    r = Path(args.research)
    params = load_params(r / "params.yaml")
    cfg = params.surrogate
    tr = pd.read_parquet(r / "data/dataset/damage.parquet")
    te = pd.read_parquet(r / "data/heldout/dataset/damage.parquet")
    ctr = case_table(tr, pd.read_parquet(r / "data/design/cases.parquet"), args.full_threshold)
    cte = case_table(te, pd.read_parquet(r / params.heldout.cases_path), args.full_threshold)
    res: dict[str, Any] = {"command": "python benchmarks/stick_slip_state.py --research "
                                      f"{args.research}",
                           "date": time.strftime("%Y-%m-%d"), "machine": platform.machine(),
                           "n_train_cases": len(ctr), "n_heldout_cases": len(cte),
                           "full_threshold": args.full_threshold}
    hist, edges = np.histogram(ctr[SEVERITY], bins=np.arange(0.8, 3.3, 0.2))
    res["severity_histogram_train"] = {"edges": [round(e, 2) for e in edges],
                                       "counts": hist.tolist()}

    # 1. draws: is the state a function of the inputs?
    draws_dir = Path(params.heldout.draws_dir)
    draws_dir = draws_dir if draws_dir.is_absolute() else r / draws_dir
    sweep_dir = Path(params.heldout.sweep_dir)
    sweep_dir = sweep_dir if sweep_dir.is_absolute() else r / sweep_dir
    if (draws_dir / "cases.parquet").is_file():
        dc = pd.read_parquet(draws_dir / "cases.parquet")
        recs = [{"base": c, SEVERITY: summary_dynamics(sweep_dir / c)[SEVERITY]}
                for c in cte["case_id"]]
        recs += [{"base": d.base_case_id, SEVERITY: summary_dynamics(
            draws_dir / "sweep" / d.case_id)[SEVERITY]} for d in dc.itertuples()]
        t = pd.DataFrame(recs).dropna()
        t["full"] = t[SEVERITY] >= args.full_threshold
        within = float(t.groupby("base")[SEVERITY].var().mean())
        mixed = t.groupby("base")["full"].agg(lambda s: 0 < s.sum() < len(s))
        res["draws"] = {"n_cases": int(t["base"].nunique()), "n_runs": len(t),
                        "severity_variance_total": round(float(t[SEVERITY].var()), 5),
                        "severity_variance_within_case": round(within, 5),
                        "within_share": round(within / float(t[SEVERITY].var()), 4),
                        "cases_with_draws_in_both_states": int(mixed.sum())}

    # 2. where the states lie
    band = pd.cut(ctr["operation.rpm"], RPM_BANDS)
    res["full_share_by_rpm_train"] = {str(k): {"cases": len(g),
                                               "full_share": round(float(g["full"].mean()), 3)}
                                      for k, g in ctr.groupby(band, observed=True)}
    res["spearman_with_severity_train"] = {
        c: round(float(spearmanr(ctr[c], ctr[SEVERITY]).statistic), 3)
        for c in (*INPUTS, *PHYSICS)}

    # 3. the state from the inputs
    base_cols = [*INPUTS, "is_profile_2", "is_profile_3"]
    folds = case_folds(ctr["case_id"].to_numpy(), cfg.conformal_folds, cfg.split_seed)
    res["state_classifier"] = {}
    probs: dict[str, tuple[np.ndarray, np.ndarray]] = {}
    for cols_name, cols in (("inputs", base_cols), ("inputs_physics", [*base_cols, *PHYSICS])):
        for name, make in classifiers().items():
            oof, pte = classify(ctr, cte, cols, make, folds)
            probs[f"{name}_{cols_name}"] = (oof, pte)
            res["state_classifier"][f"{name}_{cols_name}"] = {
                "out_of_fold": _acc(oof, ctr["full"].to_numpy()),
                "heldout": _acc(pte, cte["full"].to_numpy())}

    # 4. what the state costs the served model
    oof, pte = probs["logistic_inputs"]
    tr = tr.merge(ctr[["case_id", *PHYSICS, "full"]].assign(p_full=oof), on="case_id")
    te = te.merge(cte[["case_id", *PHYSICS, "full"]].assign(p_full=pte), on="case_id")
    tr = tr.rename(columns={"full": "state_full"})
    te = te.rename(columns={"full": "state_full"})
    ytr = log10_target(tr[cfg.target_column].to_numpy(), cfg.rate_floor_per_h)
    yte = log10_target(te[cfg.target_column].to_numpy(), cfg.rate_floor_per_h)
    res["row_model"] = {}
    mu_served = None
    for name, extra in (("served_inputs", []), ("physics", list(PHYSICS)),
                        ("stacked_state_probability", ["p_full"]),
                        ("true_state_post_run", ["state_full"]),
                        ("simulated_severity_post_run", [SEVERITY])):
        res["row_model"][name], mu = row_model(tr, te, ytr, yte, extra, cfg)
        print(name, res["row_model"][name], flush=True)
        if name == "served_inputs":
            mu_served = mu

    # 5. where the served model misses on the held-out deciding rows
    assert mu_served is not None
    c = -math.log10(cfg.horizon_h)
    d = te.assign(miss=np.abs(mu_served - yte) > LOG10_2)[mu_served >= c]
    d["state"] = np.where(d["state_full"] == 1, "full", "partial")
    d["rpm_band"] = pd.cut(d["operation.rpm"], RPM_BANDS)
    d["classifier"] = np.where((d["p_full"] > 0.1) & (d["p_full"] < 0.9), "uncertain",
                               "confident")
    res["served_misses_heldout"] = {key: _misses(d, key)
                                    for key in ("state", "rpm_band", "classifier")}
    res["wall_s"] = round(time.perf_counter() - t0, 1)
    write_json(res, args.out)  # atomic: no half-written result under the final name
    print(json.dumps({k: v for k, v in res.items() if k != "row_model"}, indent=1))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
