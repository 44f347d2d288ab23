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
from drillfatigue.config import load_params
from drillfatigue.sweep.adaptive import (
    RowSource,
    acquisition_scores,
    adaptive_design,
    case_targets,
    choose_batch,
    diverse_batch,
    row_matrix,
    row_scores,
    space_filling_batch,
    template_rows,
    unit_features,
)
from drillfatigue.sweep.cases import position_columns
from drillfatigue.sweep.design import base_case_from_params, design_cases, design_space


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


S_FROM_BIT_M = np.linspace(0.0, 90.0, 10)


def _rows_of(cases: pd.DataFrame, target: bool = True) -> pd.DataFrame:
    """Fake dataset rows: 10 locations per case, the collar's rate falling with the distance
    from the bit from the case's governing rate, the pipe's flat (:func:`_truth`)."""
    out = []
    for cid, text in zip(cases["case_id"], cases["case_json"], strict=True):
        case = json.loads(text)
        truth = _truth(case)
        for s in S_FROM_BIT_M:
            collar = s < 30.0
            y = (truth["log10_governing_rate_per_h_collar"] - 0.01 * s if collar
                 else truth["log10_governing_rate_per_h_drill_pipe"])
            row = {"case_id": cid, "operation.rpm": case["operation"]["rpm"],
                   "friction.mu_dynamic": case["friction"]["mu_dynamic"],
                   "well.profile": case["well"]["profile"], "s_from_bit_m": s,
                   "component_type": "collar" if collar else "drill_pipe"}
            if target:
                row["rate_per_h"] = 10.0**y
            out.append(row)
    return pd.DataFrame(out)


ROWS = RowSource(finished=_rows_of, candidates=lambda cases, done: _rows_of(cases, False),
                 features=("operation.rpm", "friction.mu_dynamic", "s_from_bit_m"),
                 categorical=("well.profile", "component_type"), target_column="rate_per_h",
                 floor_per_h=1e-12)


def _design(tmp_path: Path, cfg: SweepConfig, name: str = "cache", fail_after=None):
    target = _CachedTarget(tmp_path / name, fail_after)
    frame = adaptive_design(cfg, BASE, target, censor_log10=CENSOR, model=_Case, rows=ROWS)
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
    ({"acquisition": "widest"}, "sweep.adaptive.acquisition"),
    ({"space_filling_share": 1.5}, "sweep.adaptive.space_filling_share"),
])
def test_input_errors_name_the_field(block, field):
    with pytest.raises(InputError) as err:
        validate(Params, {"sweep": {"method": "adaptive", "n_cases": 16, "adaptive": block}})
    assert err.value.field == field


def test_unknown_acquisition_names_the_allowed_ones():
    with pytest.raises(InputError) as err:
        validate(Params, {"sweep": {"method": "adaptive", "n_cases": 16,
                                    "adaptive": {"acquisition": "widest"}}})
    assert all(a in err.value.allowed for a in ("governing", "rows", "mix"))
    with pytest.raises(InputError) as err:
        choose_batch("widest", np.zeros((3, 1)), np.zeros(3), np.zeros((0, 1)), 1, 1)
    assert err.value.field == "sweep.adaptive.acquisition"
    assert err.value.allowed == "governing, rows, mix"


def test_row_level_acquisition_needs_the_rows(tmp_path):
    with pytest.raises(InputError) as err:
        adaptive_design(_cfg(acquisition="rows"), BASE, _CachedTarget(tmp_path / "c"),
                        censor_log10=CENSOR, model=_Case)
    assert err.value.field == "sweep.adaptive.acquisition"


# --- row-level and mixed acquisitions -------------------------------------------------------


