"""Evaluation where it decides life: rows chosen by the predicted life, the
"longer than the horizon" answers, governing damage per component, the
monotone-in-dogleg check, gradient boosting stopped on whole cases, and
scoring on a held-out dataset."""

from __future__ import annotations

import json
import math

import numpy as np
import pandas as pd
import pytest

from drillfatigue.config.surrogate import SurrogateConfig
from drillfatigue.errors import InputError
from drillfatigue.surrogate import Surrogate, fit_surrogate, make_synthetic_dataset
from drillfatigue.surrogate.evaluation import deciding_metrics, evaluate, monotone_check
from drillfatigue.surrogate.gbm import design_matrix, fit_gbm
from drillfatigue.surrogate.served_gbm import half_width, interval_bins, interval_scale


def _pred() -> pd.DataFrame:
    # horizon 1e5 h: level -5. Case a: collar rows -2 / -4, pipe row -9; case b: all
    # beyond the horizon in the simulation, one row predicted within it.
    return pd.DataFrame({
        "case_id": ["a", "a", "a", "b", "b"],
        "component_type": ["collar", "collar", "drill_pipe", "collar", "drill_pipe"],
        "well.profile": ["p1", "p1", "p1", "p3", "p3"],
        "location": ["connection", "body", "body", "connection", "body"],
        "s_from_bit_m": [5.0, 5.0, 200.0, 5.0, 200.0],
        "y_true": [-2.0, -4.0, -9.0, -6.0, -8.0],
        "ensemble": [-2.1, -3.0, -7.0, -4.5, -8.5],
        "ensemble_lower": [-2.5, -3.5, -8.0, -5.0, -9.0],
        "ensemble_upper": [-1.5, -2.5, -6.0, -4.0, -8.0],
    })


def test_deciding_rows_are_chosen_by_the_predicted_life() -> None:
    d = deciding_metrics(_pred(), ("ensemble", "gp"), horizon_h=1e5)
    assert "gp" not in d
    e = d["ensemble"]
    # predicted >= -5: rows 0, 1 (errors -0.1, +1.0) and row 3 (-4.5 vs -6: +1.5),
    # although row 3's simulated life is beyond the horizon
    r = e["rows"]
    assert r["n"] == 3
    assert r["rmse"] == pytest.approx(math.sqrt((0.01 + 1.0 + 2.25) / 3), rel=1e-12)
    assert r["factor2_fraction"] == pytest.approx(1 / 3)
    assert r["coverage"] == pytest.approx(1 / 3)  # only row 0's interval holds its truth
    assert e["by_profile"]["p3"]["n"] == 1 and e["by_profile"]["p1"]["n"] == 2
    assert set(e["by_decade"]) == {"1e-02", "1e-04", "1e-06"}
    assert r["mean_width"] == pytest.approx(1.0)
    # row 3 is simulated beyond the horizon (-6 < -5) and its interval reaches down to
    # -5: covered as the calibration scores a censored row
    assert r["coverage_censored"] == pytest.approx(2 / 3)
    # by decade of the prediction: rows 0 and 1 predicted at -2.1 and -3.0 (1e-03),
    # row 3 at -4.5 (1e-05); by decade of the simulation they are 1e-02, 1e-04, 1e-06
    p = e["by_predicted_decade"]
    assert set(p) == {"1e-03", "1e-05"}
    assert p["1e-03"]["n"] == 2 and p["1e-03"]["coverage"] == 0.5
    assert p["1e-05"]["coverage"] == 0.0 and p["1e-05"]["coverage_censored"] == 1.0
    # "longer than": rows 2 and 4 predicted beyond, both truly beyond (precision 1);
    # 3 simulated beyond, 2 of them found (recall 2/3)
    bh = e["beyond_horizon"]
    assert bh == {"n_predicted": 2, "n_simulated": 3, "precision": 1.0,
                  "recall": pytest.approx(2 / 3)}
    # per component type x location: collar connection rows 0 and 3 (errors -0.1, +1.5),
    # collar body row 1 (+1.0); drill pipe predicted beyond the horizon only
    t = e["by_component_type_location"]
    assert set(t) == {"collar connection", "collar body"}
    assert t["collar connection"]["n"] == 2 and t["collar body"]["n"] == 1
    assert t["collar body"]["mae"] == pytest.approx(1.0)


