"""Case-study stages: each reduced study writes its tables and figures,
the report stage writes a README citing them beside the paper's numbers, and the
proposed stage/params files agree with the config models.

The studies run on a tiny params file (coarse strings, sub-second windows): the
test checks the plumbing and the outputs' content, not the physics (the
reduced default run and the report hold those numbers).
"""

from __future__ import annotations

import json
import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
import yaml

from drillfatigue.cli import main
from drillfatigue.config.base import validate
from drillfatigue.studies.stages import SECTIONS

ROOT = Path(__file__).resolve().parents[2]

TINY = {
    "case1": {"duration_s": 0.3, "kinematics_rate_hz": 100.0},
    "case2": {"n_samples": 1, "sample_s": 1.2, "settle_s": 0.8, "rpm_ramp_s": 0.3,
              "relax_s": 0.1, "string": {"dc_segments": 9, "dp_segments": 4}},
    "case3": {"trip_s": 0.2, "ramp_s": 0.3, "window_s": 0.5,
              "string": {"dc_segments": 9, "dp_segments": 4}},
    "report": {"figure_dpi": 60},
}


def _run(script: str, *args: str) -> int:
    import importlib.util

    spec = importlib.util.spec_from_file_location(f"stage_{script}", ROOT / "pipeline" /
                                                  f"{script}.py")
    mod = importlib.util.module_from_spec(spec)
    assert spec.loader is not None
    spec.loader.exec_module(mod)
    return int(mod.main(list(args)))


