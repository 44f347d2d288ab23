"""Dataset assembly from (synthetic) per-case outputs: schema, units in names, card, export."""

from __future__ import annotations

import json
import math

import numpy as np
import pandas as pd
import yaml
import pytest

from drillfatigue.errors import InputError
from drillfatigue.sweep.cases import fatigue_tasks
from drillfatigue.sweep.dataset import (
    DYNAMICS_COLUMNS,
    export_histories,
    summary_dynamics,
    unit_of,
    write_dataset,
)
from drillfatigue.sweep.runner import Case, run_sweep
from testkit.synthetic_sweep import N_JOINT, synthetic_case, synthetic_fatigue

DESIGN = {"method": "sobol", "seed": 1, "n_cases": 4, "window_s": 10.0,
          "variables": {"operation.rpm": {"low": 60.0, "high": 180.0},
                        "well.profile": {"choices": ["p1", "p2"]}}}


@pytest.fixture(scope="module")
def sweep(tmp_path_factory):
    root = tmp_path_factory.mktemp("ds")
    rows = []
    for i, (rpm, prof) in enumerate([(60.0, "p1"), (90.0, "p2"), (120.0, "p1"), (150.0, "p2")]):
        case = {"operation": {"rpm": rpm}, "well": {"profile": prof}}
        rows.append({"case_id": f"c{i}", "design_index": i, "operation.rpm": rpm,
                     "well.profile": prof, "case_json": json.dumps(case)})
    cases = pd.DataFrame(rows)
    run_sweep([Case(r["case_id"], json.loads(r["case_json"])) for r in rows], synthetic_case,
              root / "sweep", scheduler="serial")
    # case c3 "fails" fatigue (no damage.parquet): it must be missing from the dataset
    tasks = [Case(cid, inputs) for cid, inputs in fatigue_tasks(
        ["c0", "c1", "c2"], root / "sweep", {"criteria": "all"})]
    run_sweep(tasks, synthetic_fatigue, root / "fatigue", scheduler="serial")
    metrics = write_dataset(cases, root / "sweep", root / "fatigue", root / "dataset",
                            design=DESIGN, base_case={"operation": {"rpm": 120.0}})
    return root, cases, metrics


def test_damage_table_schema(sweep):
    root, cases, metrics = sweep
    df = pd.read_parquet(root / "dataset" / "damage.parquet")
    # one row per (case, component location): 3 cases x N_JOINT joints x 2 locations
    assert len(df) == 3 * N_JOINT * 2 == metrics["n_rows"]
    assert sorted(df["case_id"].unique()) == ["c0", "c1", "c2"]
    assert not df.duplicated(["case_id", "joint", "location"]).any()
    constants = json.loads((root / "dataset" / "constants.json").read_text())
    for col in ["operation.rpm", "well.profile", "md_m", "s_from_bit_m", "component",
                "location", *DYNAMICS_COLUMNS, "damage_rate_per_h_uniaxial",
                "damage_rate_per_h_matake", "damage_rate_per_h_api_rp7g", "life_h_matake"]:
        # a column with one value in every row is in constants.json instead
        assert (col in df.columns) != (col in constants), col
    # inputs copied from the design table
    merged = df.merge(cases, on="case_id", suffixes=("", "_design"))
    assert (merged["operation.rpm"] == merged["operation.rpm_design"]).all()
    # per-criterion values equal the long table's
    long = pd.read_parquet(root / "fatigue" / "c1" / "damage.parquet")
    want = long[(long.joint == 2) & (long.location == "body") & (long.criterion == "api_rp7g")]
    got = df[(df.case_id == "c1") & (df.joint == 2) & (df.location == "body")]
    assert got["damage_rate_per_h_api_rp7g"].item() == pytest.approx(want["damage_rate_per_h"].item())
    # torque statistics from channels.parquet when the summary lacks them
    torque = pd.read_parquet(root / "sweep" / "c1" / "channels.parquet")["surface_torque_Nm"]
    assert got["rms_surface_torque_Nm"].iloc[0] == pytest.approx(np.sqrt(np.mean(torque**2)))
    assert got["peak_surface_torque_Nm"].iloc[0] == pytest.approx(torque.abs().max())
    # api_rp7g has no critical plane: its all-NaN column is dropped
    assert "critical_angle_deg_api_rp7g" not in df.columns


