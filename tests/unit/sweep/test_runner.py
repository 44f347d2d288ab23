"""Sweep engine: every case once, resume, retries and failure records, threshold, kill and rerun.

The case function is :func:`testkit.synthetic_sweep.synthetic_case`, a
module-level function of the package (so it pickles by name into process-pool
and Dask workers) whose outputs are a deterministic function of its inputs.
"""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import pandas as pd
import pytest

from drillfatigue.errors import InputError
from drillfatigue.sweep.runner import (
    DONE_NAME,
    FAILURES_NAME,
    Case,
    SweepFailedError,
    is_done,
    run_sweep,
)
from testkit.synthetic_sweep import synthetic_case


def make_cases(n: int, **synthetic) -> list[Case]:
    return [Case(f"case{i:03d}", {"operation": {"rpm": 60.0 + i}, "synthetic": dict(synthetic)})
            for i in range(n)]


def tree(root: Path) -> dict[str, bytes]:
    """Every file under the case folders (not the sweep-level report), by relative path."""
    return {str(p.relative_to(root)): p.read_bytes() for p in sorted(root.rglob("*"))
            if p.is_file() and p.parent != root}


def test_all_cases_done_once_then_resume_skips(tmp_path):
    cases = make_cases(6, work=1000)
    report = run_sweep(cases, synthetic_case, tmp_path, scheduler="processes", n_workers=2)
    assert (report.n_done, report.n_skipped, report.n_failed) == (6, 0, 0)
    assert sorted(p.name for p in tmp_path.iterdir() if p.is_dir()) == [c.case_id for c in cases]
    assert all(is_done(c, tmp_path) for c in cases)
    assert not (tmp_path / ".tmp").exists()
    assert pd.read_parquet(tmp_path / FAILURES_NAME).empty
    stamp = {c.case_id: (tmp_path / c.case_id / DONE_NAME).stat().st_mtime_ns for c in cases}

    again = run_sweep(cases, synthetic_case, tmp_path, scheduler="processes", n_workers=2)
    assert (again.n_done, again.n_skipped) == (0, 6)
    assert stamp == {c.case_id: (tmp_path / c.case_id / DONE_NAME).stat().st_mtime_ns for c in cases}


_WARMED: list[dict] = []


def _strict_case(case, case_dir):
    return synthetic_case(case, case_dir)


def _strict_warmup(inputs):
    """A warm-up that needs a real case's inputs, as the converged window's does."""
    _WARMED.append(inputs)
    return inputs["operation"]["rpm"]


_strict_case.warmup = _strict_warmup  # type: ignore[attr-defined]


def test_sweep_with_every_case_done_compiles_nothing(tmp_path):
    # a finished sweep re-run (dvc repro after a code-free change, a resumed
    # stage) must not call the warm-up with an empty case: it reads the case
    cases = make_cases(3, work=100)
    run_sweep(cases, synthetic_case, tmp_path, scheduler="processes", n_workers=2)
    _WARMED.clear()
    again = run_sweep(cases, _strict_case, tmp_path, scheduler="processes", n_workers=2)
    assert (again.n_done, again.n_skipped) == (0, 3)
    assert _WARMED == []


def test_changed_inputs_rerun_the_case(tmp_path):
    cases = make_cases(2)
    run_sweep(cases, synthetic_case, tmp_path, scheduler="serial")
    changed = [cases[0], Case(cases[1].case_id, cases[1].inputs | {"x": 1.0})]
    report = run_sweep(changed, synthetic_case, tmp_path, scheduler="serial")
    assert (report.n_done, report.n_skipped) == (1, 1)
    assert json.loads((tmp_path / "case001" / "case.json").read_text())["x"] == 1.0


