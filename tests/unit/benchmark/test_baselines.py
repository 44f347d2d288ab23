"""Baselines and the leaderboard on the fixture (6 training cases, 2 held-out cases).

The fitted baselines run with small settings (few epochs, a small GP
subsample): the test checks the plumbing (every held-out row predicted, the
file scored, the page written), not the scores; the leaderboard page gives those.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from drillfatigue.benchmark.baselines import physics_log10_rate, predict_physics, case_configs
from drillfatigue.benchmark.leaderboard import leaderboard_markdown, run_leaderboard
from drillfatigue.benchmark.score import LOWER, PREDICTION, UPPER
from drillfatigue.benchmark.splits import load_split
from drillfatigue.config import FatigueConfig, load_params
from drillfatigue.errors import InputError

ROOT = Path(__file__).resolve().parents[3]
DATA = ROOT / "tests" / "data" / "research_dataset"


@pytest.fixture(scope="module")
def params():  # type: ignore[no-untyped-def]
    return load_params(ROOT / "params.yaml")


@pytest.fixture(scope="module")
def design() -> pd.DataFrame:
    return pd.read_parquet(DATA / "heldout_design.parquet")


def test_physics_baseline_follows_lubinski(params, design: pd.DataFrame) -> None:  # type: ignore[no-untyped-def]
    heldout = load_split("heldout", DATA)
    pred = predict_physics(heldout, design, params.surrogate, params.fatigue)
    assert list(pred[["case_id", "joint", "location"]].itertuples(index=False)) == \
        list(heldout[["case_id", "joint", "location"]].itertuples(index=False))
    mu = pred[PREDICTION].to_numpy()
    assert np.isfinite(mu).all() and mu.min() >= -12.0
    # more curvature, more damage: the same rows with the dogleg doubled
    case_id = heldout["case_id"].iloc[0]
    rows = heldout[heldout["case_id"] == case_id]
    case = case_configs(design)[case_id]
    base = physics_log10_rate(rows, case, params.fatigue)
    bent = physics_log10_rate(rows.assign(local_dls_deg_per_30m=2 * rows["local_dls_deg_per_30m"]),
                              case, params.fatigue)
    bending = np.isfinite(base) & (rows["local_dls_deg_per_30m"].to_numpy() > 0)
    assert bending.any() and (bent[bending] > base[bending]).all()
    # a straight hole does not bend the pipe: no damage
    straight = physics_log10_rate(rows.assign(local_dls_deg_per_30m=0.0), case, params.fatigue)
    assert np.isneginf(straight).all()


def test_physics_needs_every_heldout_case_in_the_design(params, design: pd.DataFrame) -> None:  # type: ignore[no-untyped-def]
    heldout = load_split("heldout", DATA)
    with pytest.raises(InputError, match="not in the design"):
        predict_physics(heldout, design.iloc[:1], params.surrogate, FatigueConfig())


@pytest.mark.slow
@pytest.mark.timeout(600)
def test_leaderboard_fits_scores_and_writes_the_page(params, design: pd.DataFrame,  # type: ignore[no-untyped-def]
                                                     tmp_path: Path) -> None:
    cfg = params.surrogate.model_copy(update={"max_epochs": 3, "patience": 2,
                                              "gp_max_rows": 80, "hgb_max_iter": 20,
                                              "conformal_folds": 3})
    result = run_leaderboard(DATA, tmp_path / "lb", cfg, params.fatigue, design=design,
                             variants={"ensemble_small": {
                                 "model": "ensemble", "hidden_layers": [16],
                                 "features": [*cfg.features, "log10_s_from_bit_m"]}},
                             log=lambda s: None)
    assert set(result["models"]) == {"gbm", "ensemble", "gp", "physics", "ensemble_small"}
    assert result["dataset"]["n_train_cases"] == 6 and result["dataset"]["n_heldout_cases"] == 2
    n = len(load_split("heldout", DATA))
    for name, entry in result["models"].items():
        pred = pd.read_parquet(entry["predictions"])
        assert len(pred) == n and np.isfinite(pred[PREDICTION]).all(), name
        assert (LOWER in pred) == (name != "physics") == (UPPER in pred)
        assert 0.0 <= entry["headline"]["factor2_deciding"] <= 1.0 or \
            math.isnan(entry["headline"]["factor2_deciding"])
    assert result["models"]["ensemble_small"]["overrides"]["hidden_layers"] == [16]
    page = leaderboard_markdown(result, command="drillfatigue benchmark leaderboard", note="tiny")
    assert "| gbm |" in page and "| physics |" in page and "drillfatigue benchmark leaderboard" in page
    json.dumps(result, default=str)
    with pytest.raises(InputError, match="hidden_layers"):
        run_leaderboard(DATA, tmp_path / "lb4", cfg, params.fatigue, models=[],
                        variants={"bad": {"model": "ensemble", "hidden_layers": []}})
    with pytest.raises(InputError, match="unknown model"):
        run_leaderboard(DATA, tmp_path / "lb2", cfg, params.fatigue, models=["svm"])
    with pytest.raises(InputError, match="needs the held-out cases' design"):
        run_leaderboard(DATA, tmp_path / "lb3", cfg, params.fatigue, models=["physics"])


def test_cli_leaderboard_writes_page_and_json(tmp_path: Path,
                                              capsys: pytest.CaptureFixture[str]) -> None:
    from drillfatigue.cli import main

    page, results = tmp_path / "leaderboard.md", tmp_path / "leaderboard.json"
    assert main(["benchmark", "leaderboard", "--dataset", str(DATA), "--models", "physics",
                 "--design", str(DATA / "heldout_design.parquet"), "--out",
                 str(tmp_path / "lb"), "--out-page", str(page), "--out-json", str(results),
                 "--params", str(ROOT / "params.yaml"), "--note", "fixture"]) == 0
    text = page.read_text()
    assert "| physics |" in text and "fixture" in text
    assert "drillfatigue benchmark leaderboard" in text
    data = json.loads(results.read_text(),  # strict JSON: NaN written as null
                      parse_constant=lambda c: pytest.fail(f"{c} in the JSON"))
    assert set(data["models"]) == {"physics"}
    capsys.readouterr()
    assert main(["benchmark", "leaderboard", "--dataset", str(DATA), "--models", "physics",
                 "--out", str(tmp_path / "lb"), "--out-page", str(page), "--out-json",
                 str(results), "--params", str(ROOT / "params.yaml")]) == 2
    assert "needs the held-out cases' design" in capsys.readouterr().err


def test_the_committed_variants_are_valid_surrogate_settings() -> None:
    from drillfatigue.config.surrogate import SurrogateConfig

    spec = json.loads((ROOT / "benchmarks" / "leaderboard_variants.json").read_text())
    for name, entry in spec.items():
        entry = dict(entry)
        assert entry.pop("model") in ("gbm", "ensemble", "gp"), name
        SurrogateConfig.model_validate(SurrogateConfig().model_dump() | entry)


def test_log_features_are_log10_of_the_column_plus_its_offset() -> None:
    from drillfatigue.benchmark.baselines import LOG_FEATURES, add_log_features

    frame = load_split("heldout", DATA)
    out = add_log_features(frame)
    for col, offset in LOG_FEATURES.items():
        np.testing.assert_allclose(out[f"log10_{col}"], np.log10(frame[col] + offset))
    with pytest.raises(InputError, match="has no log"):
        add_log_features(frame.assign(**{"operation.rpm": 0.0}))
