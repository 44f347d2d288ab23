"""Carrying research case files across a code change (drillfatigue.sweep.restamp) and the
``research_dataset`` stage's refusals.

The case files of a tiny research run are stamped with a foreign physics digest, as if an
earlier commit had written them: the research run refuses them; ``dataset restamp``
re-runs a sample at this code, finds it equal and records this digest beside the old one;
the run then accepts every file and re-assembles the same bytes. A case file whose rows
differ is refused with its case and column, and nothing is written. The stage that
assembles the committed dataset refuses a missing case file and digests not found equal.
"""

from __future__ import annotations

import json
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from drillfatigue.cli import main
from drillfatigue.sweep.research import (LINEAGE_FILE, physics_digest, read_case_file,
                                         read_lineage, read_marker)
from drillfatigue.sweep.research_case import write_case_file
from drillfatigue.sweep.restamp import compare_case_files, restamp_sample

from testkit.research_runs import N_HELDOUT, N_TRAIN, case_files, env, full_run

ROOT = Path(__file__).resolve().parents[2]
OLD = "0" * 64


def _restamp_files(out: Path, digest: str, tamper: bool = False) -> None:
    """Rewrite every case file's marker with ``digest`` (and, with ``tamper``, one damage
    rate changed by one part in 10^9), the rows otherwise as they are."""
    for path in case_files(out):
        marker = {**read_marker(path), "physics_digest": digest, "commit": "0ld0ld0"}
        rows = read_case_file(path)
        if tamper:
            col = "damage_rate_per_h_matake"
            rows[col] = rows[col].where(rows[col].isna(), rows[col] * (1 + 1e-9))
        write_case_file(rows, path, marker)


def _stage(root: Path, params: Path) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, str(ROOT / "pipeline" / "research_dataset.py"),
                           "--params", str(params), "--root", str(root)],
                          capture_output=True, text=True, env=env())


@pytest.fixture(scope="module")
def tiny_run(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, Path]:
    """A finished tiny research run (2 + 1 cases) whose case files carry digest OLD."""
    work = tmp_path_factory.mktemp("restamp")
    params, _ = full_run(work)
    _restamp_files(work / "research", OLD)
    return work, params


def _copy(tiny_run: tuple[Path, Path], tmp_path: Path) -> tuple[Path, Path]:
    """The tiny run's research folder copied for one test; with its params file."""
    out = tmp_path / "research"
    shutil.copytree(tiny_run[0] / "research", out)
    return out, tiny_run[1]