def test_failing_case_retried_and_recorded(tmp_path):
    cases = make_cases(4)
    bad = Case("bad", {"synthetic": {"fail_times": 99, "counter_dir": str(tmp_path / "n")}})
    flaky = Case("flaky", {"synthetic": {"fail_times": 1, "counter_dir": str(tmp_path / "n")}})
    report = run_sweep([*cases, bad, flaky], synthetic_case, tmp_path / "out", scheduler="serial",
                       max_retries=2, failure_threshold=0.5)
    assert (report.n_done, report.n_failed, report.failed_ids) == (5, 1, ["bad"])
    fails = pd.read_parquet(tmp_path / "out" / FAILURES_NAME).set_index("case_id")
    assert fails.loc["bad", "attempts"] == 3  # 1 + max_retries
    assert bool(fails.loc["bad", "final"]) is True
    assert fails.loc["bad", "error_type"] == "SimulationError"
    assert "synthetic divergence" in fails.loc["bad", "error"]
    assert "Traceback" in fails.loc["bad", "traceback_tail"]
    assert json.loads(fails.loc["bad", "inputs_json"]) == bad.inputs
    assert bool(fails.loc["flaky", "final"]) is False and fails.loc["flaky", "attempts"] == 2
    assert not (tmp_path / "out" / "bad").exists()
    assert is_done(flaky, tmp_path / "out")


def test_threshold_exceeded_raises_after_recording(tmp_path):
    cases = [*make_cases(3), Case("bad", {"synthetic": {"fail_times": 99,
                                                        "counter_dir": str(tmp_path / "n")}})]
    with pytest.raises(SweepFailedError, match=r"1 of 4 cases failed .*failures.parquet"):
        run_sweep(cases, synthetic_case, tmp_path / "out", scheduler="serial", max_retries=0,
                  failure_threshold=0.2)
    assert pd.read_parquet(tmp_path / "out" / FAILURES_NAME)["case_id"].tolist() == ["bad"]
    assert json.loads((tmp_path / "out" / "sweep.json").read_text())["n_failed"] == 1


def test_bad_arguments(tmp_path):
    with pytest.raises(InputError, match="duplicate"):
        run_sweep([Case("a", {}), Case("a", {})], synthetic_case, tmp_path, scheduler="serial")
    with pytest.raises(InputError, match="n_workers"):
        run_sweep([], synthetic_case, tmp_path, n_workers=0)


def test_worker_crash_is_retried_on_a_new_pool(tmp_path):
    """A worker process killed (SIGKILL) mid-case: the pool is rebuilt, nothing is lost."""
    cases = make_cases(4)
    crash = Case("crash", {"synthetic": {"crash_times": 1, "counter_dir": str(tmp_path / "n")}})
    report = run_sweep([*cases, crash], synthetic_case, tmp_path / "out", scheduler="processes",
                       n_workers=2, max_retries=2)
    assert (report.n_done, report.n_failed) == (5, 0)
    fails = pd.read_parquet(tmp_path / "out" / FAILURES_NAME).set_index("case_id")
    assert fails.loc["crash", "error_type"] == "BrokenProcessPool"
    assert not fails["final"].any()


_KILL_SCRIPT = textwrap.dedent("""
    import sys
    from drillfatigue.sweep.runner import Case, run_sweep
    from testkit.synthetic_sweep import synthetic_case
    if __name__ == "__main__":
        cases = [Case(f"case{i:03d}", {"operation": {"rpm": 60.0 + i},
                                       "synthetic": {"sleep_s": 0.3}}) for i in range(12)]
        run_sweep(cases, synthetic_case, sys.argv[1], scheduler="processes", n_workers=2)
""")


