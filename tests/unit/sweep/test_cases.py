"""The fatigue pass of the sweep on a synthetic run folder (the run-directory contract)."""

from __future__ import annotations

import pandas as pd
import pytest

from drillfatigue.config import FatigueConfig
from drillfatigue.fatigue import evaluate_run
from drillfatigue.sweep.cases import fatigue_case, fatigue_tasks
from drillfatigue.sweep.runner import Case, run_sweep
from testkit.synthetic_sweep import N_JOINT, synthetic_case


@pytest.fixture(scope="module")
def run_root(tmp_path_factory):
    root = tmp_path_factory.mktemp("runs")
    run_sweep([Case("c0", {"operation": {"rpm": 90.0}})], synthetic_case, root, scheduler="serial")
    return root


def test_fatigue_case_on_synthetic_run(run_root, tmp_path):
    cfg = FatigueConfig(plots=False)
    (cid, task), = fatigue_tasks(["c0", "missing"], run_root, cfg.model_dump(mode="json"),
                                 ["findley", "uniaxial"], api_rp7g=False)
    assert cid == "c0" and task["criteria"] == ["findley", "uniaxial"]
    summary = fatigue_case(task, tmp_path)
    assert summary["criteria"] == ["findley", "uniaxial"]
    damage = pd.read_parquet(tmp_path / "damage.parquet")
    # criteria x joints x (body, connection; drill pipe also upset)
    from drillfatigue.fatigue.run import joint_locations
    types = pd.read_parquet(run_root / "c0" / "joints.parquet")["component_type"]
    assert len(types) == N_JOINT
    assert len(damage) == 2 * sum(len(joint_locations(t, cfg)) for t in types)
    # the uniaxial rows (reused from the findley evaluation) equal a direct evaluation
    direct = evaluate_run(run_root / "c0", cfg, None, criterion="uniaxial")
    mine = damage[damage["criterion"] == "uniaxial"].reset_index(drop=True)
    pd.testing.assert_series_equal(mine["damage_rate_per_h"], direct["damage_rate_per_h"],
                                   rtol=1e-12)
    assert (mine["damage_rate_per_h"] > 0).all()
