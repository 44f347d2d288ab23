"""Adaptive design: seeded, resumable after an interruption, diverse batches, input errors.

A fake target function stands in for the simulator and fatigue chain: a
smooth function of the case's inputs with a sharp ridge, cached on disk per
case id as the real chain caches its run folders.
"""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Literal

import numpy as np
import pandas as pd
import pytest
from pydantic import Field

from drillfatigue.config import Params, SweepConfig, validate
from drillfatigue.config.base import StrictModel
from drillfatigue.errors import InputError
from drillfatigue.sweep.adaptive import (
    acquisition_scores,
    adaptive_design,
    case_targets,
    diverse_batch,
    unit_features,
)
from drillfatigue.sweep.design import design_cases, design_space


class _Operation(StrictModel):
    rpm: float = Field(default=120.0, ge=0.0, le=400.0)


class _Friction(StrictModel):
    mu_dynamic: float = Field(default=0.3, ge=0.0, le=1.0)


class _Well(StrictModel):
    profile: Literal["p1", "p2", "p3"] = "p1"


class _Case(StrictModel):
    operation: _Operation = Field(default_factory=_Operation)
    friction: _Friction = Field(default_factory=_Friction)
    well: _Well = Field(default_factory=_Well)


BASE = _Case().model_dump(mode="json")
VARIABLES = {"operation.rpm": {"low": 60.0, "high": 180.0},
             "friction.mu_dynamic": {"low": 0.1, "high": 0.5},
             "well.profile": {"choices": ["p1", "p2", "p3"]}}
CENSOR = -5.0


def _cfg(**adaptive) -> SweepConfig:
    block = {"n_initial": 8, "batch_size": 4, "candidates": 128, "seed": 7, "n_members": 4}
    return validate(SweepConfig, {"method": "adaptive", "n_cases": 20, "seed": 3,
                                  "variables": VARIABLES, "adaptive": block | adaptive})


def _truth(case: dict) -> dict[str, float]:
    """Fake governing log10 rates: a ridge near rpm 170 in profile p3, censored elsewhere."""
    rpm, mu = case["operation"]["rpm"], case["friction"]["mu_dynamic"]
    ridge = 5.0 * math.exp(-(((rpm - 170.0) / 8.0) ** 2)) if case["well"]["profile"] == "p3" else 0.0
    return {"log10_governing_rate_per_h_collar": -6.0 + ridge + 2.0 * mu,
            "log10_governing_rate_per_h_drill_pipe": -7.0 + 0.01 * rpm}


class _CachedTarget:
    """Evaluates cases not yet in ``folder`` (one JSON per case id), counting them;
    raises after ``fail_after`` evaluations (an interrupted design)."""

    def __init__(self, folder: Path, fail_after: int | None = None) -> None:
        self.folder = folder
        self.folder.mkdir(parents=True, exist_ok=True)
        self.fail_after = fail_after
        self.evaluated: list[str] = []

    def __call__(self, cases: pd.DataFrame) -> pd.DataFrame:
        rows = {}
        for cid, text in zip(cases["case_id"], cases["case_json"], strict=True):
            path = self.folder / f"{cid}.json"
            if not path.is_file():
                if self.fail_after is not None and len(self.evaluated) >= self.fail_after:
                    raise KeyboardInterrupt
                path.write_text(json.dumps(_truth(json.loads(text))))
                self.evaluated.append(cid)
            rows[cid] = json.loads(path.read_text())
        return pd.DataFrame.from_dict(rows, orient="index").rename_axis("case_id")


def _design(tmp_path: Path, cfg: SweepConfig, name: str = "cache", fail_after=None):
    target = _CachedTarget(tmp_path / name, fail_after)
    frame = adaptive_design(cfg, BASE, target, censor_log10=CENSOR, model=_Case)
    return frame, target


def test_rounds_sizes_and_initial_design_is_the_sobol_design(tmp_path):
    cfg = _cfg()
    frame, target = _design(tmp_path, cfg)
    assert len(frame) == 20 and frame["case_id"].is_unique
    assert frame["round"].tolist() == [0] * 8 + [1] * 4 + [2] * 4 + [3] * 4
    assert frame["acquisition_score"].iloc[:8].isna().all()
    assert (frame["acquisition_score"].iloc[8:] >= 0.0).all()
    # every case evaluated exactly once, in design order
    assert target.evaluated == frame["case_id"].tolist()
    # round 0 = the first n_initial cases of the Sobol design of sweep.seed
    sobol = design_cases(cfg.model_copy(update={"method": "sobol", "n_cases": 8}), BASE,
                         model=_Case)
    assert frame["case_id"].iloc[:8].tolist() == sobol["case_id"].tolist()
    # the last round is cut to reach n_cases exactly
    short, _ = _design(tmp_path, _cfg().model_copy(update={"n_cases": 14}), "short")
    assert short["round"].value_counts().sort_index().tolist() == [8, 4, 2]
    assert short["case_id"].tolist() == frame["case_id"].iloc[:14].tolist()