def test_killed_sweep_rerun_matches_uninterrupted(tmp_path):
    """Kill the sweep and its workers mid-way (SIGKILL), rerun: each case once, same files."""
    cases = make_cases(12, sleep_s=0.3)
    reference = tmp_path / "reference"
    run_sweep(cases, synthetic_case, reference, scheduler="serial")

    out = tmp_path / "killed"
    script = tmp_path / "sweep_script.py"
    script.write_text(_KILL_SCRIPT)
    proc = subprocess.Popen([sys.executable, str(script), str(out)], start_new_session=True,
                            env=os.environ | {"PYTHONPATH": os.pathsep.join(
                                str(Path(__file__).parents[3] / d) for d in ("src", "tests"))})
    deadline = time.monotonic() + 60
    while time.monotonic() < deadline:
        n = len(list(out.glob(f"*/{DONE_NAME}"))) if out.exists() else 0
        if n >= 3 or proc.poll() is not None:
            break
        time.sleep(0.05)
    os.killpg(proc.pid, signal.SIGKILL)  # the sweep and every worker of its session
    proc.wait()
    done_before = len(list(out.glob(f"*/{DONE_NAME}")))
    assert 3 <= done_before < 12, "the sweep must be killed mid-way"

    report = run_sweep(cases, synthetic_case, out, scheduler="processes", n_workers=2)
    assert report.n_skipped == done_before and report.n_done == 12 - done_before
    assert sorted(p.name for p in out.iterdir() if p.is_dir()) == [c.case_id for c in cases]
    assert tree(out) == tree(reference)


def test_code_change_invalidates_done_markers(tmp_path, monkeypatch):
    """A folder written by other code is not reused (the sweep outputs persist under DVC)."""
    from drillfatigue.sweep import runner

    case = runner.Case("c1", {"x": 1})
    (tmp_path / "c1").mkdir()
    marker = runner._marker("c1", {"x": 1})
    (tmp_path / "c1" / runner.DONE_NAME).write_text(json.dumps(marker))
    assert runner.is_done(case, tmp_path)
    assert len(marker["code_sha256"]) == 64
    monkeypatch.setattr(runner, "code_sha256", lambda: "0" * 64)  # the code changed
    assert not runner.is_done(case, tmp_path)


def test_failures_history_is_kept_and_printed(tmp_path, capsys):
    """A case that failed in run 1 and succeeds in run 2: the run-1 record stays in
    failures.parquet (with its run number and time), and each run says on stderr what
    failed."""
    from drillfatigue.sweep.runner import latest_failures, read_failures

    flaky = Case("flaky", {"synthetic": {"fail_times": 1, "counter_dir": str(tmp_path / "n")}})
    cases = [*make_cases(2), flaky]
    out = tmp_path / "out"
    r1 = run_sweep(cases, synthetic_case, out, scheduler="serial", max_retries=0,
                   failure_threshold=1.0)
    assert (r1.run, r1.n_failed) == (1, 1)
    err = capsys.readouterr().err
    assert "sweep run 1: 1 case(s) failed at least once, 1 still failed" in err
    assert "flaky: failed after 1 attempt(s); SimulationError: synthetic divergence" in err
    r2 = run_sweep(cases, synthetic_case, out, scheduler="serial", max_retries=0,
                   failure_threshold=1.0)
    assert (r2.run, r2.n_done, r2.n_failed) == (2, 1, 0)
    assert capsys.readouterr().err == ""
    hist = read_failures(out / FAILURES_NAME)
    assert hist["case_id"].tolist() == ["flaky"] and hist["run"].tolist() == [1]
    assert bool(hist["final"].iloc[0]) is True
    assert time.strptime(hist["time_utc"].iloc[0], "%Y-%m-%dT%H:%M:%SZ")
    assert latest_failures(out).empty  # the latest run has no failure left
    assert json.loads((out / "sweep.json").read_text())["run"] == 2


def test_sweep_refuses_a_folder_with_foreign_files(tmp_path):
    (tmp_path / "thesis.docx").write_bytes(b"x")
    with pytest.raises(InputError, match="holds files drillfatigue did not write"):
        run_sweep(make_cases(1), synthetic_case, tmp_path, scheduler="serial")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["thesis.docx"]


def test_unmarked_sweep_folder_is_adopted(tmp_path):
    """A sweep folder written before the ownership marker (it has sweep.json) resumes."""
    from drillfatigue.files import MARKER

    cases = make_cases(2)
    run_sweep(cases, synthetic_case, tmp_path, scheduler="serial")
    (tmp_path / MARKER).unlink()
    again = run_sweep(cases, synthetic_case, tmp_path, scheduler="serial")
    assert again.n_skipped == 2 and (tmp_path / MARKER).is_file()
