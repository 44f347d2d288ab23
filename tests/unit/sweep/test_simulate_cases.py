"""The example case files in data/cases validate and build."""

from __future__ import annotations

from pathlib import Path

import pytest

from drillfatigue.config import load_case
from drillfatigue.dynamics.run.model import build_model, straight_path

CASES = sorted((Path(__file__).resolve().parents[3] / "data" / "cases").glob("*.yaml"))


@pytest.mark.parametrize("path", CASES, ids=[p.stem for p in CASES])
def test_case_file_validates_and_builds(path: Path) -> None:
    cfg = load_case(path)
    model, _ = build_model(cfg, straight_path(cfg.operation.bit_md_m + 500.0))
    assert model.dt > 0.0
    assert model.hook_load_N > 0.0
