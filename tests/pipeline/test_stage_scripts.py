"""Every DVC stage script is its stage function plus a two-line ``main`` through the
shared :func:`drillfatigue.stage.stage_main`, and a bad params file is one line naming
the field, exit code 2 and nothing written."""

from __future__ import annotations

import ast
import importlib.util
import re
from pathlib import Path
from types import ModuleType

import pytest
import yaml

ROOT = Path(__file__).resolve().parents[2]

#: Modules whose ``stage_main`` a script may call: the shared one, and the case
#: studies' one, which passes their options and loader to the shared one.
SHARED_MAINS = {"drillfatigue.stage", "drillfatigue.studies.stages"}


def _dvc_scripts() -> set[str]:
    """The ``pipeline/*.py`` scripts that a ``dvc.yaml`` stage runs."""
    stages = yaml.safe_load((ROOT / "dvc.yaml").read_text(encoding="utf-8"))["stages"]
    return {m for stage in stages.values()
            for m in re.findall(r"pipeline/(\w+\.py)", " ".join(stage["cmd"].split()))}


def _module(script: str) -> ModuleType:
    spec = importlib.util.spec_from_file_location(f"stage_script_{script}",
                                                  ROOT / "pipeline" / f"{script}.py")
    assert spec is not None and spec.loader is not None
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def test_every_pipeline_script_but_the_timing_one_is_a_dvc_stage() -> None:
    # paper_scale.py measures the paper-scale run times by hand (no params file,
    # longer than the pipeline's budget): the one script that is not a stage
    scripts = {p.name for p in (ROOT / "pipeline").glob("*.py")}
    assert scripts - _dvc_scripts() == {"paper_scale.py"}
    assert _dvc_scripts() <= scripts


@pytest.mark.parametrize("script", sorted(_dvc_scripts()))
def test_stage_script_main_is_the_shared_one(script: str) -> None:
    tree = ast.parse((ROOT / "pipeline" / script).read_text(encoding="utf-8"))
    mains = [n for n in tree.body if isinstance(n, ast.FunctionDef) and n.name == "main"]
    assert len(mains) == 1, f"{script}: one top-level main"
    body = mains[0].body
    assert len(body) == 1 and isinstance(body[0], ast.Return), \
        f"{script}: main is one return statement"
    call = body[0].value
    assert isinstance(call, ast.Call) and isinstance(call.func, ast.Name) \
        and call.func.id == "stage_main", f"{script}: main returns stage_main(...)"
    origins = {n.module for n in ast.walk(tree) if isinstance(n, ast.ImportFrom)
               and any((a.asname or a.name) == "stage_main" for a in n.names)}
    assert len(origins) == 1 and origins <= SHARED_MAINS, f"{script}: stage_main from {origins}"
    names = {n.id for n in ast.walk(tree) if isinstance(n, ast.Name)}
    names |= {n.attr for n in ast.walk(tree) if isinstance(n, ast.Attribute)}
    assert "ArgumentParser" not in names, f"{script}: parses its options through the shared main"
    handlers = [h for n in ast.walk(tree) if isinstance(n, ast.Try) for h in n.handlers]
    assert not handlers, f"{script}: errors are handled by the shared main"


def test_the_case_studies_main_goes_through_the_shared_one() -> None:
    tree = ast.parse((ROOT / "src" / "drillfatigue" / "studies" / "stages.py")
                     .read_text(encoding="utf-8"))
    fn = next(n for n in tree.body if isinstance(n, ast.FunctionDef) and n.name == "stage_main")
    calls = {c.func.id for c in ast.walk(fn) if isinstance(c, ast.Call)
             and isinstance(c.func, ast.Name)}
    assert "shared_stage_main" in calls
    assert any(isinstance(n, ast.ImportFrom) and n.module == "drillfatigue.stage"
               and any(a.name == "stage_main" and a.asname == "shared_stage_main"
                       for a in n.names) for n in tree.body)


BAD = [
    # script, params file, the error line's start
    ("wells", {"well": {"bogus": 1}}, "error: well.bogus: unknown key"),
    ("simulate", {"sweep": {"n_cases": -3}}, "error: sweep.n_cases: "),
    ("case2", {"case2": {"n_samples": 0}}, "error: case2.n_samples: "),
    ("report", {"report": {"figure_dpi": -1}}, "error: report.figure_dpi: "),
]


@pytest.mark.parametrize(("script", "params", "start"), BAD, ids=[b[0] for b in BAD])
def test_bad_params_one_line_exit_2_nothing_written(
        script: str, params: dict, start: str, tmp_path: Path,
        capsys: pytest.CaptureFixture[str]) -> None:
    path = tmp_path / "params.yaml"
    path.write_text(yaml.safe_dump(params), encoding="utf-8")
    out = tmp_path / "out"
    args = ["--params", str(path), "--out", str(out)]
    if script in ("simulate", "case2"):
        args += ["--metrics", str(tmp_path / "metrics.json")]
    assert _module(script).main(args) == 2
    captured = capsys.readouterr()
    assert captured.err.startswith(start) and captured.err.count("\n") == 1, captured.err
    assert captured.out == ""
    assert sorted(p.name for p in tmp_path.iterdir()) == ["params.yaml"]


@pytest.mark.parametrize("script", ["design", "dataset", "heldout", "train", "evaluate",
                                    "research_dataset"])
def test_a_params_file_that_is_not_yaml_is_one_line(
        script: str, tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    path = tmp_path / "params.yaml"
    path.write_text("sweep: [1, 2\n", encoding="utf-8")
    assert _module(script).main(["--params", str(path)]) == 2
    err = capsys.readouterr().err
    assert err.startswith(f"error: {path}: YAML syntax error") and err.count("\n") == 1, err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["params.yaml"]
