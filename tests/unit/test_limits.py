"""Physical input bounds (:mod:`drillfatigue.limits`): what no rig or well can have is an
input error naming the field and the allowed range, before any work is done."""

from __future__ import annotations

import os
import re
from pathlib import Path

import numpy as np
import pytest

from drillfatigue.cli import main
from drillfatigue.config import case_from_dict, load_case, load_params
from drillfatigue.config.bit import BitConfig
from drillfatigue.config.operation import OperationConfig
from drillfatigue.config.rig import AutodrillerConfig
from drillfatigue.config.well import TortuosityConfig
from drillfatigue.dynamics.run.simulation import simulate
from drillfatigue.dynamics.run.model import straight_path
from drillfatigue.errors import InputError
from drillfatigue.limits import (FEATURE_BOUNDS, MD_MAX_M, RPM_MAX, check_feature_values,
                                 check_recording_rates, check_value, feature_bound)

ROOT = Path(__file__).resolve().parents[2]
CASES = ROOT / "data" / "cases"
STRING = {"components": [
    {"type": "collar", "od_m": 0.17145, "id_m": 0.0714, "length_m": 20.0, "n_segments": 2},
    {"type": "drill_pipe", "od_m": 0.127, "id_m": 0.1086, "length_m": 40.0, "n_segments": 4}]}


def _documented_bounds() -> dict[str, tuple[float, float]]:
    """``{name: (lowest, highest)}`` of the bounds table in docs/trust.md."""
    text = (Path(__file__).resolve().parents[2] / "docs" / "trust.md").read_text()
    section = text.split("## Physical input bounds", 1)[1].split("\n## ", 1)[0]
    out: dict[str, tuple[float, float]] = {}
    for line in section.splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if len(cells) < 4 or not cells[0].startswith("`"):
            continue
        for name in re.findall(r"`(\w+)`", cells[0]):
            assert name not in out, f"{name} listed twice"
            out[name] = (float(cells[1]), float(cells[2]))
    return out


def test_bounds_match_the_documented_values() -> None:
    """docs/trust.md lists every bound of the code with its numbers, and no other."""
    assert RPM_MAX == 1000.0 and MD_MAX_M == 20000.0
    assert (FEATURE_BOUNDS["rpm"].lo, FEATURE_BOUNDS["rpm"].hi) == (0.0, 1000.0)
    assert FEATURE_BOUNDS["mud_density_kg_per_m3"].lo == 0.0
    documented = _documented_bounds()
    assert sorted(documented) == sorted(FEATURE_BOUNDS)
    for name, bound in FEATURE_BOUNDS.items():
        assert documented[name] == (bound.lo, bound.hi), name


def test_every_model_input_has_a_bound() -> None:
    """Every numeric surrogate feature of params.yaml (and the design inputs the sweep
    varies) is checked against a physical bound, so no entry point lets an impossible
    value through to a number."""
    params = load_params(ROOT / "params.yaml")
    for column in params.surrogate.features:
        assert feature_bound(column) is not None, column
    for column in params.sweep.variables:
        if column in ("well.profile", "string.bha"):
            continue  # categories
        assert feature_bound(column) is not None, column
    for column in ("operation.wob_N", "bit.rop_c1_m_per_N_sqrt_s",
                   "operation.lobe_amplitude_m", "rig.autodriller.wob_set_N"):
        assert feature_bound(column) is not None, column


@pytest.mark.parametrize("model, field, name", [
    (OperationConfig, "lobe_amplitude_m", "lobe_amplitude_m"),
    (OperationConfig, "lobe_count", "lobe_count"),
    (OperationConfig, "mud_density_kg_per_m3", "mud_density_kg_per_m3"),
    (OperationConfig, "rop_m_per_s", "rop_m_per_s"),
    (OperationConfig, "bit_md_m", "bit_md_m"),
    (BitConfig, "rop_c1_m_per_N_sqrt_s", "rop_c1_m_per_N_sqrt_s"),
    (OperationConfig, "wob_N", "wob_N"),
    (AutodrillerConfig, "wob_set_N", "wob_set_N"),
    (TortuosityConfig, "amplitude_deg", "tortuosity_amplitude_deg"),
    (TortuosityConfig, "period_m", "tortuosity_period_m"),
])
def test_simulator_fields_use_the_same_bounds(model: type, field: str, name: str) -> None:
    """A simulator field of the same quantity has the table's range (one rule)."""
    lo = hi = None
    for m in model.model_fields[field].metadata:
        lo = getattr(m, "ge", None) if getattr(m, "ge", None) is not None else (
            getattr(m, "gt", None) if getattr(m, "gt", None) is not None else lo)
        hi = getattr(m, "le", None) if getattr(m, "le", None) is not None else hi
    assert (lo, hi) == (FEATURE_BOUNDS[name].lo, FEATURE_BOUNDS[name].hi)


