"""drillfatigue.io.names, io.headers, io.display: unit spellings, exact round trips."""

from __future__ import annotations

import math
from fractions import Fraction

import numpy as np
import pytest

from drillfatigue import units
from drillfatigue.errors import InputError
from drillfatigue.io.display import Display, check_system
from drillfatigue.io.headers import (
    UNIT_SPELLINGS,
    exact_factor,
    field_text,
    si_from_text,
    split_header,
    unit_factor,
)
from drillfatigue.io.names import channel_stem, force_column


def _values() -> np.ndarray:
    rng = np.random.default_rng(7)
    return np.concatenate([rng.uniform(-1e5, 1e5, 300), rng.lognormal(0.0, 8.0, 300),
                           -rng.lognormal(0.0, 8.0, 100), [0.0, 1.0, 0.1, 1e-300, 5e-324]])


@pytest.mark.parametrize(("quantity", "unit"), [(q, u) for q, t in UNIT_SPELLINGS.items()
                                                for u in t if exact_factor(q, u, "x")])
def test_si_to_field_to_si_is_exact(quantity: str, unit: str) -> None:
    # every float (whose field value is itself finite) comes back bit for bit
    for v in _values():
        text = field_text(float(v), quantity, unit)
        assert si_from_text(text, quantity, unit, "x") == v, (v, text)


def test_only_radians_lack_an_exact_factor() -> None:
    inexact = {(q, u) for q, t in UNIT_SPELLINGS.items() for u in t
               if exact_factor(q, u, "x") is None}
    assert inexact == {("angle", "rad"), ("dogleg", "rad/m")}


def test_exact_fractions_match_the_float_factors() -> None:
    # each float constant is its exact fraction to within two units in the last
    # place (derived constants such as KSI_PA = 1000 PSI_PA carry the rounding
    # of their parts)
    for name, exact in units.EXACT.items():
        f = getattr(units, name)
        assert abs(Fraction(f) - exact) <= 2 * Fraction(math.ulp(f)), name


def test_published_factors() -> None:
    # NIST SP 811 (2008) App. B: ft = 0.3048 m, lbf = 4.4482216152605 N (exact definitions)
    assert units.EXACT["FT_M"] == Fraction(3048, 10000)
    assert units.EXACT["KLBF_N"] == Fraction("4448.2216152605")
    assert units.EXACT["KFT_LBF_NM"] == Fraction("4.4482216152605") * Fraction("304.8")
    # US survey foot 1200/3937 m; 1 deg/100 ft = 30/30.48 deg/30 m
    assert float(units.EXACT["US_SURVEY_FT_M"]) == pytest.approx(0.3048006096, rel=1e-10)
    assert units.EXACT["DEG_PER_100FT_DEG_PER_30M"] == Fraction(3000, 3048)


@pytest.mark.parametrize(("header", "name", "unit"), [
    ("MD (ft)", "md", "ft"), ("Measured Depth [usft]", "measured depth", "usft"),
    ("md_m", "md", "m"), ("Incl", "incl", None), ("DLS (°/100ft)", "dls", "°/100ft"),
    ("dls_deg_per_100ft", "dls", "deg/100ft"), ("SURF_RPM", "surf rpm", None),
    ("\ufeffHook Load (klbf)", "hook load", "klbf"), ("rop_m_per_h", "rop m per h", None),
])
def test_split_header(header: str, name: str, unit: str | None) -> None:
    assert split_header(header) == (name, unit)


@pytest.mark.parametrize(("quantity", "unit", "factor"), [
    ("length", "FT", units.FT_M), ("dogleg", "°/100 ft", units.DEG_PER_100FT_DEG_PER_30M),
    ("torque", "kft.lbf", units.KFT_LBF_NM), ("torque", "kN·m", units.KNM_NM),
    ("force", "klbf", units.KLBF_N), ("flow", "galUS/min", units.US_GPM_M3_PER_S),
    ("speed", "ft/hr", units.FT_PER_H_M_PER_S), ("density", "ppg", units.PPG_KG_PER_M3),
])
def test_unit_spellings(quantity: str, unit: str, factor: float) -> None:
    assert unit_factor(quantity, unit, "c") == factor


def test_unit_of_the_wrong_quantity_names_the_field() -> None:
    with pytest.raises(InputError) as exc:
        unit_factor("force", "ft", "log.las:HKLD")
    assert exc.value.field == "log.las:HKLD" and "not a force unit" in exc.value.problem


def test_channel_suffix_parsers() -> None:
    assert channel_stem("wob_kN") == "wob"
    assert channel_stem("surface_torque_kft_lbf") == "surface_torque"
    assert channel_stem("flow_rate_gpm") == "flow_rate"
    assert channel_stem("rpm") == "rpm"
    assert force_column(["rpm", "hook_load_klbf"], "hook_load") == ("hook_load_klbf",
                                                                    units.KLBF_N)
    assert force_column(["rpm"], "hook_load") is None


def test_display_units() -> None:
    f = Display("field")
    assert f.value("length", 0.3048) == 1.0
    assert f.value("force", units.KLBF_N) == 1.0
    assert f.value("dogleg", units.DEG_PER_100FT_DEG_PER_30M) == 1.0
    assert f.unit("torque") == "kft lbf" and Display().unit("torque") == "kN m"
    x = np.array([1.0, 2.5, 1000.0])
    # display -> SI -> display of decimal inputs: within one ulp (plots only)
    np.testing.assert_allclose(f.value("length", f.to_si("length", x)), x, rtol=2.3e-16)
    assert check_system(" Field ") == "field"
    with pytest.raises(InputError, match="si, field"):
        check_system("imperial")


def test_field_headers_to_vocabulary_names() -> None:
    from drillfatigue.io.names import Vocabulary, vocabulary_name

    v = Vocabulary(["operation.rpm", "operation.wob_N", "operation.rop_m_per_s",
                    "operation.mud_density_kg_per_m3", "local_dls_deg_per_30m", "md_m"],
                   ["component_type"])
    got = {h: vocabulary_name(h, v) for h in (
        "WOB (klbf)", "ROP (ft/h)", "Mud Density (ppg)", "RPM", "Local DLS (deg/100ft)",
        "MD [ft]", "Component Type", "wob_kN", "WOB (ft)", "Torque (kft.lbf)")}
    assert got == {"WOB (klbf)": "wob_klbf", "ROP (ft/h)": "rop_ft_per_h",
                   "Mud Density (ppg)": "mud_density_ppg", "RPM": "rpm",
                   "Local DLS (deg/100ft)": "local_dls_deg_per_100ft", "MD [ft]": "md_ft",
                   "Component Type": "component_type", "wob_kN": "wob_kN",
                   # no such name: left for the vocabulary's own one-line error
                   "WOB (ft)": "WOB (ft)", "Torque (kft.lbf)": "Torque (kft.lbf)"}
