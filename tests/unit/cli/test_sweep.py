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


def _files(root):
    return {p.relative_to(root).as_posix(): p.read_bytes() for p in sorted(root.rglob("*"))
            if p.is_file()}


def test_sweep_design_keeps_a_users_files_beside_the_table(tmp_path, capsys):
    """The design writes coverage.csv and design.json beside the table the user names:
    files of those names it did not write are refused before anything is written, and a
    folder given as --out is a one-line error, not a traceback."""
    path = _params(tmp_path, {"operation.rpm": {"low": 60, "high": 120}})
    mine = tmp_path / "mine"
    mine.mkdir()
    for name, text in (("coverage.csv", "my notes\n"), ("design.json", '{"mine": 1}\n')):
        (mine / name).write_text(text)
        before = _files(tmp_path)
        assert main(["sweep", "design", "--params", str(path), "--out",
                     str(mine / "plan.parquet")]) == 2
        err = capsys.readouterr().err
        assert err.startswith("error: --out:") and name in err and err.count("\n") == 1
        assert _files(tmp_path) == before
        (mine / name).unlink()
    (mine / "notes.parquet").mkdir()
    assert main(["sweep", "design", "--params", str(path), "--out",
                 str(mine / "notes.parquet")]) == 2
    assert "is a folder" in capsys.readouterr().err
    # its own files it replaces: a second design over the first
    assert main(["sweep", "design", "--params", str(path), "--out", str(mine / "plan.parquet")]) == 0
    assert main(["sweep", "design", "--params", str(path), "--out", str(mine / "plan.parquet")]) == 0


def test_sweep_run_refuses_a_foreign_dataset_folder_before_any_case(tmp_path, capsys):
    """A foreign file in the dataset folder (the last stage's) stops `sweep run` before the
    design is written or a case simulated."""
    path = _params(tmp_path, {"operation.rpm": {"low": 60, "high": 120}})
    data = yaml.safe_load(path.read_text())
    data["sweep"]["dataset_dir"] = str(tmp_path / "dataset")
    data["sweep"]["fatigue_dir"] = str(tmp_path / "fatigue")
    path.write_text(yaml.safe_dump(data))
    (tmp_path / "dataset").mkdir()
    (tmp_path / "dataset" / "notes.txt").write_text("mine")
    before = _files(tmp_path)
    assert main(["sweep", "run", "--params", str(path), "--no-progress"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("error: sweep.dataset_dir:") and err.count("\n") == 1
    assert _files(tmp_path) == before
    assert sorted(p.name for p in tmp_path.iterdir()) == ["dataset", "params.yaml"]


def test_sweep_design_out_elsewhere_writes_only_there(tmp_path, monkeypatch, capsys):
    """`sweep design --out elsewhere` used to create the configured adaptive cache
    (data/design/adaptive/.drillfatigue.json) in the working directory."""
    work = tmp_path / "work"
    work.mkdir()
    (work / "params.yaml").write_text(yaml.safe_dump({"sweep": {
        "n_cases": 4, "variables": {"operation.rpm": {"low": 60, "high": 120}},
        "adaptive": {"cache_dir": "data/design/adaptive"}}}))
    monkeypatch.chdir(work)
    out = tmp_path / "elsewhere" / "cases.parquet"
    assert main(["sweep", "design", "--out", str(out)]) == 0, capsys.readouterr().err
    assert sorted(p.name for p in work.iterdir()) == ["params.yaml"]
    assert sorted(p.name for p in out.parent.iterdir()) == ["cases.parquet", "coverage.csv",
                                                             "design.json"]
    # the configured table still claims the configured cache (the pipeline's output)
    assert main(["sweep", "design"]) == 0, capsys.readouterr().err
    assert (work / "data" / "design" / "adaptive").is_dir()
