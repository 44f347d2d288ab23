"""Case design: reproducible, in bounds, typed variables, stable unique ids, early errors."""

from __future__ import annotations

import json
import warnings
from typing import Literal

import numpy as np
import pytest
from pydantic import Field

from drillfatigue.config import Params, SweepConfig, validate
from drillfatigue.config.base import StrictModel
from drillfatigue.errors import InputError
from drillfatigue.sweep.design import (
    apply_overrides,
    base_case_from_params,
    case_id_of,
    design_cases,
    read_cases,
    write_cases,
)


# A small stand-in for CaseConfig (the real sections are filled by their owners);
# design_cases validates against whatever model it is given.
class _Operation(StrictModel):
    rpm: float = Field(default=120.0, ge=0.0, le=400.0)
    duration_s: float = Field(default=10.0, gt=0.0)


class _Friction(StrictModel):
    mu_dynamic: float = Field(default=0.3, ge=0.0, le=1.0)


class _Bit(StrictModel):
    lobes: int = Field(default=3, ge=1, le=12)
    amplitude_m: float = Field(default=1e-3, ge=0.0, le=0.01)


class _Well(StrictModel):
    profile: Literal["p1", "p2", "p3"] = "p1"


class _Fatigue(StrictModel):
    scf: float = 1.0


class _Case(StrictModel):
    operation: _Operation = Field(default_factory=_Operation)
    friction: _Friction = Field(default_factory=_Friction)
    bit: _Bit = Field(default_factory=_Bit)
    well: _Well = Field(default_factory=_Well)
    fatigue: _Fatigue = Field(default_factory=_Fatigue)


BASE = _Case().model_dump(mode="json")
VARIABLES = {
    "operation.rpm": {"low": 60.0, "high": 180.0},
    "friction.mu_dynamic": {"low": 0.15, "high": 0.4},
    "bit.amplitude_m": {"low": 1e-4, "high": 1e-2, "scale": "log"},
    "bit.lobes": {"low": 1, "high": 4, "kind": "integer"},
    "well.profile": {"choices": ["p1", "p2", "p3"]},
}


def _cfg(**kw) -> SweepConfig:
    data = {"n_cases": 64, "seed": 7, "variables": VARIABLES} | kw
    return validate(SweepConfig, data, "sweep")


def _design(**kw):
    return design_cases(_cfg(**kw), BASE, model=_Case)


def test_same_seed_same_design_other_seed_differs():
    a, b, c = _design(), _design(), _design(seed=8)
    assert a.equals(b)
    assert not np.allclose(a["operation.rpm"], c["operation.rpm"])


def test_values_within_bounds_and_typed():
    d = _design()
    assert len(d) == 64
    assert d["operation.rpm"].between(60.0, 180.0).all()
    assert d["friction.mu_dynamic"].between(0.15, 0.4).all()
    assert d["bit.amplitude_m"].between(1e-4, 1e-2).all()
    # integer and categorical: only allowed values, and with 64 balanced Sobol
    # points every level appears (each level has >= 1/4 of the unit interval).
    assert set(d["bit.lobes"]) == {1, 2, 3, 4}
    assert all(isinstance(v, int | np.integer) for v in d["bit.lobes"])
    assert set(d["well.profile"]) == {"p1", "p2", "p3"}
    # the full case JSON carries the same values
    for _, row in d.iterrows():
        case = json.loads(row["case_json"])
        assert case["operation"]["rpm"] == row["operation.rpm"]
        assert case["well"]["profile"] == row["well.profile"]


def test_log_scale_is_uniform_in_log():
    d = _design(n_cases=256)
    logs = np.log10(d["bit.amplitude_m"].to_numpy())
    # uniform in log10 over [-4, -2]: each decade holds half the points; a Sobol
    # design of 256 points is balanced to within a few points per half.
    assert abs(np.mean(logs < -3.0) - 0.5) < 0.05