@pytest.mark.slow
def test_reduced_studies_and_report(tmp_path):
    params = tmp_path / "params.yaml"
    params.write_text(yaml.safe_dump(TINY))
    d = {c: tmp_path / c for c in ("case1", "case2", "case3")}
    for c in ("case2", "case3", "case1"):
        assert _run(c, "--params", str(params), "--out", str(d[c]), "--metrics",
                    str(tmp_path / f"{c}.json")) == 0
        assert json.loads((tmp_path / f"{c}.json").read_text())["stage_wall_s"] > 0

    t2 = pd.read_csv(d["case2"] / "case2_life.csv")
    assert list(t2["profile"]) == ["profile_1", "profile_2", "profile_3"]
    assert (t2["life_windows_critical_plane"] > 0).all()
    assert (t2["life_windows_api_rp7g"] > 0).all()
    assert list(t2["paper_life_windows"]) == [10.3, 12.8, 5.9]
    assert sorted(t2["rank_ours"]) == [1, 2, 3]
    # the default tortuosity: every profile again in its plan with it, beside the plan's
    t2t = pd.read_csv(d["case2"] / "case2_life_tortuous.csv")
    assert list(t2t["profile"]) == list(t2["profile"])
    assert (t2t["life_windows_critical_plane"] > 0).all()
    assert sorted(t2t["rank_ours"]) == [1, 2, 3]
    assert sorted(p.name for p in (d["case2"] / "runs").iterdir()) == [
        "profile_1", "profile_1_tortuous", "profile_2", "profile_2_tortuous", "profile_3",
        "profile_3_tortuous"]
    s2 = json.loads((d["case2"] / "case2_summary.json").read_text())
    assert s2["tortuous"]["tortuosity"]["amplitude_deg"] == 0.5
    assert sorted(s2["tortuous"]["order_ours"]) == sorted(t2["profile"])
    m2 = json.loads((tmp_path / "case2.json").read_text())
    assert m2["life_windows_tortuous_profile_2"] == pytest.approx(
        t2t["life_windows_critical_plane"][1])
    t3 = pd.read_csv(d["case3"] / "case3_life.csv")
    assert list(t3["s_from_bit_m"]) == [8.0, 40.0, 80.0]
    assert list(t3["paper_life_h"]) == [677.0, 625.0, 191.0]  # 191 h nearest the build
    assert np.allclose(t3["life_ratio_ours_to_paper"], t3["life_h"] / t3["paper_life_h"])
    for g in ("axial_torsion", "joint_bending", "span_bending"):  # the decomposition
        assert (t3[f"life_h_{g}_only"] > 0).all()
        assert (t3[f"sigma_amplitude_MPa_{g}"] >= 0).all()
    assert set(t3["dominant_load"]) <= {"axial_torsion", "joint_bending", "span_bending",
                                        "none"}
    dec3 = pd.read_csv(d["case3"] / "case3_decomposition.csv")
    assert set(dec3["load"]) == {"all", "axial_torsion", "joint_bending", "span_bending"}
    # the default tortuosity: the case again in the tortuous hole, beside the plan's
    t3t = pd.read_csv(d["case3"] / "case3_life_tortuous.csv")
    assert list(t3t["s_from_bit_m"]) == [8.0, 40.0, 80.0]
    assert list(t3t["paper_life_h"]) == [677.0, 625.0, 191.0]
    assert (t3t["life_h"] > 0).all() and (t3["joint_bending_amplitude_Nm"] >= 0).all()
    assert (d["case3"] / "case3_decomposition_tortuous.csv").is_file()
    assert sorted(p.name for p in (d["case3"] / "runs").iterdir()) == [
        "profile_1", "profile_1_tortuous"]
    s3 = json.loads((d["case3"] / "case3_summary.json").read_text())
    assert s3["tortuous"]["tortuosity"]["amplitude_deg"] == 0.5
    assert [r["life_h"] for r in s3["tortuous"]["rows"]] == pytest.approx(list(t3t["life_h"]))
    m3 = json.loads((tmp_path / "case3.json").read_text())
    assert m3["life_h_tortuous_8m"] == pytest.approx(t3t["life_h"][0])
    assert m3["dominant_load_tortuous_80m"] == t3t["dominant_load"][2]
    t1 = pd.read_csv(d["case1"] / "case1_whirl.csv")
    assert set(t1["model"]) == {"karnopp", "tanh_exp"} and set(t1["friction"]) == {"low", "high"}
    assert (t1["rolling_ratio"].round(3) == -1.429).all()  # -63.5 / (107.95 - 63.5)

    figs = {"case1": ["case1_orbits.png", "case1_whirl_rate.png"],
            "case2": ["case2_loads.png", "case2_connection_stress.png", "case2_life.png"],
            "case3": ["case3_loads.png", "case3_life.png"]}
    for c, names in figs.items():
        for n in names:
            assert (d[c] / n).read_bytes()[:4] == b"\x89PNG", n

    timings = tmp_path / "timings.json"
    timings.write_text(json.dumps({"rows": [{"run": "x", "ours": "1 h", "paper": "38 h"}],
                                   "note": "test note"}))
    out = tmp_path / "report"
    assert _run("report", "--params", str(params), "--case1", str(d["case1"]), "--case2",
                str(d["case2"]), "--case3", str(d["case3"]), "--plan", str(tmp_path / "none"),
                "--timings", str(timings), "--out", str(out)) == 0
    text = (out / "README.md").read_text()
    images = re.findall(r"!\[[^\]]*\]\(([^)]+)\)", text)
    assert sorted(images) == sorted(n for names in figs.values() for n in names)
    for img in images:
        assert (out / img).is_file()
    # our lives stand next to the paper's, and the wall times next to 38 h / 2 h / 47-18 min
    for r in t2.itertuples():
        assert f"| {r.profile} |" in text
    assert "span_bending only" in text and "ours / paper" in text
    # case 3's lives table: location, paper, plan hole, tortuous hole, the load that sets each
    assert ("| location: behind the bit, m | paper, h | plan: joint, m | plan hole, h | "
            "plan: load that sets it | tortuous: joint, m | tortuous hole, h | "
            "tortuous: load that sets it |") in text
    assert "sine, amplitude 0.5° over 30 m" in text
    assert "Order in the tortuous holes (longest life first)" in text
    assert "| life, windows (tortuous, critical plane) | life, windows (plan) |" in text
    for paper in ("10.3", "12.8", "5.9", "191", "625", "677", "38 h", "2 h", "47", "test note"):
        assert paper in text, paper


@pytest.mark.slow
def test_case3_without_tortuosity_is_the_plan_run_alone(tmp_path):
    """``case3.tortuosity: null``: one run (the plan), whose tables, decomposition and
    loads are byte for byte those of the plan half of a run with a tortuosity: the
    second hole changes nothing of the first."""
    outs = {}
    for name, tort in (("plan_only", None),
                       ("both", {"model": "sine", "amplitude_deg": 1.0, "period_m": 30.0})):
        params = tmp_path / f"{name}.yaml"
        params.write_text(yaml.safe_dump({"case3": {**TINY["case3"], "tortuosity": tort}}))
        outs[name] = tmp_path / name
        assert _run("case3", "--params", str(params), "--out", str(outs[name]),
                    "--metrics", str(tmp_path / f"{name}.json")) == 0
    one, two = outs["plan_only"], outs["both"]
    assert [p.name for p in (one / "runs").iterdir()] == ["profile_1"]
    assert not (one / "case3_life_tortuous.csv").exists()
    summary = json.loads((one / "case3_summary.json").read_text())
    assert "tortuous" not in summary and "tortuosity" not in summary["config"]
    assert not any("tortuous" in k for k in json.loads((tmp_path / "plan_only.json")
                                                       .read_text()))
    for f in ("case3_life.csv", "case3_decomposition.csv", "runs/profile_1/loads.parquet"):
        assert (one / f).read_bytes() == (two / f).read_bytes(), f
    assert (two / "case3_life_tortuous.csv").read_bytes() != (one / "case3_life.csv").read_bytes()


