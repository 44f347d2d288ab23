"""The dataset card's text is pinned: ``tests/data/dataset_card_reference.md`` holds the
card of a small hand-built table (every section: a Sobol design with a converged window,
rig boundaries, categorical and numeric variables, constants, a floor, a base case; and
the card of a bare design), with the software versions replaced by fixed ones."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from drillfatigue.sweep import dataset
from drillfatigue.sweep.dataset import dataset_card

REFERENCE = Path(__file__).resolve().parents[2] / "data" / "dataset_card_reference.md"


def _frame() -> pd.DataFrame:
    n = 6
    return pd.DataFrame({
        "case_id": np.repeat(["a1", "b2", "c3"], 2).astype(object),
        "operation.rpm": np.linspace(60.0, 180.0, n),
        "bit.lobes": np.array([1, 1, 3, 3, 5, 5], dtype=np.int64),
        "well.profile": np.array(["build_hold", "s_shape"] * 3, dtype=object),
        "s_from_bit_m": np.tile([2.0, 22.0], 3),
        "achieved_mean_wob_N": np.linspace(8e4, 9e4, n),
        "window_converged": np.array([True, False] * 3),
        "damage_rate_per_h_matake": np.array([0.0, 1e-6, 2e-5, 0.0, 3e-4, 1e-7]),
    })


def cards() -> str:
    frame = _frame()
    design = {"method": "sobol", "seed": 3, "n_cases": 3, "boundaries": "rig", "window_s": 4.0,
              "criterion": "matake",
              "window": {"mode": "converged", "growth": 2, "max_s": 16, "tol_rel": 0.1},
              "variables": {"operation.rpm": {"low": 60, "high": 180, "scale": "linear"},
                            "well.profile": {"choices": ["build_hold", "s_shape"]},
                            "bit.lobes": {"low": 1, "high": 5, "kind": "int"}}}
    metrics = {"n_cases_designed": 4, "n_cases_in_dataset": 3, "n_cases_failed_simulation": 1,
               "n_cases_failed_fatigue": 0, "n_rows": len(frame), "n_rows_zero_damage": 2}
    full = dataset_card(frame, design=design, metrics=metrics,
                        base_case={"operation": {"rpm": 120.0}, "bit": {"lobes": 3}},
                        constants={"rig.block_mass_kg": 1.5e4, "bit.kind": "pdc"},
                        floor_per_h=1e-9, paths={"dataset": "x/dataset"})
    bare = dataset_card(frame, design={"method": "lhs", "seed": 1}, metrics={})
    return full + "\n<!-- the card of a bare design -->\n" + bare


def test_the_card_text_is_the_reference(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(dataset, "_versions", lambda: {"python": "3.x", "numpy": "1.x"})
    assert cards() == REFERENCE.read_text(encoding="utf-8")