def test_seeded_determinism(tmp_path):
    a, _ = _design(tmp_path, _cfg(), "a")
    b, _ = _design(tmp_path, _cfg(), "b")
    pd.testing.assert_frame_equal(a, b)
    c, _ = _design(tmp_path, _cfg(seed=8), "c")
    assert c["case_id"].iloc[:8].tolist() == a["case_id"].iloc[:8].tolist()
    assert set(c["case_id"].iloc[8:]) != set(a["case_id"].iloc[8:])


def test_resume_after_interruption_gives_the_same_design(tmp_path):
    whole, _ = _design(tmp_path, _cfg(), "whole")
    with pytest.raises(KeyboardInterrupt):
        _design(tmp_path, _cfg(), "resumed", fail_after=14)  # stops inside round 2
    resumed, target = _design(tmp_path, _cfg(), "resumed")
    pd.testing.assert_frame_equal(resumed, whole)
    # only the cases not finished before the interruption were evaluated again
    assert target.evaluated == whole["case_id"].iloc[14:].tolist()


def test_batches_go_where_the_ensemble_disagrees(tmp_path):
    """The ridge (p3, rpm near 170) is where members disagree: the rounds put more
    cases near it than the space-filling start does (1/3 of p3 cases, 10/120 of rpm)."""
    frame, _ = _design(tmp_path, _cfg(), "ridge")
    added = frame[frame["round"] > 0]
    p3 = added["well.profile"] == "p3"
    assert p3.mean() > 1.0 / 3.0
    assert (added["operation.rpm"][p3] > 150.0).mean() > 0.5


def test_agreement_beyond_the_horizon_scores_zero():
    rng = np.random.default_rng(0)
    x = rng.random((20, 2))
    y = CENSOR - 1.0 - x[:, :1]  # every life beyond the horizon, varying below it
    s = acquisition_scores(x, y, rng.random((50, 2)), n_members=4, seed=1, censor_log10=CENSOR)
    assert np.all(s == 0.0)
    s = acquisition_scores(x, y, rng.random((50, 2)), n_members=4, seed=1, censor_log10=None)
    assert np.all(s >= 0.0) and s.max() > 0.0


def test_diversity_rule():
    # 6 disputed candidates in a tight cluster at the origin, 2 less disputed far ones
    x_cand = np.array([[0.0, 0.0], [0.01, 0.0], [0.0, 0.01], [0.01, 0.01], [0.02, 0.0],
                       [0.0, 0.02], [1.0, 1.0], [1.0, 0.0]])
    score = np.array([9.0, 8.0, 7.0, 6.0, 5.0, 4.0, 3.0, 2.0])
    design = np.empty((0, 2))
    # pool = the 3 most disputed only: the batch stays in the cluster, most disputed first
    assert diverse_batch(x_cand, score, design, 3, 3).tolist() == [0, 1, 2]
    # a wider pool: the first is the most disputed, then the farthest points (max-min)
    assert diverse_batch(x_cand, score, design, 3, 8).tolist() == [0, 6, 7]
    # a design point at (1, 1) makes (1, 0) the farthest after the first
    assert diverse_batch(x_cand, score, np.array([[1.0, 1.0]]), 2, 8).tolist() == [0, 7]


def test_unit_features_scale_a_level_change_to_one():
    space = design_space(_cfg(), BASE, model=_Case)
    x = unit_features(space, np.array([[0.0, 0.0, 0.1], [0.0, 0.0, 0.9]]))
    assert x.shape == (2, 5)
    assert np.linalg.norm(x[0] - x[1]) == pytest.approx(1.0)


def test_case_targets_governing_per_component():
    rows = pd.DataFrame({"case_id": ["a", "a", "a", "b"],
                         "component_type": ["collar", "collar", "drill_pipe", "collar"],
                         "damage_rate_per_h_matake": [1e-3, 1e-2, 0.0, 1e-5]})
    t = case_targets(rows, "damage_rate_per_h_matake", 1e-12)
    assert t.loc["a", "log10_governing_rate_per_h_collar"] == pytest.approx(-2.0)
    assert t.loc["a", "log10_governing_rate_per_h_drill_pipe"] == pytest.approx(-12.0)
    assert t.loc["b", "log10_governing_rate_per_h_collar"] == pytest.approx(-5.0)
    assert np.isnan(t.loc["b", "log10_governing_rate_per_h_drill_pipe"])


@pytest.mark.parametrize(("block", "field"), [
    ({"n_initial": 32}, "sweep.adaptive.n_initial"),
    ({"n_initial": 1}, "sweep.adaptive.n_initial"),
    ({"batch_size": 0}, "sweep.adaptive.batch_size"),
    ({"batch_size": 64, "candidates": 32}, "sweep.adaptive.candidates"),
    ({"n_members": 1}, "sweep.adaptive.n_members"),
    ({"pool_factor": 0.5}, "sweep.adaptive.pool_factor"),
    ({"batches": 3}, "sweep.adaptive.batches"),
])
def test_input_errors_name_the_field(block, field):
    with pytest.raises(InputError) as err:
        validate(Params, {"sweep": {"method": "adaptive", "n_cases": 16, "adaptive": block}})
    assert err.value.field == field