@pytest.mark.parametrize("acquisition", ["rows", "mix"])
def test_row_level_designs_are_seeded_and_resume(tmp_path, acquisition):
    whole, _ = _design(tmp_path, _cfg(acquisition=acquisition), "whole")
    assert len(whole) == 20 and whole["case_id"].is_unique
    again, _ = _design(tmp_path, _cfg(acquisition=acquisition), "again")
    pd.testing.assert_frame_equal(again, whole)
    with pytest.raises(KeyboardInterrupt):
        _design(tmp_path, _cfg(acquisition=acquisition), "resumed", fail_after=14)
    resumed, target = _design(tmp_path, _cfg(acquisition=acquisition), "resumed")
    pd.testing.assert_frame_equal(resumed, whole)
    assert target.evaluated == whole["case_id"].iloc[14:].tolist()
    # round 0 is the Sobol start whatever the acquisition; the rounds differ from governing's
    gov, _ = _design(tmp_path, _cfg(), "governing")
    assert whole["case_id"].iloc[:8].tolist() == gov["case_id"].iloc[:8].tolist()
    assert whole["case_id"].iloc[8:].tolist() != gov["case_id"].iloc[8:].tolist()


def test_row_level_batches_go_where_the_rows_are_disputed(tmp_path):
    """The collar rows' ridge (p3, rpm near 170) is where the members disagree: the rounds
    put more cases into p3 than its share (1/3) and, there, nearer the ridge than a uniform
    draw would (mean |rpm - 170| over rpm 60-180: (110^2 + 10^2) / 240 = 50.8). The members
    (at least 20 rows, 2 cases, per leaf) see the 8-rpm-wide ridge smeared over tens of rpm,
    so the bound is 3/4 of the uniform mean, not the governing target's sharper one."""
    frame, _ = _design(tmp_path, _cfg(acquisition="rows"), "ridge")
    added = frame[frame["round"] > 0]
    p3 = added["well.profile"] == "p3"
    assert p3.mean() > 1.0 / 3.0
    assert np.mean(np.abs(added["operation.rpm"][p3] - 170.0)) < 0.75 * 50.8


def test_row_scores_sum_the_rows_and_ignore_disputes_beyond_the_horizon():
    cases = design_cases(validate(SweepConfig, {"n_cases": 16, "seed": 1,
                                                "variables": VARIABLES}), BASE, model=_Case)
    rows = _rows_of(cases)
    levels = ROWS.levels(rows)
    x = row_matrix(rows, ROWS.features, ROWS.categorical, levels)
    assert x.shape == (160, 3 + 3 + 2)
    y, g = ROWS.log10_rate(rows), rows["case_id"].to_numpy()
    kw = {"n_members": 4, "seed": 2, "censor_log10": CENSOR}
    train = np.isin(g, cases["case_id"].iloc[:12])
    s = row_scores(x[train], y[train], g[train], x[~train], g[~train], **kw)
    assert s.index.tolist() == cases["case_id"].iloc[12:].tolist()
    assert np.all(s >= 0.0) and s.max() > 0.0
    # seeded: the same members, the same scores
    pd.testing.assert_series_equal(s, row_scores(x[train], y[train], g[train], x[~train],
                                                 g[~train], **kw))
    # the score of a case is the sum over its rows: a copy of a case's rows doubles it
    c0 = g[~train] == cases["case_id"].iloc[12]
    xd, gd = np.vstack([x[~train][c0], x[~train][c0]]), np.repeat("dup", 2 * c0.sum())
    sd = row_scores(x[train], y[train], g[train], np.vstack([x[~train], xd]),
                    np.concatenate([g[~train], gd]), **kw)
    assert sd["dup"] == pytest.approx(2.0 * s.iloc[0], rel=1e-12)
    # every rate beyond the horizon: the members may differ below it, the score is zero
    low = np.full_like(y, CENSOR - 2.0) - 0.1 * x[:, 0] / 180.0
    assert np.all(row_scores(x[train], low[train], g[train], x[~train], g[~train], **kw) == 0.0)


def test_space_filling_batch_is_max_min():
    # corners of the unit square and its centre; a design point at (0, 0)
    x = np.array([[0.5, 0.5], [1.0, 1.0], [0.0, 1.0], [1.0, 0.0], [0.1, 0.1]])
    pick = space_filling_batch(x, np.array([[0.0, 0.0]]), 3)
    assert pick.tolist() == [1, 2, 3]  # (1, 1) farthest; then (0, 1) before (1, 0): ties low
    assert space_filling_batch(x, np.array([[0.0, 0.0]]), 2, exclude=[1]).tolist() == [2, 3]
    assert space_filling_batch(x, np.empty((0, 2)), 1).tolist() == [0]