def test_units_in_names():
    assert unit_of("damage_rate_per_h_matake") == "1/h"
    assert unit_of("life_h_api_rp7g") == "h"
    assert unit_of("critical_angle_deg_findley") == "deg"
    assert unit_of("operation.rop_m_per_s") == "m/s"
    assert unit_of("operation.rpm") == "rev/min"
    assert unit_of("rms_surface_torque_Nm") == "N·m"
    assert unit_of("max_contact_force_N") == "N"
    assert unit_of("s_from_bit_m") == "m"
    assert unit_of("well.dls_deg_per_30m") == "deg/30 m"
    assert unit_of("stick_slip_severity") == "1"
    assert unit_of("friction.mu_dynamic") == "1"
    assert unit_of("well.profile") == "-"
    # compound units, each once given a wrong unit by its last token
    assert unit_of("operation.mud_damping_axial_N_s_per_m2") == "N·s/m²"
    assert unit_of("operation.mud_damping_torsional_N_m_s_per_m") == "N·m·s/m"
    assert unit_of("bit.omega_threshold_rad_s") == "rad/s"
    assert unit_of("bit.rop_c1_m_per_N_sqrt_s") == "m/(N·√s)"
    assert unit_of("bit.tob_b1_s_per_rad") == "s/rad"
    assert unit_of("bit.tob_b3_s2_per_rad2") == "s²/rad²"
    assert unit_of("achieved_on_bottom_fraction") == "1"


def test_card_and_metrics(sweep):
    root, _, metrics = sweep
    card = (root / "dataset" / "README.md").read_text()
    df = pd.read_parquet(root / "dataset" / "damage.parquet")
    for heading in ("## Purpose", "## Licence", "## How to regenerate", "## Sampling design",
                    "## Rows are correlated: split by case", "## Column roles", "## Censoring",
                    "## Schema", "## Constant columns", "## Software versions", "## Loading",
                    "torch.utils.data.TensorDataset"):
        assert heading in card
    # the card's loading snippets are valid Python; the pandas one splits this dataset by case
    blocks = [b.split("\n", 1)[1] for b in card.split("```python")[1:]]
    blocks = [b.split("```", 1)[0] for b in blocks]
    assert len(blocks) == 3 and "from datasets import load_dataset" in blocks[1]
    for code in blocks:
        compile(code, "card", "exec")
    scope: dict = {}
    exec(blocks[0], scope)
    train, test = scope["train"], scope["test"]
    assert len(train) + len(test) == len(df) and len(test) > 0 and len(train) > 0
    assert not set(train["case_id"]) & set(test["case_id"])
    assert set(scope["inputs"]) <= set(df.columns) and np.isfinite(scope["y_train"]).all()
    for col in df.columns:
        assert f"| `{col}` |" in card
    assert "| `operation.rpm` | 60.0 ... 180.0 | linear | float |" in card
    assert "cases designed: 4" in card and "cases in the dataset: 3" in card
    assert metrics["n_cases_designed"] == 4 and metrics["n_cases_in_dataset"] == 3
    assert json.loads((root / "dataset" / "metrics.json").read_text()) == metrics
    hist = pd.read_csv(root / "dataset" / "plots" / "damage_rate_hist.csv")
    assert set(hist["criterion"]) == {"uniaxial", "matake", "api_rp7g"}
    assert hist.groupby("criterion")["count"].sum().eq(len(df)).all()


def test_missing_dynamics_are_nan(tmp_path):
    (tmp_path / "summary.json").write_text(json.dumps({"status": "complete", "duration_s": 5}))
    dyn = summary_dynamics(tmp_path)
    assert dyn["duration_s"] == 5.0
    assert math.isnan(dyn["max_contact_force_N"]) and math.isnan(dyn["rms_surface_torque_Nm"])
    assert dyn["whirl_class"] is None


def test_export_histories_partitioned_by_case(sweep, tmp_path):
    root, _, _ = sweep
    out = export_histories(root / "sweep", tmp_path / "hist")
    loads = pd.read_parquet(out / "loads")
    assert sorted(loads["case_id"].astype(str).unique()) == ["c0", "c1", "c2", "c3"]
    one = pd.read_parquet(root / "sweep" / "c2" / "loads.parquet")
    part = loads[loads["case_id"].astype(str) == "c2"].drop(columns="case_id").reset_index(drop=True)
    pd.testing.assert_frame_equal(part, one)
    assert (out / "channels" / "case_id=c0" / "part-0.parquet").is_file()
    export_histories(root / "sweep", out, case_ids=["c1"])  # replaces the previous export
    assert sorted(p.name for p in (out / "loads").iterdir()) == ["case_id=c1"]
    with pytest.raises(InputError):
        export_histories(tmp_path / "nothing", tmp_path / "h2")