def test_ids_stable_unique_and_order_free():
    d = _design()
    assert d["case_id"].is_unique
    assert all(len(i) == 12 for i in d["case_id"])
    for _, row in d.iterrows():
        assert case_id_of(json.loads(row["case_json"])) == row["case_id"]
    # the id depends only on the inputs: a row reached by another seed/method
    # with the same inputs has the same id; key order does not matter.
    case = json.loads(d["case_json"].iloc[5])
    reordered = {k: case[k] for k in reversed(list(case))}
    assert case_id_of(reordered) == d["case_id"].iloc[5]
    # the fatigue section is applied to all cases later: not part of the id
    assert case_id_of(case | {"fatigue": {"scf": 2.0}}) == d["case_id"].iloc[5]
    assert case_id_of(apply_overrides(case, {"operation.rpm": 61.0})) != d["case_id"].iloc[5]


def test_identical_cases_are_merged():
    cfg = validate(SweepConfig, {"n_cases": 16, "variables": {"well.profile": {"choices": ["p1", "p2"]}}})
    with pytest.warns(UserWarning, match="merged"):
        d = design_cases(cfg, BASE, model=_Case)
    assert sorted(d["well.profile"]) == ["p1", "p2"]


def test_sobol_rounds_up_lhs_exact():
    with pytest.warns(UserWarning, match="rounded up to 8"):
        d = _design(n_cases=5)
    assert len(d) == 8
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        lhs = _design(n_cases=5, method="lhs")
    assert len(lhs) == 5
    assert lhs["operation.rpm"].between(60.0, 180.0).all()


def test_fixed_and_window_applied():
    d = _design(fixed={"friction.mu_dynamic": 0.25}, window_s=30.0,
                variables={"operation.rpm": {"low": 60, "high": 90}})
    cases = [json.loads(t) for t in d["case_json"]]
    assert all(c["operation"]["duration_s"] == 30.0 for c in cases)
    assert all(c["friction"]["mu_dynamic"] == 0.25 for c in cases)


@pytest.mark.parametrize(("variables", "field", "text"), [
    ({"operation.rpmm": {"low": 1, "high": 2}}, "sweep.variables.operation.rpmm", "unknown"),
    ({"operation.rpm": {"low": 60, "high": 1000}}, "sweep.variables.operation.rpm", "<= 400"),
    ({"bit.lobes": {"low": 0, "high": 3, "kind": "integer"}}, "sweep.variables.bit.lobes", ">= 1"),
    ({"well.profile": {"choices": ["p1", "p9"]}}, "sweep.variables.well.profile", "p9"),
])
def test_bad_variable_fails_before_sampling(variables, field, text, monkeypatch):
    import drillfatigue.sweep.design as design

    def no_sampling(*a, **k):  # the error must come before any sampling
        raise AssertionError("sampled before validating the variables")

    monkeypatch.setattr(design, "_unit_sample", no_sampling)
    with pytest.raises(InputError) as err:
        design_cases(_cfg(variables=variables), BASE, model=_Case)
    assert err.value.field == field
    assert text in str(err.value)


@pytest.mark.parametrize(("data", "field"), [
    ({"variables": {"operation.rpm": {"low": 2, "high": 1}}}, "sweep.variables.operation.rpm"),
    ({"variables": {"bit.amplitude_m": {"low": 0.0, "high": 1.0, "scale": "log"}}},
     "sweep.variables.bit.amplitude_m"),
    ({"variables": {"bit.lobes": {"low": 1.5, "high": 3, "kind": "integer"}}}, "sweep.variables.bit.lobes"),
    ({"variables": {"fatigue.scf": {"low": 1, "high": 2}}}, "sweep.variables"),
    ({"variables": {"rpm": {"low": 1, "high": 2}}}, "sweep.variables"),
    ({"variables": {"operation.rpm": {"choices": []}}}, "sweep.variables.operation.rpm"),
    ({"scheduler": "cluster"}, "sweep.scheduler"),
    ({"n_cases": 0}, "sweep.n_cases"),
    ({"failure_threshold": 1.5}, "sweep.failure_threshold"),
    ({"method": "grid"}, "sweep.method"),
])
def test_sweep_config_rejects_bad_values(data, field):
    with pytest.raises(InputError) as err:
        validate(SweepConfig, data, "sweep")
    assert err.value.field.startswith(field)
    assert "allowed" in str(err.value)


def test_scheduler_address_accepted():
    assert validate(SweepConfig, {"scheduler": "tcp://10.0.0.5:8786"}).scheduler == "tcp://10.0.0.5:8786"


