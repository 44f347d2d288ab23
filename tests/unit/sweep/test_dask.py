"""Dask scheduler: a LocalCluster with 2 worker processes gives the same outputs as the local pool."""

from __future__ import annotations

from pathlib import Path

import pandas as pd
import pytest

from drillfatigue.sweep.runner import FAILURES_NAME, Case, run_sweep
from testkit.synthetic_sweep import synthetic_case


def _tree(root: Path) -> dict[str, bytes]:
    return {str(p.relative_to(root)): p.read_bytes() for p in sorted(root.rglob("*"))
            if p.is_file() and p.parent != root}


@pytest.mark.slow  # a Dask LocalCluster takes 5-15 s to start on 2 busy cores
def test_local_cluster_matches_process_pool(tmp_path):
    cases = [Case(f"case{i:03d}", {"operation": {"rpm": 50.0 + 7 * i},
                                   "synthetic": {"work": 20000}}) for i in range(6)]
    bad = Case("bad", {"synthetic": {"fail_times": 99, "counter_dir": str(tmp_path / "n")}})
    pool = run_sweep([*cases, bad], synthetic_case, tmp_path / "pool", scheduler="processes",
                     n_workers=2, max_retries=1, failure_threshold=0.5)
    dask = run_sweep([*cases, bad], synthetic_case, tmp_path / "dask", scheduler="local-cluster",
                     n_workers=2, max_retries=1, failure_threshold=0.5)
    assert (dask.n_done, dask.n_failed) == (pool.n_done, pool.n_failed) == (6, 1)
    assert _tree(tmp_path / "dask") == _tree(tmp_path / "pool")
    cols = ["case_id", "attempts", "final", "error_type", "error"]
    f_pool = pd.read_parquet(tmp_path / "pool" / FAILURES_NAME)[cols]
    f_dask = pd.read_parquet(tmp_path / "dask" / FAILURES_NAME)[cols]
    pd.testing.assert_frame_equal(f_pool, f_dask)


def test_scheduler_address(tmp_path):
    """``tcp://host:port`` of a running scheduler: same outputs, warm-up run on each worker.

    The cluster's workers are threads of this process (quick to start); the
    sweep still connects through the TCP address like a remote cluster.
    """
    import logging

    from distributed import LocalCluster

    cases = [Case(f"case{i:03d}", {"operation": {"rpm": 50.0 + 7 * i}}) for i in range(3)]
    run_sweep(cases, synthetic_case, tmp_path / "serial", scheduler="serial")
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=False, protocol="tcp",
                      dashboard_address=None, silence_logs=logging.ERROR) as cluster:
        address = cluster.scheduler_address
        assert address.startswith("tcp://")
        report = run_sweep(cases, synthetic_case, tmp_path / "tcp", scheduler=address)
    assert report.n_done == 3
    assert _tree(tmp_path / "tcp") == _tree(tmp_path / "serial")
