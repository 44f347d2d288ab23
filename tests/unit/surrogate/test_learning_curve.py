"""benchmarks/learning_curve_research.py: which cases each fit of the learning curve trains on."""

from __future__ import annotations

import sys
from pathlib import Path

import pandas as pd

sys.path.insert(0, str(Path(__file__).resolve().parents[3] / "benchmarks"))
from learning_curve_research import case_order, fit_blocks, markdown_table  # noqa: E402


def test_cases_follow_the_sobol_sequence_and_skip_the_ones_not_simulated() -> None:
    design = pd.DataFrame({"case_id": ["c", "a", "b", "d"], "design_index": [2, 0, 1, 3]})
    train = pd.DataFrame({"case_id": ["d", "a", "c", "a"]})
    assert case_order(design, train) == ["a", "c", "d"]


def test_blocks_are_disjoint_below_the_full_size_and_the_whole_sequence_at_it() -> None:
    order = [f"c{i}" for i in range(16)]
    blocks = fit_blocks(order, 4, 3)
    assert blocks == [order[0:4], order[4:8], order[8:12]]
    assert fit_blocks(order, 8, 5) == [order[:8], order[8:]]  # only two blocks of 8
    full = fit_blocks(order, 16, 3)
    assert len(full) == 3 and all(b == order for b in full)
    assert fit_blocks(order, 12, 3) == [order[:12]] * 3  # one block fits: seeds vary


def test_the_table_gives_mean_spread_and_range() -> None:
    summary = {m: {"mean": 0.5, "std": 0.01, "min": 0.49, "max": 0.51}
               for m in ("factor2_fraction", "rmse", "governing_factor2_fraction")}
    table = markdown_table({"sizes": [{"n_cases": 64, "fits": [{}, {}], "varies": "case block",
                                       "summary": summary}]})
    assert "| 64 | 2 | case block | 0.500 ± 0.010 (0.490–0.510) |" in table