def test_governing_damage_per_component_type() -> None:
    g = deciding_metrics(_pred(), ("ensemble",), horizon_h=1e5)["ensemble"]["governing"]
    # groups (a, collar): sim max -2 (row 0), pred max -2.1 (row 0): error -0.1, same place
    # (a, drill_pipe): both -9 / -7 beyond the horizon: agreed "longer than", not scored
    # (b, collar): sim -6, pred -4.5 within: error +1.5 (a false alarm, scored)
    # (b, drill_pipe): both beyond
    assert g["n_groups"] == 4 and g["n_both_beyond_horizon"] == 2 and g["n"] == 2
    assert g["rmse"] == pytest.approx(math.sqrt((0.01 + 2.25) / 2), rel=1e-12)
    assert g["factor2_fraction"] == 0.5 and g["same_location_fraction"] == 1.0
    assert g["by_component_type"]["collar"]["n"] == 2
    with pytest.raises(ValueError, match="horizon_h"):
        deciding_metrics(_pred(), horizon_h=0.0)


def _rows(n: int = 30) -> pd.DataFrame:
    rng = np.random.default_rng(0)
    return pd.DataFrame({"local_dls_deg_per_30m": rng.uniform(0, 9, n),
                         "local_max_dls_deg_per_30m": rng.uniform(0, 9, n),
                         "operation.rpm": rng.uniform(80, 180, n)})


def test_monotone_check_passes_a_monotone_model_and_catches_a_dip() -> None:
    rows = _rows()
    ok = monotone_check(lambda f: -6.0 + 0.3 * f["local_dls_deg_per_30m"].to_numpy()
                        + 0.1 * f["local_max_dls_deg_per_30m"].to_numpy(), rows)
    assert ok["fraction_rows_violating"] == 0.0 and ok["n_rows"] == 30
    # a model with a dip of 0.4 decades around 4.5 deg/30 m for rpm > 130 only
    def dip(f: pd.DataFrame) -> np.ndarray:
        x = f["local_dls_deg_per_30m"].to_numpy()
        return (-6.0 + 0.1 * x - 0.4 * np.exp(-((x - 4.5) / 1.0) ** 2)
                * (f["operation.rpm"].to_numpy() > 130.0))
    bad = monotone_check(dip, rows, n_grid=19)
    share = float(np.mean(rows["operation.rpm"] > 130.0))
    assert bad["fraction_rows_violating"] == pytest.approx(share)
    assert bad["max_drop_decades"] > 0.1
    assert monotone_check(dip, rows.drop(columns="local_dls_deg_per_30m")) == {}


def test_gbm_early_stopping_holds_out_whole_cases() -> None:
    # 40 cases x 10 identical rows, the target pure per-case noise: nothing to learn
    # across cases. Held-out rows of seen cases would reward memorising each case
    # (many trees); held-out cases stop after a few trees.
    rng = np.random.default_rng(1)
    x_case, y_case = rng.uniform(size=(40, 3)), rng.normal(size=40)
    x, y = np.repeat(x_case, 10, axis=0), np.repeat(y_case, 10)
    groups = np.repeat(np.arange(40), 10)
    cfg = SurrogateConfig(hgb_max_iter=60, censoring="none")
    model, info = fit_gbm(x, y, groups, cfg)
    assert info["n_val_cases"] == 6  # 15 % of 40 cases, rounded up by GroupShuffleSplit
    assert info["n_iter"] <= 10 and model.n_iter_ == info["n_iter"]
    # with rows held out instead, the memorising model keeps (nearly) all trees
    model_rows, info_rows = fit_gbm(x, y, np.arange(x.shape[0]), cfg)
    assert info_rows["n_iter"] > 40


CFG = SurrogateConfig(hidden_layers=(16,), max_epochs=20, patience=5, batch_size=64,
                      n_threads=1, gp_max_rows=80, hgb_max_iter=40, horizon_h=1e7)


@pytest.fixture(scope="module")
def fitted() -> tuple[pd.DataFrame, object]:
    data = make_synthetic_dataset(30, seed=2)
    return data, fit_surrogate(data, CFG)