def test_real_case_config_base_case(tmp_path):
    params = Params()
    d = design_cases(params.sweep.model_copy(update={"variables": {}}), base_case_from_params(params))
    assert len(d) == 1
    path = write_cases(d, tmp_path / "design" / "cases.parquet")
    back = read_cases(path)
    assert back["case_id"].tolist() == d["case_id"].tolist()
    assert json.loads(back["case_json"].iloc[0]) == json.loads(d["case_json"].iloc[0])


def test_read_cases_errors(tmp_path):
    with pytest.raises(InputError):
        read_cases(tmp_path / "missing.parquet")


def test_a_bad_variable_bound_in_a_rig_design_names_the_variable() -> None:
    """Rig boundaries: the fixed settings are validated on a probe case that carries the
    variables at an extreme; a bad bound is the variable's error, not the first fixed key's."""
    from pathlib import Path

    import yaml

    from drillfatigue.sweep.design import base_case_from_params, design_cases

    data = yaml.safe_load((Path(__file__).resolve().parents[3] / "params.yaml").read_text())
    assert data["sweep"]["boundaries"] == "rig" and data["sweep"]["fixed"]
    data["sweep"]["variables"]["operation.rpm"] = {"low": -500.0, "high": 80.0}
    params = Params.model_validate(data)
    with pytest.raises(InputError) as exc:
        design_cases(params.sweep, base_case_from_params(params))
    assert exc.value.field == "sweep.variables.operation.rpm"


def test_the_wob_set_point_moves_to_the_autodriller_and_is_refused_in_a_case() -> None:
    from drillfatigue.config import CaseConfig
    from drillfatigue.sweep.design import rig_case

    case = {"operation": {"wob_N": 90_000.0, "rpm": 120.0}}
    out = rig_case(case, {"block_mode": "autodriller", "autodriller": {"measurement": "wob"}})
    assert out["rig"]["autodriller"]["wob_set_N"] == 90_000.0
    assert out["operation"]["wob_N"] is None
    with pytest.raises(ValueError, match="operation.wob_N"):
        CaseConfig.model_validate({"operation": {"wob_N": 90_000.0}})


def test_optional_fields_not_given_leave_the_case_id_unchanged() -> None:
    from drillfatigue.sweep.design import case_id_of

    base = {"operation": {"rpm": 120.0}, "string": {"components": []}}
    with_none = {"operation": {"rpm": 120.0, "wob_N": None},
                 "string": {"components": [], "bha": None}}
    assert case_id_of(base) == case_id_of(with_none)
    assert case_id_of(base) != case_id_of({**with_none, "string": {"components": [],
                                                                     "bha": "slick"}})


def _params_yaml() -> dict:
    from pathlib import Path

    import yaml

    return yaml.safe_load((Path(__file__).resolve().parents[3] / "params.yaml").read_text())


def test_default_design_records_inside_every_case() -> None:
    """params.yaml's design passes the recording-window and bit-in-well checks."""
    params = Params.model_validate(_params_yaml())
    assert params.sweep.window_s > params.recording.start_s
    design_cases(params.sweep.model_copy(update={"n_cases": 4}), base_case_from_params(params))


def test_bit_depth_bound_beyond_the_wells_td_is_an_error() -> None:
    """A design whose bit can start below a well's TD used to pass and fail per case at
    simulation time; it is refused before sampling, naming the variable and the TD."""
    data = _params_yaml()
    data["sweep"]["variables"]["operation.bit_md_m"] = {"low": 560.0, "high": 5000.0}
    params = Params.model_validate(data)
    with pytest.raises(InputError) as exc:
        design_cases(params.sweep, base_case_from_params(params))
    assert exc.value.field == "sweep.variables.operation.bit_md_m"
    assert exc.value.problem.startswith("5000 m is beyond the total depth ")
    assert "the shallowest TD of the design's well profiles" in exc.value.allowed


def test_window_ending_before_the_record_starts_is_an_error() -> None:
    """sweep.window_s sets each case's duration: at or before recording.start_s no case
    would record anything (the runs completed without loads, fatigue then failed)."""
    data = _params_yaml()
    data["sweep"]["window_s"] = data["recording"]["start_s"]
    params = Params.model_validate(data)  # the file alone is fine: the sweep sets durations
    with pytest.raises(InputError) as exc:
        design_cases(params.sweep, base_case_from_params(params))
    assert exc.value.field == "sweep.window_s"
    assert "no case would record anything" in exc.value.problem