def test_study_cli_bad_section_exit_2(tmp_path, capsys):
    params = tmp_path / "params.yaml"
    params.write_text(yaml.safe_dump({"case2": {"n_samples": 0}}))
    assert main(["study", "case2", "--params", str(params), "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err
    assert err.startswith("error: case2.n_samples:") and err.count("\n") == 1
    assert not (tmp_path / "o").exists()
    assert main(["study", "case9", "--params", str(params)]) == 2


def test_project_params_and_stages_match_the_models():
    params = yaml.safe_load((ROOT / "params.yaml").read_text())
    for name, model in SECTIONS.items():
        validate(model, params.get(name, {}), name)  # every project value is valid
    defaults = {n: m().model_dump(mode="json") for n, m in SECTIONS.items()}
    # the reduced case-study defaults documented in the report are the models' defaults
    for name in ("case1", "case2", "case3", "report"):
        for key, value in params[name].items():
            want = defaults[name][key]
            got = list(value) if isinstance(value, list | tuple) else value
            want = list(want) if isinstance(want, list | tuple) else want
            if isinstance(got, dict):
                got = {**want, **got}
            assert got == want, f"{name}.{key}: params file {value!r} != model default {want!r}"
    stages = yaml.safe_load((ROOT / "dvc.yaml").read_text())["stages"]
    assert {"case1", "case2", "case3", "plan", "report"} <= set(stages)
    outs = {o if isinstance(o, str) else next(iter(o)) for st in stages.values()
            for o in st.get("outs", [])}
    for name, st in stages.items():
        for dep in st["deps"]:
            assert dep in outs or (ROOT / dep).exists(), f"{name}: {dep}"
        if name in SECTIONS:
            assert name in st["params"]
    assert params["plan"]["surrogate_dir"] in outs  # the plan ranks with the trained model


@pytest.mark.skipif(not Path(sys.executable).with_name("dvc").exists(),
                    reason="dvc not installed in this environment")
def test_project_dvc_yaml_is_valid_to_dvc():
    """DVC itself accepts the whole dvc.yaml (schema, output overlaps, plots):
    `dvc dag` loads every stage and fails on an invalid pipeline."""
    r = subprocess.run([str(Path(sys.executable).with_name("dvc")), "dag", "--md"], cwd=ROOT,
                       capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stderr
    for stage in ("wells", "simulate", "train", "evaluate", "case2", "plan", "report"):
        assert stage in r.stdout


def test_study_and_report_refuse_a_folder_with_foreign_files(tmp_path, capsys):
    """`drillfatigue study` and the report stage with an --out folder holding a user's
    file: exit 2, one line, before any simulation; the file survives. The report
    rewritten into its own folder keeps a user's file beside it."""
    params = tmp_path / "params.yaml"
    params.write_text(yaml.safe_dump(TINY))
    mine = tmp_path / "mine"
    mine.mkdir()
    (mine / "case2_life.csv").write_text("my numbers\n")
    assert main(["study", "case2", "--params", str(params), "--out", str(mine)]) == 2
    err = capsys.readouterr().err
    assert err.startswith("error: --out: ") and "did not write" in err and err.count("\n") == 1
    assert [p.name for p in mine.iterdir()] == ["case2_life.csv"]
    assert _run("report", "--params", str(params), "--case1", str(tmp_path / "n1"),
                "--case2", str(tmp_path / "n2"), "--case3", str(tmp_path / "n3"),
                "--out", str(mine)) == 2
    assert "did not write" in capsys.readouterr().err
    assert (mine / "case2_life.csv").read_text() == "my numbers\n"
    out = tmp_path / "report"
    args = ["--params", str(params), "--case1", str(tmp_path / "n1"), "--case2",
            str(tmp_path / "n2"), "--case3", str(tmp_path / "n3"), "--out", str(out)]
    assert _run("report", *args) == 0
    (out / "notes.md").write_text("mine")
    assert _run("report", *args) == 0
    assert (out / "notes.md").read_text() == "mine"


def test_committed_report_marker_lists_the_committed_report() -> None:
    """data/report is git-tracked (a DVC out without cache): its ownership marker is
    committed with it, listing exactly the report's files, so the report stage accepts
    the folder on `dvc repro`."""
    folder = ROOT / "data" / "report"
    marker = json.loads((folder / ".drillfatigue.json").read_text())
    assert marker["kind"] == "report"
    assert marker["files"] == sorted(p.name for p in folder.iterdir()
                                     if not p.name.startswith("."))
