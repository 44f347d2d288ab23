"""The pipeline under DVC: ``dvc repro`` in a temporary git+DVC repo, then a no-op rerun.

Uses the stages ``wells`` → ``design`` → ``simulate`` → ``fatigue`` →
``dataset`` → ``replicates`` → ``heldout`` → ``heldout_draws`` → ``train`` →
``evaluate`` of the project's ``dvc.yaml`` with the repository's pipeline
scripts, the installed package and a tiny params file (6 cases and 2 held-out
ones with 2 draws each, 16 segments, 0.3 s window, a 5-epoch ensemble).
"""

from __future__ import annotations

import json
import shutil
import subprocess
import sys
import time
from pathlib import Path

import pandas as pd
import pytest
import yaml

from drillfatigue.config import Params

ROOT = Path(__file__).parents[2]
DVC = Path(sys.executable).with_name("dvc")

TINY = {
    "operation": {"duration_s": 0.3, "bit_md_m": 500.0, "rop_m_per_s": 0.005, "rpm": 60.0},
    "string": {"components": [
        {"type": "collar", "name": "DC", "od_m": 0.17145, "id_m": 0.0714, "length_m": 60.0,
         "n_segments": 6},
        {"type": "drill_pipe", "name": "DP", "od_m": 0.127, "id_m": 0.1086, "length_m": 440.0,
         "tool_joint_od_m": 0.1683, "tool_joint_id_m": 0.0826,
         "tool_joint_length_fraction": 0.05, "n_segments": 10}]},
    "recording": {"joints": [1, 2, 4, 6, 8, 10, 12, 14], "loads_rate_hz": 100.0},
    "fatigue": {"plots": False},
    "surrogate": {"features": ["operation.rpm", "friction.mu_dynamic", "md_m", "s_from_bit_m",
                               "local_dls_deg_per_30m"],
                  "criterion": "uniaxial",
                  "hidden_layers": [16], "max_epochs": 5, "patience": 5, "n_threads": 1,
                  "gp_max_rows": 60, "hgb_max_iter": 20,
                  "heldout_path": "data/heldout/dataset/damage.parquet"},
    "replicates": {"n_cases": 2, "n_replicates": 2},
    "heldout": {"n_cases": 2, "seed": 6, "draws": 2},
    "sweep": {"method": "lhs", "n_cases": 6, "seed": 5, "scheduler": "serial",
              "fatigue_criteria": ["uniaxial"],
              "variables": {"operation.rpm": {"low": 40.0, "high": 120.0},
                            "friction.mu_dynamic": {"low": 0.15, "high": 0.3}}},
}


STAGES = ("wells", "design", "simulate", "fatigue", "dataset", "replicates", "heldout",
          "heldout_draws", "train", "evaluate")


def _run(args: list[str], cwd: Path) -> subprocess.CompletedProcess:
    return subprocess.run(args, cwd=cwd, capture_output=True, text=True, timeout=300)


def _stages() -> dict:
    """The chain's stages of the project's own dvc.yaml, runnable in the temporary repo."""
    spec = yaml.safe_load((ROOT / "dvc.yaml").read_text())
    names = STAGES
    stages = {name: spec["stages"][name] for name in names}
    for stage in stages.values():
        assert stage["cmd"].startswith("python ")
        stage["cmd"] = f"{sys.executable} " + stage["cmd"][len("python "):]
        # the temporary repo holds the scripts, not the package sources or the well inputs
        stage["deps"] = [d for d in stage["deps"] if str(d).startswith(("pipeline/", "data/"))]
    return {"stages": stages}


@pytest.mark.slow  # several dvc invocations (~3 s start each), six tiny cases, a 5-epoch ensemble
@pytest.mark.skipif(not DVC.exists(), reason="dvc not installed in this environment")
def test_dvc_repro_then_noop(tmp_path):
    repo = tmp_path / "repo"
    (repo / "pipeline").mkdir(parents=True)
    for name in STAGES:
        shutil.copy(ROOT / "pipeline" / f"{name}.py", repo / "pipeline" / f"{name}.py")
    shutil.copytree(ROOT / "data" / "wells" / "inputs", repo / "data" / "wells" / "inputs")
    # DVC needs every listed key present: write the full validated params
    # the project's well section: the wells stage's outs name its profiles
    tiny = dict(TINY, well=yaml.safe_load((ROOT / "params.yaml").read_text())["well"])
    (repo / "params.yaml").write_text(yaml.safe_dump(Params.model_validate(tiny).model_dump(mode="json")))
    (repo / "dvc.yaml").write_text(yaml.safe_dump(_stages(), sort_keys=False))
    for cmd in (["git", "init", "-q"], [str(DVC), "init", "-q"],
                [str(DVC), "config", "core.analytics", "false"]):
        assert _run(cmd, repo).returncode == 0
    first = _run([str(DVC), "repro"], repo)
    assert first.returncode == 0, first.stdout + first.stderr
    df = pd.read_parquet(repo / "data" / "dataset" / "damage.parquet")
    assert df["case_id"].nunique() == 6
    assert (repo / "data" / "dataset" / "README.md").is_file()
    assert (repo / "metrics" / "simulate.json").is_file()
    assert (repo / "data" / "wells" / "profile_2" / "survey.csv").is_file()
    assert (repo / "data" / "surrogate" / "model" / "model.ts").is_file()
    m = json.loads((repo / "data" / "surrogate" / "metrics.json").read_text())
    assert {"ensemble", "gp", "hgb"} <= set(m) and m["n_test_cases"] >= 1
    spread = json.loads((repo / "data" / "replicates" / "spread.json").read_text())
    assert spread["n_cases"] == 2 and spread["criterion"] == "uniaxial"
    assert m["noise_floor"]["sigma_log10"] == spread["sigma_log10"]
    draws = pd.read_parquet(repo / "data" / "heldout" / "draws" / "spread.parquet")
    assert (draws.groupby("base_case_id")["replicate"].nunique() == 2).all()
    assert m["deciding_draws"]["n_cases"] == draws["base_case_id"].nunique() >= 1

    t0 = time.perf_counter()
    second = _run([str(DVC), "repro"], repo)
    elapsed = time.perf_counter() - t0
    assert second.returncode == 0, second.stderr
    assert "Running stage" not in second.stdout  # nothing re-ran
    # goal 10 s; DVC start-up alone is a few s on a busy 2-core box
    assert elapsed < 30.0, f"no-op rerun took {elapsed:.1f} s"

    shown = _run([str(DVC), "metrics", "show", "--json"], repo)
    assert shown.returncode == 0 and "n_cases_in_dataset" in shown.stdout

    # an experiment on the surrogate's settings re-runs only the stages that read them,
    # and `dvc exp show` lists its metrics and the setting
    for cmd in (["git", "add", "-A"], ["git", "-c", "user.name=t", "-c", "user.email=t@t",
                                        "commit", "-qm", "baseline"]):
        assert _run(cmd, repo).returncode == 0
    exp = _run([str(DVC), "exp", "run", "-S", "surrogate.max_epochs=4"], repo)
    assert exp.returncode == 0, exp.stdout + exp.stderr
    assert "Running stage 'train'" in exp.stdout and "Running stage 'simulate'" not in exp.stdout
    assert json.loads((repo / "data" / "surrogate" / "model" / "metadata.json").read_text())[
        "config"]["max_epochs"] == 4
    table = _run([str(DVC), "exp", "show", "--json"], repo)
    assert table.returncode == 0 and "n_cases_in_dataset" in table.stdout, table.stdout[-2000:]
    assert "max_epochs" in table.stdout
