"""Oilfield unit conversions: the only place unit factors are written.

Multiply a value in the unit named after the underscore-free prefix to get SI,
e.g. ``od_m = od_in * INCH_M``. Exact factors from NIST SP 811 (2008), App. B.
"""

from __future__ import annotations

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