def test_evaluate_on_a_heldout_dataset(fitted) -> None:
    data, model = fitted
    held = make_synthetic_dataset(8, seed=11)
    held["case_id"] = "held_" + held["case_id"]
    met, pred = evaluate(data, model, CFG, heldout=held)
    assert met["test_source"] == "heldout" and met["n_test_cases"] == 8
    assert met["n_test_rows"] == len(held) == len(pred)
    for m in ("ensemble", "gp", "hgb"):
        assert met["deciding"][m]["rows"]["n"] + met["deciding"][m]["beyond_horizon"][
            "n_predicted"] == len(held)
    assert met["monotone_dls"]["hgb"]["fraction_rows_violating"] == 0.0  # constrained
    # the baseline has the served gradient boosting's interval (scaled by default)
    assert met["hgb"]["interval"] == CFG.gbm_interval
    assert len(met["hgb"]["conformal_half_widths"]) == len(met["hgb"]["conformal_bins_log10"]) + 1
    split, _ = evaluate(data, model, CFG, baselines=False)
    assert split["test_source"] == "split"
    assert split["n_test_cases"] == len(model.metadata["split"]["test_cases"])
    # a "held-out" set that repeats training cases is no held-out set
    with pytest.raises(InputError, match="training cases"):
        evaluate(data, model, CFG, baselines=False, heldout=data)


def test_served_gbm_behind_the_same_interface(fitted, tmp_path) -> None:
    data, _ = fitted
    # 20 rows a bin: several bins on the small synthetic calibration set
    cfg = CFG.model_copy(update={"served_model": "gbm", "conformal_bin_min_rows": 20,
                                 "gbm_interval": "per_decade"})
    sur = fit_surrogate(data, cfg)
    rows = data.iloc[::11]
    p = sur.predict(rows, refuse=False)
    # the numbers are the boosted trees' with the half-width of their decade's bin
    mu = sur.gbm.predict(design_matrix(sur.preprocessor, *sur.encode(rows)))
    np.testing.assert_array_equal(p["log10_damage_rate_per_h"].to_numpy(), mu)
    g = sur.metadata["gbm"]
    edges, widths = np.asarray(g["conformal_bins_log10"]), np.asarray(g["conformal_half_widths"])
    assert edges.size >= 1 and widths.size == edges.size + 1 and np.ptp(widths) > 0
    half = widths[np.searchsorted(edges, mu, side="right")]
    np.testing.assert_allclose(p["log10_damage_rate_per_h_upper"] - mu, half, rtol=1e-12)
    np.testing.assert_allclose(mu - p["log10_damage_rate_per_h_lower"], half, rtol=1e-12)
    assert sur.metadata["served_model"] == "gbm" and sur.gbm.n_iter_ <= CFG.hgb_max_iter
    sur.save(tmp_path / "m")
    names = {f.name for f in (tmp_path / "m").iterdir()}
    assert "gbm.pkl" in names and "model.ts" not in names  # the exports are the ensemble's
    again = Surrogate.load(tmp_path / "m")
    assert again.metadata["gbm"]["conformal_bins_log10"] == g["conformal_bins_log10"]
    assert again.metadata["gbm"]["conformal_half_widths"] == g["conformal_half_widths"]
    pd.testing.assert_frame_equal(again.predict(rows), sur.predict(rows))
    # a model saved without bins (constant interval) answers the one global width
    meta_path = tmp_path / "m" / "metadata.json"
    meta = json.loads(meta_path.read_text(encoding="utf-8"))
    del meta["gbm"]["conformal_bins_log10"], meta["gbm"]["conformal_half_widths"]
    meta_path.write_text(json.dumps(meta), encoding="utf-8")
    old = Surrogate.load(tmp_path / "m").predict(rows, refuse=False)
    np.testing.assert_array_equal(old["log10_damage_rate_per_h"].to_numpy(), mu)
    np.testing.assert_allclose(old["log10_damage_rate_per_h_upper"] - mu,
                               g["conformal_quantile"], rtol=1e-12)
    # gbm_interval: constant writes no bins
    flat = fit_surrogate(data, cfg.model_copy(update={"gbm_interval": "constant"}))
    assert "conformal_half_widths" not in flat.metadata["gbm"]
    np.testing.assert_allclose(flat.predict(rows, refuse=False)["log10_damage_rate_per_h_upper"]
                               - mu, flat.metadata["gbm"]["conformal_quantile"], rtol=1e-12)
    # gbm_interval: scaled (the default): the bin's multiplier times the row's scale from
    # the scale model (the flat-forest kernel answers scikit-learn's numbers), the global
    # width beyond the horizon; saved and loaded with the regressor
    sc = fit_surrogate(data, cfg.model_copy(update={"gbm_interval": "scaled"}))
    x = design_matrix(sc.preprocessor, *sc.encode(rows))
    mu_s = sc.gbm.predict(x)
    gs = sc.metadata["gbm"]
    want_half = half_width(mu_s, gs, interval_bins(gs), interval_scale(sc.gbm, x))
    ps = sc.predict(rows, refuse=False)
    np.testing.assert_allclose(ps["log10_damage_rate_per_h_upper"] - mu_s, want_half, rtol=1e-9)
    assert np.ptp(want_half[mu_s >= gs["censor_level_log10"]]) > 0
    sc.save(tmp_path / "s")
    pd.testing.assert_frame_equal(Surrogate.load(tmp_path / "s").predict(rows, refuse=False), ps)
    # monotone in the local dogleg by construction
    assert monotone_check(lambda f: sur.predict(f, refuse=False)["log10_damage_rate_per_h"]
                          .to_numpy(), rows, sur.domain)["fraction_rows_violating"] == 0.0
    # evaluate scores the ensemble's own answers even when gradient boosting is served
    _, pred = evaluate(data, sur, cfg, baselines=False)
    ens = Surrogate(sur.module, sur.preprocessor, sur.domain, sur.metadata, None)
    test = data[data["case_id"].isin(sur.metadata["split"]["test_cases"])]
    want = ens.predict(test, refuse=False)["log10_damage_rate_per_h"].to_numpy()
    np.testing.assert_allclose(np.sort(pred["ensemble"].to_numpy()), np.sort(want), rtol=1e-6)