def test_export_histories_keeps_a_users_files(sweep, tmp_path, capsys):
    """`dataset export --histories --out DIR`: an existing DIR with a user's file is
    refused (exit 2, one line) and left as it was; in a folder of an earlier export the
    user's file beside the export survives a rerun."""
    from drillfatigue.cli import main

    root, _, _ = sweep
    mine = tmp_path / "mine"
    mine.mkdir()
    (mine / "notes.txt").write_text("field notes")
    assert main(["dataset", "export", "--histories", "--sweep-dir", str(root / "sweep"),
                 "--out", str(mine)]) == 2
    err = capsys.readouterr().err
    assert err.startswith("error: --out: ") and err.count("\n") == 1
    assert [p.name for p in mine.iterdir()] == ["notes.txt"]
    out = tmp_path / "hist"
    assert main(["dataset", "export", "--histories", "--sweep-dir", str(root / "sweep"),
                 "--out", str(out)]) == 0
    (out / "notes.txt").write_text("kept")
    (out / "loads" / "case_id=c0" / "extra.txt").write_text("kept too")
    assert main(["dataset", "export", "--histories", "--sweep-dir", str(root / "sweep"),
                 "--out", str(out)]) == 0
    assert (out / "notes.txt").read_text() == "kept"
    assert (out / "loads" / "case_id=c0" / "extra.txt").read_text() == "kept too"
    assert len(pd.read_parquet(out / "loads" / "case_id=c1")) > 0
    # a file where the folder should be
    (tmp_path / "afile").write_text("x")
    assert main(["dataset", "export", "--histories", "--sweep-dir", str(root / "sweep"),
                 "--out", str(tmp_path / "afile")]) == 2
    assert "is a file" in capsys.readouterr().err


def test_dataset_folder_with_foreign_files_is_refused(sweep, tmp_path):
    root, cases, _ = sweep
    mine = tmp_path / "ds"
    mine.mkdir()
    (mine / "README.md").write_text("my dataset notes")
    with pytest.raises(InputError, match=r"sweep\.dataset_dir: .* did not write"):
        write_dataset(cases, root / "sweep", root / "fatigue", mine, design=DESIGN)
    assert [p.name for p in mine.iterdir()] == ["README.md"]
    assert (mine / "README.md").read_text() == "my dataset notes"


def test_committed_dataset_marker_lists_the_stage_outputs():
    """data/dataset is git-tracked beside DVC outputs; its committed marker makes the
    dataset stage accept it on `dvc repro` (DVC's .gitignore there is left alone)."""
    from pathlib import Path

    from drillfatigue.sweep.dataset import DATASET_FILES, DATASET_KIND

    folder = Path(__file__).resolve().parents[3] / "data" / "dataset"
    marker = json.loads((folder / ".drillfatigue.json").read_text())
    assert marker == {"kind": DATASET_KIND, "files": sorted(DATASET_FILES)}


def _front_matter(card: str) -> dict:
    assert card.startswith("---\n")
    return yaml.safe_load(card.split("---\n", 2)[1])


def test_card_matches_the_table(sweep):
    """Every column of the table is listed once, with its unit and role, in the schema and
    in the machine-readable front matter; no column is constant; the constants file holds
    the rest."""
    root, _, _ = sweep
    card = (root / "dataset" / "README.md").read_text()
    df = pd.read_parquet(root / "dataset" / "damage.parquet")
    meta = _front_matter(card)
    assert meta["license"] == "cc-by-4.0"
    assert [f["name"] for f in meta["dataset_info"]["features"]] == list(df.columns)
    columns = meta["drillfatigue"]["columns"]
    assert list(columns) == list(df.columns)
    schema = card.split("## Schema", 1)[1].split("## Constant columns", 1)[0]
    for col in df.columns:
        assert schema.count(f"| `{col}` |") == 1, col
        assert f"| `{col}` | {columns[col]['role']} | {df[col].dtype} | {unit_of(col)} |" in schema
        assert columns[col]["unit"] == unit_of(col)
    assert meta["drillfatigue"]["group_column"] == "case_id"
    roles = {c: v["role"] for c, v in columns.items()}
    assert roles["operation.rpm"] == "input" and roles["damage_rate_per_h_matake"] == "target"
    assert roles["max_contact_force_N"] == "post_run"
    assert all(df[c].nunique(dropna=False) > 1 for c in df.columns if c != "case_id")
    constants = json.loads((root / "dataset" / "constants.json").read_text())
    assert constants and not set(constants) & set(df.columns)
    for col, entry in constants.items():
        assert entry["unit"] == unit_of(col) and f"| `{col}` |" in card
