"""The design stage in ``sweep.method: adaptive`` with the synthetic simulator and fatigue:
the case table gains rounds, the cases run into the cache folder, a rerun simulates nothing."""

from __future__ import annotations

import importlib.util
import json
from pathlib import Path

import pandas as pd
import yaml

from drillfatigue.config import load_params
from drillfatigue.files import MARKER
from drillfatigue.sweep.stages import (
    adaptive_rows,
    design_stage,
    heldout_params,
    simulate_stage,
)
from testkit.synthetic_sweep import TINY_PARAMS as TINY
from testkit.synthetic_sweep import synthetic_case, synthetic_fatigue

ROOT = Path(__file__).parents[2]


def _params(tmp_path: Path, **sweep) -> Path:
    data = TINY | {"sweep": {
        "method": "adaptive", "n_cases": 7, "seed": 3, "scheduler": "serial",
        "adaptive": {"n_initial": 4, "batch_size": 2, "candidates": 32, "seed": 5,
                     "n_members": 3, "cache_dir": str(tmp_path / "design" / "adaptive")},
        "variables": {"operation.rpm": {"low": 40.0, "high": 120.0},
                      "friction.mu_dynamic": {"low": 0.15, "high": 0.3}},
        "cases_path": str(tmp_path / "design" / "cases.parquet"),
        "sweep_dir": str(tmp_path / "sweep"), "fatigue_dir": str(tmp_path / "fatigue"),
        "dataset_dir": str(tmp_path / "dataset")} | sweep}
    path = tmp_path / "params.yaml"
    path.write_text(yaml.safe_dump(data))
    return path


def test_adaptive_design_stage_caches_cases_and_reruns_without_simulating(tmp_path):
    params = load_params(_params(tmp_path))
    frame = design_stage(params, case_fn=synthetic_case, fatigue_fn=synthetic_fatigue)
    assert frame["round"].tolist() == [0, 0, 0, 0, 1, 1, 2]
    written = pd.read_parquet(tmp_path / "design" / "cases.parquet")
    assert written["case_id"].tolist() == frame["case_id"].tolist()
    assert "round" in written.columns
    info = json.loads((tmp_path / "design" / "design.json").read_text())
    assert info["method"] == "adaptive" and info["adaptive"]["cases_per_round"] == [4, 2, 1]
    cache = tmp_path / "design" / "adaptive"
    assert sorted(p.name for p in (cache / "fatigue").iterdir() if p.is_dir()) == \
        sorted(frame["case_id"])
    sweep_report = json.loads((cache / "sweep" / "sweep.json").read_text())
    # rerun: the same design, every case read back from the cache (no simulation)
    again = design_stage(params, case_fn=synthetic_case, fatigue_fn=synthetic_fatigue)
    pd.testing.assert_frame_equal(again, frame)
    report = json.loads((cache / "sweep" / "sweep.json").read_text())
    assert report["n_done"] == 0 and report["run"] > sweep_report["run"]
    # the simulate stage reads the written table like any design
    assert simulate_stage(params, case_fn=synthetic_case).n_done == 7


def test_sobol_design_claims_an_empty_cache_folder_beside_the_table(tmp_path):
    # no adaptive.cache_dir: the folder is adaptive/ beside the case table
    params = load_params(_params(tmp_path, method="sobol", n_cases=4, adaptive={}))
    frame = design_stage(params)
    assert len(frame) == 4 and "round" not in frame.columns
    cache = tmp_path / "design" / "adaptive"
    assert [p.name for p in cache.iterdir()] == [MARKER]


def test_held_out_design_of_an_adaptive_training_design_is_sobol(tmp_path):
    params = load_params(_params(tmp_path))
    assert heldout_params(params).sweep.method == "sobol"


def _design_script_error(path, capsys) -> str:
    """Run pipeline/design.py on ``path``; it must exit with 2 and print one line: that line."""
    spec = importlib.util.spec_from_file_location("pipeline_design", ROOT / "pipeline" / "design.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    assert module.main(["--params", str(path)]) == 2
    err = capsys.readouterr().err.strip()
    assert err.count("\n") == 0
    return err


def test_bad_adaptive_block_one_line_error_nothing_written(tmp_path, capsys):
    path = _params(tmp_path, adaptive={"n_initial": 16, "cache_dir": str(tmp_path / "c")})
    err = _design_script_error(path, capsys)
    assert err.startswith("error: sweep.adaptive.n_initial: 16 initial cases exceed n_cases = 7")
    assert not (tmp_path / "design").exists() and not (tmp_path / "c").exists()


def test_row_level_acquisition_in_the_stage_builds_candidate_rows_and_resumes(tmp_path):
    """``acquisition: mix`` (row-level disagreement, half the batch space-filling) runs in
    the stage on the dataset rows of the cached cases and candidates' rows built from their
    inputs; a rerun gives the same design without simulating."""
    params = load_params(_params(tmp_path, n_cases=8, adaptive={
        "n_initial": 4, "batch_size": 2, "candidates": 32, "seed": 5, "n_members": 3,
        "acquisition": "mix", "space_filling_share": 0.5,
        "cache_dir": str(tmp_path / "design" / "adaptive")}))
    frame = design_stage(params, case_fn=synthetic_case, fatigue_fn=synthetic_fatigue)
    assert frame["round"].tolist() == [0, 0, 0, 0, 1, 1, 2, 2]
    # (the synthetic chain's rates do not depend on the inputs: nothing to dispute here;
    # tests/unit/sweep/test_adaptive.py checks where the row-level batches go)
    assert (frame["acquisition_score"].iloc[4:] >= 0.0).all()
    # the candidates' rows: the locations of a finished case, moved to the candidate's bit
    src = adaptive_rows(params)
    done = src.finished(frame.iloc[:4])
    cand = src.candidates(frame.iloc[4:], done)
    assert set(cand["case_id"]) == set(frame["case_id"].iloc[4:])
    one = cand[cand["case_id"] == frame["case_id"].iloc[4]]
    assert len(one) == (done["case_id"] == done["case_id"].iloc[0]).sum()
    assert (one["operation.rpm"] == frame["operation.rpm"].iloc[4]).all()
    again = design_stage(params, case_fn=synthetic_case, fatigue_fn=synthetic_fatigue)
    pd.testing.assert_frame_equal(again, frame)
    report = json.loads((tmp_path / "design" / "adaptive" / "sweep" / "sweep.json").read_text())
    assert report["n_done"] == 0


def test_unknown_acquisition_one_line_error_nothing_written(tmp_path, capsys):
    path = _params(tmp_path, adaptive={"acquisition": "widest",
                                       "cache_dir": str(tmp_path / "c")})
    err = _design_script_error(path, capsys)
    assert err.startswith("error: sweep.adaptive.acquisition: ")
    assert "(allowed: 'governing', 'rows' or 'mix')" in err
    assert not (tmp_path / "design").exists() and not (tmp_path / "c").exists()