def test_served_gbm_trains_on_every_case_the_heldout_design_frees(fitted, tmp_path) -> None:
    data, _ = fitted
    # per_decade: the model stands in below for one saved before the calibration keys
    # existed (a scaled model's scale model came with them)
    cfg = CFG.model_copy(update={"served_model": "gbm", "conformal_bin_min_rows": 20,
                                 "heldout_path": "held-out.parquet",
                                 "gbm_interval": "per_decade"})
    sur = fit_surrogate(data, cfg)
    g, sp = sur.metadata["gbm"], sur.metadata["split"]
    # cross-conformal by case over every case: the split's calibration and test cases
    # train the served gradient boosting too (the ensemble keeps its split)
    assert g["calibration"] == "cross" and g["conformal_folds"] == cfg.conformal_folds
    assert g["train_cases"] == sorted(sp["train_cases"] + sp["calibration_cases"]
                                      + sp["test_cases"])
    assert g["n_train_rows"] == g["n_calibration_rows"] == len(data)
    assert g["n_calibration_cases"] == data["case_id"].nunique()
    # the domain is every case the served model trains on, its threshold cross-fitted
    dom = sur.domain.to_dict()
    assert dom["threshold_source"] == f"cross-fitted, {cfg.conformal_folds} folds of whole cases"
    n_ref = min(len(data), dom["reference_rows"])
    assert sur.domain.reference_.shape[0] == n_ref
    assert sur.metadata["training"]["n_train_rows"] < len(data)
    sur.save(tmp_path / "m")
    again = Surrogate.load(tmp_path / "m")
    assert again.metadata["gbm"] == g
    rows = data.iloc[::13]
    pd.testing.assert_frame_equal(again.predict(rows), sur.predict(rows))
    # the evaluation's baseline is the served procedure on the same cases
    held = make_synthetic_dataset(6, seed=12)
    held["case_id"] = "held_" + held["case_id"]
    met, pred = evaluate(data, sur, cfg, heldout=held)
    assert met["hgb"]["same_cases_as_served"] is True
    assert met["hgb"]["calibration"] == "cross" and met["hgb"]["n_train_cases"] == 30
    served = sur.predict(held, refuse=False)
    np.testing.assert_allclose(pred["hgb"], served["log10_damage_rate_per_h"], rtol=1e-12)
    np.testing.assert_allclose(pred["hgb_upper"], served["log10_damage_rate_per_h_upper"],
                               rtol=1e-12)
    # a held-out set holding a case the gradient boosting trained on (a test case
    # of the ensemble's split) is refused
    leak = pd.concat([held, data[data["case_id"] == sp["test_cases"][0]]], ignore_index=True)
    with pytest.raises(InputError, match="training cases"):
        evaluate(data, sur, cfg, baselines=False, heldout=leak)
    # scored on its own test cases, the baseline leaves them out of training (and says
    # it is not the served model's case set)
    own, _ = evaluate(data, sur, cfg.model_copy(update={"gp_max_rows": 20}))
    assert own["hgb"]["same_cases_as_served"] is False
    assert own["hgb"]["n_train_cases"] == len(sp["train_cases"]) + len(sp["calibration_cases"])
    # a model saved before the calibration keys existed loads and answers the same
    meta_path = tmp_path / "m" / "metadata.json"
    meta = json.loads(meta_path.read_text(encoding="utf-8"))
    for key in ("calibration", "conformal_folds", "train_cases", "n_calibration_rows",
                "n_calibration_cases", "interval", "n_train_rows"):
        del meta["gbm"][key]
    meta_path.write_text(json.dumps(meta), encoding="utf-8")
    old = Surrogate.load(tmp_path / "m")
    pd.testing.assert_frame_equal(old.predict(rows), sur.predict(rows))
    old_met, _ = evaluate(data, old, cfg, baselines=False, heldout=held)
    assert old_met["n_test_cases"] == 6


