"""A whole params.yaml doubles as a case file (its case sections form the case)."""

from __future__ import annotations

from pathlib import Path

import pytest
import yaml

from drillfatigue.config import load_case, load_params
from drillfatigue.errors import InputError

ROOT = Path(__file__).parents[3]


def test_project_params_load_as_a_case() -> None:
    params = load_params(ROOT / "params.yaml")
    case = load_case(ROOT / "params.yaml")
    assert case.operation == params.operation
    assert case.string == params.string
    assert case.well == params.well


def test_pipeline_sections_are_still_validated(tmp_path: Path) -> None:
    data = yaml.safe_load((ROOT / "params.yaml").read_text())
    data["sweep"]["n_cases"] = 0
    bad = tmp_path / "params.yaml"
    bad.write_text(yaml.safe_dump(data))
    with pytest.raises(InputError) as exc:
        load_case(bad)
    assert exc.value.field == "sweep.n_cases"