@pytest.mark.parametrize(("share", "n_space"), [(0.0, 0), (0.25, 2), (0.5, 4), (0.3, 2),
                                                (0.45, 4), (1.0, 8)])
def test_mix_takes_the_stated_share_space_filling(share, n_space):
    rng = np.random.default_rng(3)
    x_cand, x_design = rng.random((200, 3)), rng.random((10, 3))
    score = rng.random(200)
    pick = choose_batch("mix", x_cand, score, x_design, 8, 24, share)
    assert len(pick) == 8 and len(set(pick.tolist())) == 8
    disputed, spread = pick[:8 - n_space], pick[8 - n_space:]
    # the disputed part is the diversity rule's batch of that size ...
    if n_space < 8:
        assert disputed.tolist() == diverse_batch(x_cand, score, x_design, 8 - n_space,
                                                  24).tolist()
    # ... the rest max-min from the design and the disputed picks, disagreement ignored
    ref = np.vstack([x_design, x_cand[disputed]])
    assert spread.tolist() == space_filling_batch(x_cand, ref, n_space, disputed).tolist()
    if n_space:
        # the space-filling picks need not be among the 24 most disputed candidates
        top = set(np.argsort(-score)[:24].tolist())
        assert not set(spread.tolist()) <= top or n_space <= 2
    # governing and rows ignore the share: the diversity rule alone
    for acq in ("governing", "rows"):
        assert choose_batch(acq, x_cand, score, x_design, 8, 24, share).tolist() == \
            diverse_batch(x_cand, score, x_design, 8, 24).tolist()


def test_candidate_rows_take_the_hole_geometry_of_their_own_well():
    """A candidate's rows: the locations of the finished case of its profile nearest in bit
    MD, the MD moved by the bit difference, the geometry columns as the fatigue stage's
    (:func:`position_columns`) at the moved positions: exactly equal (same function)."""
    params = load_params(Path(__file__).parents[3] / "params.yaml")
    cfg = params.sweep.model_copy(update={"n_cases": 8, "method": "sobol"})
    cases = design_cases(cfg, base_case_from_params(params))
    variables = tuple(cfg.variables)
    s = np.array([1.0, 5.0, 40.0, 200.0])
    done_cases = cases.iloc[:4]
    parts = []
    for _, c in done_cases.iterrows():
        md = float(c["operation.bit_md_m"]) - s
        geo = position_columns(json.loads(c["case_json"]), md, s)
        parts.append(pd.DataFrame({"case_id": c["case_id"], "md_m": md, "s_from_bit_m": s,
                                   "location": "body", **{v: c[v] for v in variables},
                                   **geo}))
    done = pd.concat(parts, ignore_index=True)
    # a finished case as its own candidate: its rows come back unchanged
    back = template_rows(done_cases.iloc[:1], done, variables)
    pd.testing.assert_frame_equal(back[done.columns], done.iloc[:4], check_dtype=False)
    cand = template_rows(cases.iloc[4:], done, variables)
    for _, c in cases.iloc[4:].iterrows():
        rows = cand[cand["case_id"] == c["case_id"]]
        same = done_cases[done_cases["well.profile"] == c["well.profile"]]
        if not len(same):
            assert rows.empty  # no template of its profile: no rows, score zero
            continue
        # template MD (its bit - s) moved by (candidate's bit - template's bit)
        np.testing.assert_allclose(rows["s_from_bit_m"], s)
        np.testing.assert_allclose(rows["md_m"], float(c["operation.bit_md_m"]) - s,
                                   rtol=0, atol=1e-9)
        geo = position_columns(json.loads(c["case_json"]), rows["md_m"], rows["s_from_bit_m"])
        for col, v in geo.items():
            np.testing.assert_array_equal(rows[col].to_numpy(), np.asarray(v))
        assert (rows["operation.rpm"] == c["operation.rpm"]).all()