def test_mean_of_draws_is_the_arithmetic_mean_rate_floored() -> None:
    from drillfatigue.surrogate.evaluation import mean_of_draws_log10

    rows = pd.DataFrame({"case_id": ["a", "a", "b", "c"], "joint": [0, 1, 0, 0],
                         "location": ["body"] * 4})
    draws = pd.DataFrame({
        "base_case_id": ["a"] * 6 + ["b"] * 3 + ["c"],
        "joint": [0, 0, 0, 1, 1, 1, 0, 0, 0, 0], "location": ["body"] * 10,
        "replicate": [0, 1, 2, 0, 1, 2, 0, 1, 2, 0],
        "damage_rate_per_h": [1e-3, 1e-2, 1e-1, np.nan, 0.0, 3e-13, 0.0, 0.0, 0.0, 1.0]})
    y = mean_of_draws_log10(rows, draws, floor_per_h=1e-12)
    # (1e-3 + 1e-2 + 1e-1) / 3: the mean rate, not the mean of the logs (-2)
    assert y[0] == pytest.approx(math.log10(0.111 / 3), rel=1e-12)
    assert y[1] == -12.0 and y[2] == -12.0  # no cycle in any draw: the floor
    assert np.isnan(y[3])  # one draw only
    g = mean_of_draws_log10(rows, draws, floor_per_h=1e-12, average="log10")
    assert g[0] == pytest.approx(-2.0, rel=1e-12)  # the mean of the logs
    assert g[1] == -12.0 and np.isnan(g[3])
    with pytest.raises(InputError, match="average"):
        mean_of_draws_log10(rows, draws, floor_per_h=1e-12, average="median")


def test_draws_metrics_score_the_same_rows_twice() -> None:
    from drillfatigue.surrogate.evaluation import draws_metrics

    rng = np.random.default_rng(0)
    n = 60
    truth = rng.uniform(-4, 0, n)
    pred = pd.DataFrame({"case_id": np.repeat(list("abcdef"), 10), "y_true": truth + 0.5,
                         "hgb": truth, "hgb_lower": truth - 0.2, "hgb_upper": truth + 0.2})
    y_draws = truth.copy()
    y_draws[:10] = np.nan
    d = draws_metrics(pred, y_draws, ("hgb",), 1e5)
    assert d["n_rows"] == 50 and d["n_cases"] == 5
    assert d["single_run"]["hgb"]["rows"]["factor2_fraction"] == 0.0  # 0.5 decades off
    assert d["mean_of_draws"]["hgb"]["rows"]["factor2_fraction"] == 1.0
    assert d["mean_of_draws"]["hgb"]["rows"]["n"] == 50 and "log_mean_of_draws" not in d
    d = draws_metrics(pred, y_draws, ("hgb",), 1e5, y_draws + 1.0)
    assert d["log_mean_of_draws"]["hgb"]["rows"]["factor2_fraction"] == 0.0
    assert draws_metrics(pred, np.full(n, np.nan), ("hgb",), 1e5) == {"n_rows": 0, "n_cases": 0}
