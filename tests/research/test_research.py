"""The research sweep (drillfatigue.sweep.research): a run stopped by SIGKILL after a
finished case and continued from a fresh clone assembles the same dataset as an
uninterrupted run (byte for byte: the tables leave out the measured wall_time_s; the
same bytes from the same case files); the physics digest covers every module a case imports; files of
another digest are refused."""

from __future__ import annotations

import json
import os
import random
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from drillfatigue.cli import main
from drillfatigue.sweep.research import (PHYSICS_MODULES, _load_or_write_design,
                                         physics_digest, read_marker)
from drillfatigue.sweep.research_case import write_case_file
from testkit.research_runs import (N_HELDOUT, N_TRAIN, case_files, command, env, full_run, git,
                                   tiny_params)

ROOT = Path(__file__).resolve().parents[2]


@pytest.mark.slow
@pytest.mark.timeout(900)  # a fresh numba cache compiles the kernels first
def test_killed_run_continued_from_a_clone_assembles_the_same_dataset(tmp_path: Path) -> None:
    full = tmp_path / "full"
    params, _ = full_run(full)  # uninterrupted (shared with the restamp tests)
    n_total = N_TRAIN + N_HELDOUT
    assert len(case_files(full / "research")) == n_total

    # the same run, SIGKILLed (with its workers) after a random number of finished cases
    part = tmp_path / "part"
    part.mkdir()
    shutil.copy(params, part / "params.yaml")
    stop_after = random.Random().randint(1, n_total - 1)
    proc = subprocess.Popen(command(part / "params.yaml", part / "research"), cwd=part,
                            env=env(), start_new_session=True, stdout=subprocess.DEVNULL,
                            stderr=subprocess.DEVNULL)
    deadline = time.monotonic() + 600
    while len(case_files(part / "research")) < stop_after and proc.poll() is None:
        assert time.monotonic() < deadline, "no case finished in time"
        time.sleep(0.05)
    os.killpg(proc.pid, signal.SIGKILL)
    proc.wait()
    done = len(case_files(part / "research"))
    assert done >= stop_after

    # what the repository holds at the stop, committed and cloned into a fresh folder
    git(part, "init", "-q")
    git(part, "add", "-A")
    git(part, "commit", "-qm", "partial research run")
    clone = tmp_path / "clone"
    git(tmp_path, "clone", "-q", str(part), str(clone))
    res = subprocess.run(command(clone / "params.yaml", clone / "research"), cwd=clone,
                         env=env(), capture_output=True, text=True)
    assert res.returncode == 0, res.stderr
    skipped = int(res.stdout.split(" run, ")[1].split(" already done")[0])
    assert skipped == done < n_total or done == n_total
    import pandas as pd

    # the tables leave out the measured wall time: byte for byte the uninterrupted run's
    for name in ("train.parquet", "heldout.parquet"):
        a = full / "research" / "dataset" / name
        b = clone / "research" / "dataset" / name
        assert "wall_time_s" not in pd.read_parquet(a).columns
        assert a.read_bytes() == b.read_bytes(), name
    assert ((full / "research" / "dataset" / "constants.json").read_bytes()
            == (clone / "research" / "dataset" / "constants.json").read_bytes())
    # from the same case files the assembly is the same bytes
    again = tmp_path / "again"
    shutil.copytree(full / "research", again)
    for f in (again / "dataset").iterdir():
        f.unlink()
    from drillfatigue.config import load_params
    from drillfatigue.sweep.research import assemble_research

    assemble_research(again, load_params(params))
    for name in ("train.parquet", "heldout.parquet", "constants.json"):
        assert ((full / "research" / "dataset" / name).read_bytes()
                == (again / "dataset" / name).read_bytes()), name

    train = pd.read_parquet(clone / "research" / "dataset" / "train.parquet")
    assert train["case_id"].nunique() == N_TRAIN and set(train["split"]) == {"train"}
    keys = train[["case_id", "joint", "location"]]
    assert keys.equals(keys.sort_values(["case_id", "joint", "location"]))


@pytest.mark.slow
@pytest.mark.timeout(600)
def test_a_case_imports_only_modules_of_the_physics_digest(tmp_path: Path) -> None:
    from drillfatigue.config import load_params
    from drillfatigue.sweep.research import _case_inputs, research_design

    # the design is made by the parent (its modules decide which cases, not their rows)
    p = load_params(tiny_params(tmp_path))
    row = research_design(p, 1, 0)["train"].to_dict("records")[0]
    task = {"row": row, "split": "train", "inputs": _case_inputs(p, row, list(p.sweep.variables)),
            "marker": {}, "path": str(tmp_path / "case.parquet")}
    (tmp_path / "task.json").write_text(json.dumps(task), encoding="utf-8")
    script = """
import json, sys
from drillfatigue import scope_numba_cache
scope_numba_cache()
from drillfatigue.sweep.research_case import research_case
rec = research_case(json.load(open("task.json")))
assert rec["ok"], rec
print(json.dumps(sorted(m.__file__ for n, m in sys.modules.items()
                        if n.startswith("drillfatigue") and getattr(m, "__file__", None))))
"""
    res = subprocess.run([sys.executable, "-c", script], cwd=tmp_path, env=env(),
                         capture_output=True, text=True, check=True)
    files = json.loads(res.stdout.strip().splitlines()[-1])
    pkg = ROOT / "src" / "drillfatigue"
    outside = []
    for f in files:
        rel = Path(f).resolve().relative_to(pkg.resolve()).as_posix()
        if not any(rel == m or (m.endswith("/") and rel.startswith(m)) for m in PHYSICS_MODULES):
            outside.append(rel)
    assert not outside, f"modules a case imports, missing from PHYSICS_MODULES: {outside}"


def test_files_of_another_physics_digest_are_refused(tmp_path: Path,
                                                     capsys: pytest.CaptureFixture[str]) -> None:
    from drillfatigue.config import load_params
    from drillfatigue.files import OutputFolder
    from drillfatigue.sweep.research import RESEARCH_KIND

    params = tiny_params(tmp_path)
    p = load_params(params)
    out = tmp_path / "research"
    designs = _load_or_write_design(OutputFolder(out, RESEARCH_KIND), p, N_TRAIN, N_HELDOUT)
    cid = str(designs["train"]["case_id"].iloc[0])
    path = out / "cases" / "train" / f"{cid}.parquet"
    import pandas as pd

    marker = {"case_id": cid, "split": "train", "inputs_sha256": "x",
              "physics_digest": "0" * 64, "commit": "abc1234"}
    write_case_file(pd.DataFrame({"case_id": [cid], "joint": [0]}), path, marker)
    assert read_marker(path) == marker
    code = main(["dataset", "research", "--params", str(params), "--n-cases", str(N_TRAIN),
                 "--heldout-cases", str(N_HELDOUT), "--out", str(out), "--no-progress"])
    err = capsys.readouterr().err
    assert code == 2
    assert "physics digest 000000000000 at commit abc1234" in err
    assert physics_digest()[:12] in err
    assert len(err.strip().splitlines()) == 1
