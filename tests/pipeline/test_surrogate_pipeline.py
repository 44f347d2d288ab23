"""``train`` and ``evaluate`` stage scripts on a tiny params file and the synthetic table."""

from __future__ import annotations

import importlib.util
import json
from pathlib import Path

import pandas as pd

from drillfatigue.surrogate import make_synthetic_dataset

ROOT = Path(__file__).resolve().parents[2]


def _stage(name: str):  # noqa: ANN202
    spec = importlib.util.spec_from_file_location(f"stage_{name}", ROOT / "pipeline" / f"{name}.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def test_train_then_evaluate(tmp_path: Path, capsys) -> None:
    params = tmp_path / "params.yaml"
    params.write_text("surrogate:\n  hidden_layers: [16]\n  max_epochs: 5\n  patience: 5\n"
                      "  n_threads: 1\n  gp_max_rows: 60\n  hgb_max_iter: 20\n", encoding="utf-8")
    model, live = tmp_path / "models" / "surrogate", tmp_path / "live"
    assert _stage("train").main(["--params", str(params), "--out", str(model), "--live", str(live),
                                 "--synthetic-cases", "25"]) == 0
    assert (model / "metadata.json").is_file() and (model / "model.ts").is_file()
    # dvclive curves: one train and one val series per member, one row per epoch
    tsv = live / "plots" / "metrics" / "train" / "loss" / "member4.tsv"
    assert len(pd.read_csv(tsv, sep="\t")) == json.loads(
        (model / "metadata.json").read_text())["training"]["epochs"]
    metrics, plots = tmp_path / "metrics.json", tmp_path / "plots"
    assert _stage("evaluate").main(["--params", str(params), "--model", str(model),
                                    "--metrics", str(metrics), "--plots", str(plots),
                                    "--synthetic-cases", "25"]) == 0
    m = json.loads(metrics.read_text())
    for name in ("ensemble", "gp", "hgb"):
        assert {"r2", "rmse", "mae", "coverage", "mean_width", "factor2_fraction"} <= set(m[name])
    assert m["gp"]["train_rows"] <= 60
    pred = pd.read_csv(plots / "predictions.csv")
    assert len(pred) == m["n_test_rows"]
    assert (plots / "parity.png").is_file() and (plots / "residuals.png").is_file()
    assert m["test_source"] == "split" and "deciding" in m and "monotone_dls" in m
    # a held-out dataset of its own design, named in params: every row scored
    held = make_synthetic_dataset(6, seed=99)
    held["case_id"] = "held_" + held["case_id"]
    held_path = tmp_path / "heldout.parquet"
    held.to_parquet(held_path)
    params.write_text(params.read_text(encoding="utf-8") + f"  heldout_path: {held_path}\n",
                      encoding="utf-8")
    assert _stage("evaluate").main(["--params", str(params), "--model", str(model),
                                    "--metrics", str(metrics), "--plots", str(plots),
                                    "--synthetic-cases", "25"]) == 0
    m = json.loads(metrics.read_text())
    assert m["test_source"] == "heldout" and m["n_test_rows"] == len(held)
    assert "scored on heldout cases (6)" in capsys.readouterr().out


def test_missing_dataset_exits_2(tmp_path: Path, capsys) -> None:
    params = tmp_path / "params.yaml"
    params.write_text("surrogate: {}\n", encoding="utf-8")
    rc = _stage("train").main(["--params", str(params), "--data", str(tmp_path / "none.parquet"),
                               "--out", str(tmp_path / "m"), "--live", str(tmp_path / "l")])
    assert rc == 2
    assert "none.parquet" in capsys.readouterr().err
    assert not (tmp_path / "m").exists()


def test_train_refuses_a_foreign_out_folder_before_training(tmp_path: Path, capsys) -> None:
    """`train.py --out DIR` with a user's file in DIR: exit 2, one line, before any
    training (no live curves written), and the file survives."""
    params = tmp_path / "params.yaml"
    params.write_text("surrogate:\n  hidden_layers: [8]\n  max_epochs: 2\n  n_threads: 1\n",
                      encoding="utf-8")
    out = tmp_path / "models"
    out.mkdir()
    (out / "thesis.docx").write_bytes(b"user data")
    live = tmp_path / "live"
    rc = _stage("train").main(["--params", str(params), "--out", str(out), "--live", str(live),
                               "--synthetic-cases", "20"])
    assert rc == 2
    err = capsys.readouterr().err
    assert err.startswith("error: --out: ") and err.count("\n") == 1
    assert "did not write" in err
    assert sorted(p.name for p in out.iterdir()) == ["thesis.docx"]
    assert (out / "thesis.docx").read_bytes() == b"user data"
    assert not live.exists()


def test_evaluate_refuses_a_foreign_plots_folder_first(tmp_path: Path, capsys) -> None:
    """`evaluate.py --plots DIR` with a user's file: exit 2, one line, before the model is
    even loaded (the model folder does not exist), the file untouched; the committed
    data/surrogate/plots marker lists exactly the stage's three files."""
    plots = tmp_path / "plots"
    plots.mkdir()
    (plots / "parity.png").write_bytes(b"my figure")
    rc = _stage("evaluate").main(["--params", str(tmp_path / "none.yaml"), "--model",
                                  str(tmp_path / "no_model"), "--metrics",
                                  str(tmp_path / "m.json"), "--plots", str(plots)])
    assert rc == 2
    err = capsys.readouterr().err
    assert err.startswith("error: --plots: ") and err.count("\n") == 1
    assert (plots / "parity.png").read_bytes() == b"my figure"
    assert not (tmp_path / "m.json").exists()
    committed = ROOT / "data" / "surrogate" / "plots"
    marker = json.loads((committed / ".drillfatigue.json").read_text())
    assert marker == {"kind": _stage("evaluate").PLOTS_KIND,
                      "files": sorted(p.name for p in committed.iterdir()
                                      if not p.name.startswith("."))}
