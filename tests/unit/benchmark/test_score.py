"""The evaluation command: a prediction file scored on the held-out split."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from drillfatigue.benchmark.score import LOWER, PREDICTION, UPPER, score_predictions
from drillfatigue.benchmark.splits import load_split
from drillfatigue.cli import main
from drillfatigue.errors import InputError

DATA = Path(__file__).resolve().parents[2] / "data" / "research_dataset"


@pytest.fixture(scope="module")
def heldout() -> pd.DataFrame:
    return load_split("heldout", DATA)


def truth(heldout: pd.DataFrame) -> np.ndarray:
    return np.log10(np.maximum(heldout["damage_rate_per_h_matake"].to_numpy(), 1e-12))


def predictions(heldout: pd.DataFrame, offset: float = 0.0, interval: float | None = 0.5
                ) -> pd.DataFrame:
    pred = heldout[["case_id", "joint", "location"]].copy()
    pred[PREDICTION] = truth(heldout) + offset
    if interval is not None:
        pred[LOWER] = pred[PREDICTION] - interval
        pred[UPPER] = pred[PREDICTION] + interval
    return pred.sample(frac=1.0, random_state=0)  # any row order


def test_the_simulation_itself_scores_perfectly(heldout: pd.DataFrame) -> None:
    m = score_predictions(predictions(heldout), heldout)
    h = m["headline"]
    assert h["factor2_deciding"] == 1.0 and h["factor2_governing_component"] == 1.0
    assert h["coverage_deciding"] == 1.0 and h["rmse_all"] == 0.0
    # the fixture has rows simulated beyond the horizon: answered so, and only those
    assert h["longer_than_precision"] == 1.0 and h["longer_than_recall"] == 1.0
    assert h["n_deciding_rows"] == int((truth(heldout) >= -5.0).sum())
    assert m["n_rows"] == len(heldout) and m["n_cases"] == 2
    d = m["deciding"]
    assert set(d["by_component_type_location"]) >= {"drill_pipe body", "drill_pipe connection"}
    assert all(v["factor2_fraction"] == 1.0 for v in d["by_decade"].values())


def test_a_factor_3_error_fails_factor_2_everywhere(heldout: pd.DataFrame) -> None:
    h = score_predictions(predictions(heldout, offset=math.log10(3.0), interval=None),
                          heldout)["headline"]
    assert h["factor2_deciding"] == 0.0
    assert h["coverage_deciding"] is None and h["mean_width_deciding"] is None


def test_no_interval_gives_no_coverage_anywhere(heldout: pd.DataFrame) -> None:
    m = score_predictions(predictions(heldout, interval=None), heldout)
    text = json.dumps(m, default=str)
    assert '"coverage"' not in text and '"mean_width"' not in text


@pytest.mark.parametrize(("change", "message"), [
    (lambda p: p.drop(columns=[PREDICTION]), "columns \\['log10_damage_rate_per_h'\\] missing"),
    (lambda p: p.drop(columns=[LOWER]), "an interval needs both bounds"),
    (lambda p: p.assign(**{PREDICTION: np.nan}), "value\\(s\\) missing"),
    (lambda p: p.assign(**{LOWER: p[UPPER] + 1.0}), "lower bound above the upper"),
    (lambda p: pd.concat([p, p.iloc[:1]]), "given twice"),
    (lambda p: p.iloc[1:], "held-out row\\(s\\) without a prediction"),
    (lambda p: pd.concat([p, p.iloc[:1].assign(case_id="notacase")]),
     "not in the held-out split"),
])
def test_bad_prediction_tables_are_one_line_input_errors(heldout: pd.DataFrame, change,
                                                         message: str) -> None:
    with pytest.raises(InputError, match=message):
        score_predictions(change(predictions(heldout)), heldout)


def test_cli_scores_a_file_and_refuses_bad_ones(heldout: pd.DataFrame, tmp_path: Path,
                                               capsys: pytest.CaptureFixture[str]) -> None:
    good = tmp_path / "pred.parquet"
    predictions(heldout).to_parquet(good, index=False)
    out = tmp_path / "metrics.json"
    assert main(["benchmark", "score", "--predictions", str(good), "--dataset", str(DATA),
                 "--out", str(out)]) == 0
    assert "factor 2, deciding rows" in capsys.readouterr().out
    assert json.loads(out.read_text())["headline"]["factor2_deciding"] == 1.0
    csv = tmp_path / "pred.csv"
    predictions(heldout, interval=None).to_csv(csv, index=False)
    assert main(["benchmark", "score", "--predictions", str(csv), "--dataset", str(DATA)]) == 0
    capsys.readouterr()
    for bad, text in ((tmp_path / "missing.parquet", "not found"),
                      (tmp_path / "junk.parquet", "not a readable parquet")):
        if "junk" in bad.name:
            bad.write_text("not parquet")
        assert main(["benchmark", "score", "--predictions", str(bad), "--dataset",
                     str(DATA)]) == 2
        err = capsys.readouterr().err
        assert text in err and err.count("\n") == 1
    partial = tmp_path / "partial.parquet"
    predictions(heldout).iloc[5:].to_parquet(partial, index=False)
    assert main(["benchmark", "score", "--predictions", str(partial), "--dataset",
                 str(DATA)]) == 2
    assert "without a prediction" in capsys.readouterr().err
