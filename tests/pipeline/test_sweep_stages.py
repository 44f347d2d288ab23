"""Sweep stages on a tiny params file: design → simulate → fatigue → dataset.

With the synthetic case functions (fast, checks the wiring and resume), and
once with the real simulator and fatigue chain on a 2-case, 16-segment,
0.3 s sweep (slow marker).
"""

from __future__ import annotations

import importlib.util
import json
from pathlib import Path

import pandas as pd
import pytest
import yaml

from drillfatigue.config import load_params
from drillfatigue.config.fatigue import UPSET_TYPES
from drillfatigue.sweep.stages import dataset_stage, design_stage, fatigue_stage, simulate_stage
from testkit.synthetic_sweep import TINY_PARAMS as TINY
from testkit.synthetic_sweep import synthetic_case, synthetic_fatigue

ROOT = Path(__file__).parents[2]


def _params(tmp_path: Path, **sweep) -> Path:
    data = TINY | {"sweep": {
        "method": "sobol", "n_cases": 4, "seed": 3, "scheduler": "serial",
        "variables": {"operation.rpm": {"low": 40.0, "high": 120.0},
                      "friction.mu_dynamic": {"low": 0.15, "high": 0.3}},
        "cases_path": str(tmp_path / "design" / "cases.parquet"),
        "sweep_dir": str(tmp_path / "sweep"), "fatigue_dir": str(tmp_path / "fatigue"),
        "dataset_dir": str(tmp_path / "dataset")} | sweep}
    path = tmp_path / "params.yaml"
    path.write_text(yaml.safe_dump(data))
    return path


def test_chain_with_synthetic_cases_and_rerun_is_noop(tmp_path):
    params = load_params(_params(tmp_path))
    cases = design_stage(params)
    assert len(cases) == 4 and (tmp_path / "design" / "coverage.csv").is_file()
    rep = simulate_stage(params, case_fn=synthetic_case)
    assert rep.n_done == 4
    rep = fatigue_stage(params, fatigue_fn=synthetic_fatigue)
    assert rep.n_done == 4
    metrics = dataset_stage(params)
    df = pd.read_parquet(tmp_path / "dataset" / "damage.parquet")
    assert metrics["n_cases_in_dataset"] == 4 and len(df) == metrics["n_rows"] > 0
    assert {"operation.rpm", "friction.mu_dynamic"} <= set(df.columns)
    # second pass: design identical, nothing re-run
    again = design_stage(params)
    assert again["case_id"].tolist() == cases["case_id"].tolist()
    assert simulate_stage(params, case_fn=synthetic_case).n_skipped == 4
    assert fatigue_stage(params, fatigue_fn=synthetic_fatigue).n_skipped == 4
    # changed fatigue settings re-evaluate fatigue only
    changed = params.model_copy(update={"fatigue": params.fatigue.model_copy(update={"grade": "E-75"})})
    assert design_stage(changed).equals(cases)
    assert simulate_stage(changed, case_fn=synthetic_case).n_skipped == 4
    assert fatigue_stage(changed, fatigue_fn=synthetic_fatigue).n_done == 4


