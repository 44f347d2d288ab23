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
