"""Oilfield unit conversions: the only place unit factors are written.

Multiply a value in the unit named after the underscore-free prefix to get SI,
e.g. ``od_m = od_in * INCH_M``. Exact factors from NIST SP 811 (2008), App. B.
"""

from __future__ import annotations

import math
from fractions import Fraction
from typing import TYPE_CHECKING, TypeVar

if TYPE_CHECKING:
    import numpy as np

#: A float or an array of them.
_X = TypeVar("_X", float, "np.ndarray")

# --- physical constants and rotation speed ---
STANDARD_GRAVITY_M_PER_S2 = 9.80665  # standard gravity (exact, CGPM 1901)
RAD_S_PER_RPM = 2.0 * math.pi / 60.0  # (rad/s) per rpm
RPM_PER_RAD_S = 60.0 / (2.0 * math.pi)  # rpm per (rad/s)


def rad_per_s_from_rpm(rpm: _X) -> _X:
    """``rpm`` in rad/s, computed as ``rpm * 2 pi / 60`` in that order (the order the
    callers' results were recorded with; ``rpm * RAD_S_PER_RPM`` can differ in the
    last bit)."""
    return rpm * 2.0 * math.pi / 60.0


def rpm_from_rad_per_s(omega: _X) -> _X:
    """``omega`` (rad/s) in rpm, computed as ``omega * 30 / pi`` in that order."""
    return omega * 30.0 / math.pi


INCH_M = 0.0254  # m per inch (exact)
FT_M = 0.3048  # m per foot (exact)
LBF_N = 4.4482216152605  # N per pound-force
PSI_PA = 6894.757293168361  # Pa per psi
LB_PER_FT_KG_PER_M = 0.45359237 / 0.3048  # kg/m per lb/ft
LB_KG = 0.45359237  # kg per pound (exact)

# --- user-facing units at the surrogate query and twin boundary ---
KN_N = 1000.0  # N per kilonewton
KLBF_N = 1000.0 * LBF_N  # N per kilo-pound-force
MM_M = 1e-3  # m per millimetre
HOUR_S = 3600.0  # s per hour
M_PER_H_M_PER_S = 1.0 / HOUR_S  # (m/s) per (m/h)
FT_PER_H_M_PER_S = FT_M / HOUR_S  # (m/s) per (ft/h)
SG_KG_PER_M3 = 1000.0  # kg/m^3 per unit specific gravity (water = 1000 kg/m^3)
US_GAL_M3 = 231.0 * INCH_M**3  # m^3 per US gallon (exact, 231 in^3)
PPG_KG_PER_M3 = LB_KG / US_GAL_M3  # kg/m^3 per lb/US gal (mud weight)
DEG_PER_100FT_DEG_PER_30M = 30.0 / (100.0 * FT_M)  # (deg/30 m) per (deg/100 ft)

# --- fatigue (S-N curves are tabulated in MPa, API RP7G in psi) ---
MPA_PA = 1e6  # Pa per megapascal
KSI_PA = 1000.0 * PSI_PA  # Pa per ksi

# --- field data: rig logs, tallies, surveys (drillfatigue.io) ---
MINUTE_S = 60.0  # s per minute
MS_S = 1e-3  # s per millisecond
LBF_FT_NM = LBF_N * FT_M  # N m per ft lbf
KFT_LBF_NM = 1000.0 * LBF_FT_NM  # N m per kft lbf
KNM_NM = 1000.0  # N m per kN m
KPA_PA = 1000.0  # Pa per kPa
BAR_PA = 1e5  # Pa per bar (exact)
US_GPM_M3_PER_S = US_GAL_M3 / MINUTE_S  # (m^3/s) per US gal/min
L_PER_MIN_M3_PER_S = 1e-3 / MINUTE_S  # (m^3/s) per litre/min
BBL_M3 = 42.0 * US_GAL_M3  # m^3 per oil barrel (42 US gal, exact)
BBL_PER_MIN_M3_PER_S = BBL_M3 / MINUTE_S  # (m^3/s) per bbl/min
FT_PER_MIN_M_PER_S = FT_M / MINUTE_S  # (m/s) per ft/min
KDAN_N = 1e4  # N per kilodecanewton
TONNE_FORCE_N = 1000.0 * STANDARD_GRAVITY_M_PER_S2  # N per metric tonne-force (exact)
US_SURVEY_FT_M = 1200.0 / 3937.0  # m per US survey foot (exact by definition)
M_PER_MIN_M_PER_S = 1.0 / MINUTE_S  # (m/s) per m/min
M3_PER_MIN_M3_PER_S = 1.0 / MINUTE_S  # (m^3/s) per m^3/min
DEG_PER_100USFT_DEG_PER_30M = 30.0 / (100.0 * US_SURVEY_FT_M)  # (deg/30 m) per (deg/100 US ft)
DEG_PER_10M_DEG_PER_30M = 3.0  # (deg/30 m) per (deg/10 m)

# The factors above as exact fractions (each float above is its fraction to
# within two units in the last place), so that a value written in field units
# with enough digits reads back to the same SI bits
# (drillfatigue.io.headers.si_from_text / field_text).
_F = Fraction
_IN, _FT, _LBF, _LB = _F("0.0254"), _F("0.3048"), _F("4.4482216152605"), _F("0.45359237")
_GAL = 231 * _IN**3
_USFT = _F(1200, 3937)
EXACT: dict[str, Fraction] = {
    "INCH_M": _IN, "FT_M": _FT, "LBF_N": _LBF, "PSI_PA": _LBF / _IN**2,
    "LB_PER_FT_KG_PER_M": _LB / _FT, "LB_KG": _LB, "KN_N": _F(1000), "KLBF_N": 1000 * _LBF,
    "MM_M": _F(1, 1000), "HOUR_S": _F(3600), "M_PER_H_M_PER_S": _F(1, 3600),
    "FT_PER_H_M_PER_S": _FT / 3600, "SG_KG_PER_M3": _F(1000), "US_GAL_M3": _GAL,
    "PPG_KG_PER_M3": _LB / _GAL, "DEG_PER_100FT_DEG_PER_30M": 30 / (100 * _FT),
    "MPA_PA": _F(10**6), "KSI_PA": 1000 * _LBF / _IN**2, "MINUTE_S": _F(60),
    "MS_S": _F(1, 1000), "LBF_FT_NM": _LBF * _FT, "KFT_LBF_NM": 1000 * _LBF * _FT,
    "KNM_NM": _F(1000), "KPA_PA": _F(1000), "BAR_PA": _F(10**5),
    "US_GPM_M3_PER_S": _GAL / 60, "L_PER_MIN_M3_PER_S": _F(1, 60000), "BBL_M3": 42 * _GAL,
    "BBL_PER_MIN_M3_PER_S": 42 * _GAL / 60, "FT_PER_MIN_M_PER_S": _FT / 60,
    "KDAN_N": _F(10**4), "TONNE_FORCE_N": _F("9806.65"), "US_SURVEY_FT_M": _USFT,
    "M_PER_MIN_M_PER_S": _F(1, 60), "M3_PER_MIN_M3_PER_S": _F(1, 60),
    "DEG_PER_100USFT_DEG_PER_30M": 30 / (100 * _USFT), "DEG_PER_10M_DEG_PER_30M": _F(3),
}
