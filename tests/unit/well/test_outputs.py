"""The ``wells`` stage script on a tiny params file."""

from __future__ import annotations

import importlib.util
import json
from pathlib import Path

import pyarrow.parquet as pq
import pytest

ROOT = Path(__file__).resolve().parents[3]


def _stage():
    spec = importlib.util.spec_from_file_location("wells_stage", ROOT / "pipeline" / "wells.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


PARAMS = """
well:
  family: {tvd_end_m: 300.0, displacement_m: 250.0}
  profiles:
    a: {kind: family_member, member: 1, kop_m: 100.0}
    b: {kind: family_member, member: 3, kop_m: 100.0, tangent_length_m: 30.0}
    v: {kind: vertical, td_m: 50.0}
  min_clearance_m: 0.05
"""


def test_stage_writes_every_profile(tmp_path: Path) -> None:
    (tmp_path / "params.yaml").write_text(PARAMS)
    out = tmp_path / "wells"
    assert _stage().main(["--params", str(tmp_path / "params.yaml"), "--out", str(out)]) == 0
    summary = json.loads((out / "summary.json").read_text())
    assert set(summary["profiles"]) == {"a", "b", "v"}
    assert summary["family_end_spread_m"] < 0.1
    for name in ("a", "b", "v"):
        assert (out / name / "survey.csv").is_file()
        assert (out / name / "profile.png").is_file()
        table = pq.read_table(out / name / "cylinders.parquet")
        assert table.num_rows == summary["profiles"][name]["n_cylinders"]
        assert "radius_m" in table.column_names
    assert summary["profiles"]["a"]["max_dls_deg_per_30m"] == pytest.approx(
        30.0 / 200.0 * 180.0 / 3.141592653589793, rel=1e-9)


def test_stage_writes_the_tortuous_hole_and_its_report(tmp_path: Path) -> None:
    """With well.tortuosity the survey file is the tortuous hole's (the plan's stations
    plus 32 per period below the start) and the summary reports the tortuosity;
    without it the summary has no such entry."""
    (tmp_path / "params.yaml").write_text(
        PARAMS + "  tortuosity: {model: random, amplitude_deg: 0.5, period_m: 10.0, "
                 "md_start_m: 20.0, seed: 5}\n")
    out = tmp_path / "wells"
    assert _stage().main(["--params", str(tmp_path / "params.yaml"), "--out", str(out)]) == 0
    summary = json.loads((out / "summary.json").read_text())["profiles"]
    rep = summary["v"]["tortuosity"]
    assert (rep["model"], rep["seed"], rep["amplitude_deg"]) == ("random", 5, 0.5)
    assert rep["plan"]["max_dls_deg_per_30m"] == 0.0
    assert 0.0 < rep["tortuous"]["max_dls_deg_per_30m"] <= 2 * 0.5 / 10.0 * 30.0 + 1e-9
    md = [float(r.split(",")[0]) for r in (out / "v" / "survey.csv").read_text().split()[1:]]
    # the plan's 0, 25 and 50 m, and every 10/32 m from 20 m (25 m is one of them)
    assert len(md) == rep["tortuous"]["n_stations"] == 3 + 3 * 32 - 1
    (tmp_path / "params.yaml").write_text(PARAMS)
    assert _stage().main(["--params", str(tmp_path / "params.yaml"), "--out", str(out)]) == 0
    summary = json.loads((out / "summary.json").read_text())["profiles"]
    assert all("tortuosity" not in s for s in summary.values())


def test_stage_bad_params_writes_nothing(tmp_path: Path, capsys) -> None:
    (tmp_path / "params.yaml").write_text("well:\n  profile: zz\n")
    out = tmp_path / "wells"
    assert _stage().main(["--params", str(tmp_path / "params.yaml"), "--out", str(out)]) == 2
    assert capsys.readouterr().err.startswith("error: well.profile: ")
    assert not out.exists()


def test_stage_refuses_a_profile_folder_with_foreign_files(tmp_path: Path, capsys) -> None:
    """A user's file in the folder a profile is written to: exit 2, one line, nothing of
    any profile written, the file untouched; a rerun keeps a file added beside its own."""
    (tmp_path / "params.yaml").write_text(PARAMS)
    out = tmp_path / "wells"
    (out / "b").mkdir(parents=True)
    (out / "b" / "survey.csv").write_text("my survey\n")
    argv = ["--params", str(tmp_path / "params.yaml"), "--out", str(out)]
    assert _stage().main(argv) == 2
    err = capsys.readouterr().err
    assert err.startswith(f"error: {out / 'b'}: ") and "did not write" in err
    assert err.count("\n") == 1
    assert sorted(p.name for p in out.iterdir()) == ["b"]
    assert (out / "b" / "survey.csv").read_text() == "my survey\n"
    (out / "b" / "survey.csv").unlink()
    assert _stage().main(argv) == 0
    (out / "a" / "notes.txt").write_text("mine")
    assert _stage().main(argv) == 0
    assert (out / "a" / "notes.txt").read_text() == "mine"
