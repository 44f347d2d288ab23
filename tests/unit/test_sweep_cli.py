"""CLI: ``sweep design``, ``sweep run`` argument errors, ``dataset export --histories``."""

from __future__ import annotations

import pandas as pd
import pytest
import yaml

from drillfatigue.cli import main
from drillfatigue.sweep.runner import Case, run_sweep
from testkit.synthetic_sweep import synthetic_case


def _params(tmp_path, variables):
    path = tmp_path / "params.yaml"
    path.write_text(yaml.safe_dump({"sweep": {
        "n_cases": 4, "variables": variables, "scheduler": "serial",
        "cases_path": str(tmp_path / "design" / "cases.parquet"),
        "sweep_dir": str(tmp_path / "sweep")}}))
    return path


def test_sweep_design_writes_cases(tmp_path, capsys):
    path = _params(tmp_path, {"operation.rpm": {"low": 60, "high": 120}})
    assert main(["sweep", "design", "--params", str(path)]) == 0
    cases = pd.read_parquet(tmp_path / "design" / "cases.parquet")
    assert len(cases) == 4 and cases["operation.rpm"].between(60, 120).all()
    assert "4 cases" in capsys.readouterr().out


def test_bad_input_is_one_line_exit_2_and_writes_nothing(tmp_path, capsys):
    path = _params(tmp_path, {"operation.rpm": {"low": 60, "high": 9000}})
    assert main(["sweep", "design", "--params", str(path)]) == 2
    err = capsys.readouterr().err
    assert err.startswith("error: sweep.variables.operation.rpm:") and err.count("\n") == 1
    assert not (tmp_path / "design").exists()
    path = _params(tmp_path, {})
    assert main(["sweep", "run", "--params", str(path), "--scheduler", "bogus"]) == 2
    assert "sweep.scheduler" in capsys.readouterr().err
    assert not (tmp_path / "design").exists()
    assert main(["dataset", "export", "--params", str(path)]) == 2
    assert "--histories" in capsys.readouterr().err


def test_dataset_export_histories(tmp_path):
    path = _params(tmp_path, {})
    run_sweep([Case(f"c{i}", {"x": float(i)}) for i in range(3)], synthetic_case,
              tmp_path / "sweep", scheduler="serial")
    out = tmp_path / "hist"
    assert main(["dataset", "export", "--histories", "--params", str(path), "--out", str(out)]) == 0
    loads = pd.read_parquet(out / "loads")
    assert sorted(loads["case_id"].astype(str).unique()) == ["c0", "c1", "c2"]


@pytest.mark.parametrize("argv", [["sweep", "design"], ["sweep", "run"], ["dataset", "build"],
                                  ["dataset", "export", "--histories"]])
def test_params_without_sweep_section_is_an_error(tmp_path, capsys, argv):
    """A params file with no `sweep` section would design one case of defaults: the
    commands that need the section say so (one line, exit 2, nothing written)."""
    path = tmp_path / "params.yaml"
    path.write_text("operation:\n  rpm: 100\n")
    assert main([*argv, "--params", str(path)]) == 2
    err = capsys.readouterr().err
    assert err.startswith(f"error: {path}: has no 'sweep' section") and err.count("\n") == 1
    assert sorted(p.name for p in tmp_path.iterdir()) == ["params.yaml"]


def test_params_with_an_empty_sweep_section_is_accepted(tmp_path, capsys):
    path = tmp_path / "params.yaml"
    path.write_text(f"sweep:\n  n_cases: 2\n  cases_path: {tmp_path / 'c.parquet'}\n")
    assert main(["sweep", "design", "--params", str(path)]) == 0