def test_drillability_bound() -> None:
    """bit.rop_c1_m_per_N_sqrt_s: 0 <= c1 <= 1e-6 in the configuration as in the table."""
    with pytest.raises(InputError, match=r"bit\.rop_c1_m_per_N_sqrt_s"):
        case_from_dict({"string": STRING, "bit": {"rop_c1_m_per_N_sqrt_s": 2e-6}})
    case_from_dict({"string": STRING, "bit": {"rop_c1_m_per_N_sqrt_s": 1e-6}})
    with pytest.raises(InputError) as e:
        check_value("--set", "bit.rop_c1_m_per_N_sqrt_s", -1e-9)
    assert str(e.value) == ("--set: -1e-09 is outside the physical range "
                            "(allowed: 0 <= rop_c1_m_per_N_sqrt_s <= 1e-06)")


def test_bound_message_in_user_units() -> None:
    with pytest.raises(InputError) as e:
        check_feature_values("wob_klbf", "operation.wob_N", np.array([10e3, 2e6]), 4448.2216152605)
    assert e.value.field == "wob_klbf"
    assert "(row 2)" in e.value.problem
    assert e.value.allowed == "0 <= wob_klbf <= 224.809"
    check_feature_values("rpm", "operation.rpm", [0.0, 1000.0])  # both ends allowed
    check_feature_values("x", "some.unbounded_column", [-1e300])  # no bound, no error


def test_simulate_bit_below_td_is_an_input_error() -> None:
    cfg = case_from_dict({"string": STRING, "operation": {"bit_md_m": 150.0}})
    with pytest.raises(InputError, match=r"operation\.bit_md_m: 150 m is beyond the well's "
                                         r"total depth 100 m"):
        simulate(cfg, None, progress=False, path=straight_path(100.0))


def test_recording_rate_above_the_integrator_rate_is_an_input_error() -> None:
    cfg = case_from_dict({"string": STRING, "operation": {"bit_md_m": 60.0},
                          "recording": {"channels_rate_hz": 50000.0}})
    with pytest.raises(InputError) as e:
        simulate(cfg, None, progress=False, path=straight_path(100.0))
    assert e.value.field == "recording.channels_rate_hz"
    assert e.value.allowed.startswith("<= ") and "integrator rate" in e.value.allowed
    top = float(e.value.allowed.split()[1])
    assert 100.0 < top < 50000.0
    # the named rate is accepted, a rate just above it is not
    check_recording_rates(cfg.recording.model_copy(update={"channels_rate_hz": top}),
                          1.0 / (top + 1e-3))
    with pytest.raises(InputError):
        check_recording_rates(cfg.recording.model_copy(update={"loads_rate_hz": 1001.0}), 1e-3)


def test_cli_simulate_bit_below_td_writes_nothing(tmp_path, monkeypatch, capsys) -> None:
    text = (CASES / "vertical_quick.yaml").read_text().replace("bit_md_m: 300.0",
                                                              "bit_md_m: 500.0")
    (tmp_path / "case.yaml").write_text(text)
    monkeypatch.chdir(tmp_path)
    assert main(["simulate", "case.yaml", "--out", "run", "--no-progress"]) == 2
    err = capsys.readouterr().err
    assert err == ("error: operation.bit_md_m: 500 m is beyond the well's total depth 400 m "
                   "(allowed: 0 < bit_md_m <= 400 (the TD of the well profile))\n")
    assert sorted(os.listdir(tmp_path)) == ["case.yaml"]


def test_reference_cases_are_within_bounds() -> None:
    """Every shipped case starts its bit inside its well (the check rejects none of them)."""
    from drillfatigue.dynamics.run.simulation import _wellpath

    for f in sorted(CASES.glob("*.yaml")):
        cfg = load_case(f)
        assert cfg.operation.bit_md_m <= _wellpath(cfg).node_md_m[-1], f.name


def test_record_starting_at_or_after_the_end_is_a_case_error(tmp_path, monkeypatch,
                                                            capsys) -> None:
    """recording.start_s >= operation.duration_s used to run to completion with no loads
    (and `fatigue` then failed on the missing file)."""
    with pytest.raises(InputError) as e:
        case_from_dict({"string": STRING, "operation": {"bit_md_m": 60.0, "duration_s": 5.0},
                        "recording": {"start_s": 5.0}})
    assert e.value.field == "recording.start_s"
    assert str(e.value).endswith("(allowed: 0 <= start_s < operation.duration_s)")
    case_from_dict({"string": STRING, "operation": {"bit_md_m": 60.0, "duration_s": 5.0},
                    "recording": {"start_s": 4.9}})
    case = load_case(CASES / "vertical_quick.yaml")
    data = case.model_dump(mode="json")
    data["recording"]["start_s"] = data["operation"]["duration_s"] + 1.0
    import yaml

    (tmp_path / "case.yaml").write_text(yaml.safe_dump(data))
    monkeypatch.chdir(tmp_path)
    assert main(["simulate", "case.yaml", "--out", "run", "--no-progress"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("error: recording.start_s: ") and err.count("\n") == 1
    assert sorted(os.listdir(tmp_path)) == ["case.yaml"]