def _script(name: str):
    spec = importlib.util.spec_from_file_location(f"pipeline_{name}", ROOT / "pipeline" / f"{name}.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_bad_params_one_line_error_before_any_work(tmp_path, capsys):
    path = _params(tmp_path, variables={"operation.rpmm": {"low": 1, "high": 2}})
    assert _script("design").main(["--params", str(path)]) == 2
    err = capsys.readouterr().err.strip()
    assert err.count("\n") == 0
    assert err.startswith("error: sweep.variables.operation.rpmm: unknown configuration path")
    assert not (tmp_path / "design").exists()
    path = _params(tmp_path, variables={"operation.rpm": {"low": 1, "high": 500}})
    assert _script("design").main(["--params", str(path)]) == 2
    assert "sweep.variables.operation.rpm" in capsys.readouterr().err


@pytest.mark.slow  # real simulator + fatigue on 2 tiny cases, ~15-30 s with numba compile
def test_chain_with_real_simulator_and_fatigue(tmp_path):
    path = _params(tmp_path, n_cases=2, method="lhs", fatigue_criteria=["matake", "uniaxial"])
    assert _script("design").main(["--params", str(path)]) == 0
    # process pool: the warm-up hooks run in this process, the case functions pickle by name
    for stage in ("simulate", "fatigue"):
        args = ["--params", str(path), "--no-progress", "--scheduler", "processes",
                "--metrics", str(tmp_path / f"{stage}.json")]
        assert _script(stage).main(args) == 0
        assert json.loads((tmp_path / f"{stage}.json").read_text())["n_done"] == 2
    assert _script("dataset").main(["--params", str(path)]) == 0
    df = pd.read_parquet(tmp_path / "dataset" / "damage.parquet")
    assert df["case_id"].nunique() == 2
    # 2 cases x 2 recorded joints x (body, connection), and the upset run-out of drill pipe
    per_joint = df.groupby(["case_id", "joint"])["location"].agg(lambda x: tuple(sorted(x)))
    assert len(per_joint) == 2 * 2
    ctype = df.groupby(["case_id", "joint"])["component_type"].first()
    for key, locs in per_joint.items():
        want = ("body", "connection", "upset") if ctype[key] in UPSET_TYPES else ("body", "connection")
        assert locs == want, (key, ctype[key], locs)
    for col in ("damage_rate_per_h_matake", "damage_rate_per_h_uniaxial", "damage_rate_per_h_api_rp7g",
                "peak_surface_torque_Nm", "rms_surface_torque_Nm", "md_m", "s_from_bit_m"):
        assert col in df.columns, col
    assert (df["damage_rate_per_h_uniaxial"] >= 0).all()
    assert df["peak_surface_torque_Nm"].notna().all()
    # API RP7G rows exist for pipe bodies only
    body = df[df["location"] == "body"]
    assert body["damage_rate_per_h_api_rp7g"].notna().all()
    assert df.loc[df["location"] == "connection", "damage_rate_per_h_api_rp7g"].isna().all()
    # the uniaxial rows reused from the matake evaluation equal a direct uniaxial evaluation
    from drillfatigue.fatigue import evaluate_run

    cid = df["case_id"].iloc[0]
    direct = evaluate_run(tmp_path / "sweep" / cid, load_params(path).fatigue, None,
                          criterion="uniaxial").set_index(["joint", "location"])
    mine = df[df["case_id"] == cid].set_index(["joint", "location"])
    pd.testing.assert_series_equal(mine["damage_rate_per_h_uniaxial"].sort_index(),
                                   direct["damage_rate_per_h"].sort_index(), check_names=False,
                                   rtol=1e-12)
    card = (tmp_path / "dataset" / "README.md").read_text()
    assert "cases in the dataset: 2" in card
    report = json.loads((tmp_path / "sweep" / "sweep.json").read_text())
    assert report["n_failed"] == 0


def test_replicates_stage_with_synthetic_cases_resumes_and_pools(tmp_path):
    from drillfatigue.sweep.replicates import replicates_stage

    path = _params(tmp_path)
    data = yaml.safe_load(path.read_text())
    data["replicates"] = {"n_cases": 2, "n_replicates": 3, "rel_step": 1e-4,
                          "out_dir": str(tmp_path / "replicates")}
    path.write_text(yaml.safe_dump(data))
    params = load_params(path)
    design_stage(params)
    simulate_stage(params, case_fn=synthetic_case)
    fatigue_stage(params, fatigue_fn=synthetic_fatigue)
    out = replicates_stage(params, case_fn=synthetic_case, fatigue_fn=synthetic_fatigue)
    assert out["sweeps"]["simulate"]["n_done"] == 4 and out["sweeps"]["fatigue"]["n_done"] == 4
    table = pd.read_parquet(tmp_path / "replicates" / "spread.parquet")
    # 2 cases x 3 runs (the design run is replicate 0, read from the sweep's fatigue)
    assert sorted(table.groupby("base_case_id")["replicate"].nunique()) == [3, 3]
    assert out["n_cases"] == 2 and out["n_rows"] == len(table) and out["sigma_log10"] >= 0.0
    saved = json.loads((tmp_path / "replicates" / "spread.json").read_text())
    assert saved["sigma_log10"] == out["sigma_log10"] and saved["criterion"] == "matake"
    again = replicates_stage(params, case_fn=synthetic_case, fatigue_fn=synthetic_fatigue)
    assert again["sweeps"]["simulate"]["n_skipped"] == 4 and again["sigma_log10"] == out["sigma_log10"]


def _heldout_params(tmp_path: Path, **sweep) -> Path:
    path = _params(tmp_path, **sweep)
    data = yaml.safe_load(path.read_text())
    data["heldout"] = {"n_cases": 4, "seed": 11,
                       **{k: str(tmp_path / "heldout" / v) for k, v in (
                           ("cases_path", "design/cases.parquet"), ("sweep_dir", "sweep"),
                           ("fatigue_dir", "fatigue"), ("dataset_dir", "dataset"))}}
    path.write_text(yaml.safe_dump(data))
    return path


def test_heldout_stage_runs_the_sweep_code_apart_and_shares_no_case(tmp_path):
    from drillfatigue.sweep.stages import heldout_stage

    params = load_params(_heldout_params(tmp_path))
    train = design_stage(params)
    # a training table with a column that is constant in the test design
    (tmp_path / "dataset").mkdir()
    pd.DataFrame({"case_id": ["a", "b"], "wall_time_s": [1.0, 2.0]}).to_parquet(
        tmp_path / "dataset" / "damage.parquet")
    metrics = heldout_stage(params, case_fn=synthetic_case, fatigue_fn=synthetic_fatigue)
    test = pd.read_parquet(tmp_path / "heldout" / "dataset" / "damage.parquet")
    # the synthetic runs report a wall time of 0: constant, kept for the training table's sake
    assert "wall_time_s" in test.columns and test["wall_time_s"].nunique() == 1
    assert metrics["n_cases_in_dataset"] == 4 == test["case_id"].nunique()
    assert not set(test["case_id"]) & set(train["case_id"])
    assert metrics["n_cases_shared_with_training_dropped"] == 0
    # the training runs are untouched: the held-out runs live under heldout/
    assert not (tmp_path / "sweep").exists() and (tmp_path / "heldout" / "sweep").is_dir()
    card = (tmp_path / "heldout" / "dataset" / "README.md").read_text()
    assert "seed 11" in card and f"{tmp_path / 'heldout' / 'sweep'}/failures.parquet" in card


def test_heldout_cases_shared_with_training_are_left_out(tmp_path):
    """A design of two categorical values has the same two cases for every seed: the
    held-out stage drops them, and refuses a test set left empty."""
    from drillfatigue.errors import InputError
    from drillfatigue.sweep.stages import heldout_stage

    path = _heldout_params(tmp_path, variables={"friction.mu_dynamic": {"choices": [0.2, 0.3]}})
    params = load_params(path)
    with pytest.warns(UserWarning, match="merged"):
        design_stage(params)
    with pytest.raises(InputError) as exc, pytest.warns(UserWarning, match="merged"):
        heldout_stage(params, case_fn=synthetic_case, fatigue_fn=synthetic_fatigue)
    assert exc.value.field == "heldout.n_cases"
    same_seed = params.model_copy(update={"heldout": params.heldout.model_copy(
        update={"seed": params.sweep.seed})})
    with pytest.raises(InputError, match="equals sweep.seed"):
        heldout_stage(same_seed, case_fn=synthetic_case, fatigue_fn=synthetic_fatigue)


def test_heldout_draws_run_every_heldout_case_centred_on_its_rpm(tmp_path):
    from drillfatigue.sweep.replicates import heldout_draws_stage
    from drillfatigue.sweep.stages import heldout_stage

    path = _heldout_params(tmp_path)
    data = yaml.safe_load(path.read_text())
    data["heldout"] |= {"draws": 3, "draw_rel_step": 0.02,
                        "draws_dir": str(tmp_path / "heldout" / "draws")}
    path.write_text(yaml.safe_dump(data))
    params = load_params(path)
    design_stage(params)
    heldout_stage(params, case_fn=synthetic_case, fatigue_fn=synthetic_fatigue)
    out = heldout_draws_stage(params, case_fn=synthetic_case, fatigue_fn=synthetic_fatigue)
    draws = tmp_path / "heldout" / "draws"
    cases = pd.read_parquet(draws / "cases.parquet")
    held = pd.read_parquet(tmp_path / "heldout" / "design" / "cases.parquet")
    # every held-out case, two more runs at rpm x 1.02 and x 0.98
    assert set(cases["base_case_id"]) == set(held["case_id"]) and len(cases) == 2 * len(held)
    rpm = {cid: json.loads(t)["operation"]["rpm"]
           for cid, t in zip(held["case_id"], held["case_json"], strict=True)}
    ratio = sorted({round(v / rpm[b], 12)
                    for v, b in zip(cases["value"], cases["base_case_id"], strict=True)})
    assert ratio == [0.98, 1.02]
    table = pd.read_parquet(draws / "spread.parquet")
    assert (table.groupby("base_case_id")["replicate"].nunique() == 3).all()
    assert out["symmetric"] is True and out["n_cases"] == len(held)
    assert not (tmp_path / "replicates").exists()  # the training noise floor is untouched


def test_heldout_draws_one_draw_runs_nothing(tmp_path):
    from drillfatigue.errors import InputError
    from drillfatigue.sweep.replicates import heldout_draws_stage
    from drillfatigue.sweep.stages import heldout_stage

    path = _heldout_params(tmp_path)
    data = yaml.safe_load(path.read_text())
    data["heldout"] |= {"draws": 1, "draws_dir": str(tmp_path / "heldout" / "draws")}
    path.write_text(yaml.safe_dump(data))
    params = load_params(path)
    with pytest.raises(InputError, match="heldout.cases_path"):
        heldout_draws_stage(params, case_fn=synthetic_case, fatigue_fn=synthetic_fatigue)
    design_stage(params)
    heldout_stage(params, case_fn=synthetic_case, fatigue_fn=synthetic_fatigue)
    out = heldout_draws_stage(params, case_fn=synthetic_case, fatigue_fn=synthetic_fatigue)
    assert out["n_rows"] == 0 and out["sweeps"] == {}
    assert len(pd.read_parquet(tmp_path / "heldout" / "draws" / "spread.parquet")) == 0