@pytest.mark.slow
@pytest.mark.timeout(900)
def test_restamp_carries_equal_case_files_to_this_code(
        tiny_run: tuple[Path, Path], tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    out, params = _copy(tiny_run, tmp_path)
    dataset = {n: (out / "dataset" / n).read_bytes() for n in ("train.parquet", "heldout.parquet")}
    args = ["--params", str(params), "--out", str(out), "--no-progress"]
    research = ["dataset", "research", "--n-cases", str(N_TRAIN), "--heldout-cases",
                str(N_HELDOUT), *args]

    assert main(research) == 2  # files of another digest, not known equal
    assert "dataset restamp" in capsys.readouterr().err

    assert main(["dataset", "restamp", "--sample", "2", *args]) == 0
    said = capsys.readouterr().out
    assert "2 cases" in said and "re-run equal bit for bit" in said, said
    lineage = read_lineage(out)
    assert [e["physics_digest"] for e in lineage] == [OLD, physics_digest()]
    assert lineage[1]["checked_against"] == [OLD]
    assert sum(len(v) for v in lineage[1]["cases"].values()) == 2
    assert lineage[1]["cases"]["heldout"], "every split is sampled"
    assert {read_marker(p)["physics_digest"] for p in case_files(out)} == {OLD}  # kept

    assert main(["dataset", "restamp", *args]) == 0
    assert "nothing run" in capsys.readouterr().out
    assert main(research) == 0
    assert "0 run, 3 already done" in capsys.readouterr().out
    for name, data in dataset.items():
        assert (out / "dataset" / name).read_bytes() == data, name

    # the stage accepts digests found equal, and refuses one that is not among them
    res = _stage(out, params)
    assert res.returncode == 0, res.stderr
    other = case_files(out)[0]
    write_case_file(read_case_file(other), other, {**read_marker(other),
                                                  "physics_digest": "f" * 64})
    before = {p: p.read_bytes() for p in (out / "dataset").iterdir()}
    res = _stage(out, params)
    assert res.returncode == 2
    assert "physics digests not found equal" in res.stderr
    assert len(res.stderr.strip().splitlines()) == 1
    assert {p: p.read_bytes() for p in (out / "dataset").iterdir()} == before


@pytest.mark.slow
@pytest.mark.timeout(900)
def test_restamp_refuses_rows_that_differ_and_writes_nothing(
        tiny_run: tuple[Path, Path], tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    out, params = _copy(tiny_run, tmp_path)
    _restamp_files(out, OLD, tamper=True)
    before = {p: p.read_bytes() for p in out.rglob("*") if p.is_file()}
    code = main(["dataset", "restamp", "--params", str(params), "--out", str(out),
                 "--sample", "1", "--no-progress"])
    err = capsys.readouterr().err
    assert code == 2
    assert "differs from its committed file: column damage_rate_per_h_matake" in err, err
    assert len(err.strip().splitlines()) == 1
    assert not (out / LINEAGE_FILE).exists()
    assert {p: p.read_bytes() for p in out.rglob("*") if p.is_file()} == before


def test_the_sample_covers_each_split_and_both_window_paths(tiny_run: tuple[Path, Path]
                                                            ) -> None:
    work, _ = tiny_run
    out = work / "research"
    one = restamp_sample(out, "a" * 64, 1)
    assert len(one["train"]) == 1 and len(one["heldout"]) == 1
    every = restamp_sample(out, "a" * 64, 100)
    assert sorted(every["train"] + every["heldout"]) == sorted(p.stem for p in case_files(out))
    # another digest orders the cases by another hash, the same digest by the same
    assert restamp_sample(out, "a" * 64, 1) == one


def test_compare_names_dtype_and_value_differences(tiny_run: tuple[Path, Path],
                                                   tmp_path: Path) -> None:
    work, _ = tiny_run
    path = case_files(work / "research")[0]
    marker = read_marker(path)
    rows = read_case_file(path)
    same = tmp_path / "same.parquet"
    write_case_file(rows.assign(wall_time_s=rows["wall_time_s"] + 1.0), same, marker)
    assert compare_case_files(path, same) is None  # the machine's wall time is not compared
    neg = tmp_path / "neg.parquet"
    col = "md_m"
    write_case_file(rows.assign(**{col: rows[col].astype("float32")}), neg, marker)
    assert compare_case_files(path, neg) == f"column {col}: dtype float32, committed float64"
    val = tmp_path / "val.parquet"
    changed = rows.copy()
    changed.loc[changed.index[0], col] = np.nextafter(changed[col].iloc[0], np.inf)
    write_case_file(changed, val, marker)
    assert compare_case_files(path, val).startswith(f"column {col}: largest relative difference")


def test_stage_refuses_a_missing_case_file_and_writes_nothing(tiny_run: tuple[Path, Path],
                                                              tmp_path: Path) -> None:
    out, params = _copy(tiny_run, tmp_path)
    shutil.rmtree(out / "dataset")
    sorted((out / "cases" / "train").glob("*.parquet"))[0].unlink()
    res = _stage(out, params)
    assert res.returncode == 2
    assert "1 of 2 designed cases have no case file" in res.stderr
    assert len(res.stderr.strip().splitlines()) == 1
    assert not (out / "dataset").exists()
    assert json.loads((out / "design" / "design.json").read_text())["n_cases"] == N_TRAIN
