"""Units of tables and plots: SI (default) or the engineer's field units (``--units field``).

Values stay SI inside; only what is shown is converted, here, once:

=========  ==========  ===========
quantity   si          field
=========  ==========  ===========
length     m           ft
force      kN          klbf
torque     kN m        kft lbf
dogleg     deg/30 m    deg/100 ft
speed      m/h         ft/h
diameter   mm          in
=========  ==========  ===========

Files written for other programs (CSV, JSON) stay SI with the unit in each
column name.
"""

from __future__ import annotations

from typing import overload

from dataclasses import dataclass

import numpy as np

from drillfatigue import units
from drillfatigue.errors import InputError

UNIT_SYSTEMS: tuple[str, ...] = ("si", "field")

#: system -> quantity -> (label, SI value per displayed unit)
_DISPLAY: dict[str, dict[str, tuple[str, float]]] = {
    "si": {"length": ("m", 1.0), "force": ("kN", units.KN_N), "torque": ("kN m", units.KNM_NM),
           "dogleg": ("deg/30m", 1.0), "speed": ("m/h", units.M_PER_H_M_PER_S),
           "diameter": ("mm", units.MM_M)},
    "field": {"length": ("ft", units.FT_M), "force": ("klbf", units.KLBF_N),
              "torque": ("kft lbf", units.KFT_LBF_NM),
              "dogleg": ("deg/100ft", units.DEG_PER_100FT_DEG_PER_30M),
              "speed": ("ft/h", units.FT_PER_H_M_PER_S), "diameter": ("in", units.INCH_M)},
}


def check_system(name: str, option: str = "--units") -> str:
    """``name`` lower-cased if it is a unit system; InputError otherwise."""
    s = name.strip().lower()
    if s not in UNIT_SYSTEMS:
        raise InputError(option, f"unknown unit system {name!r}", ", ".join(UNIT_SYSTEMS))
    return s


@dataclass(frozen=True)
class Display:
    """Converts SI values for display in one unit system.

    The SI "unit" of a dogleg is deg/30 m (the project's input unit), of a
    force kN, of a torque kN m: what an engineer reads, not base SI.
    """

    system: str = "si"

    def __post_init__(self) -> None:
        object.__setattr__(self, "system", check_system(self.system))

    def unit(self, quantity: str) -> str:
        """Label of ``quantity``'s display unit (``'ft'``, ``'klbf'``)."""
        return _DISPLAY[self.system][quantity][0]

    @overload
    def value(self, quantity: str, si: float) -> float: ...

    @overload
    def value(self, quantity: str, si: np.ndarray) -> np.ndarray: ...

    def value(self, quantity: str, si: float | np.ndarray) -> float | np.ndarray:
        """``si`` (m, N, N m, deg/30 m, m/s, m) in the display unit."""
        f = _DISPLAY[self.system][quantity][1]
        return np.asarray(si) / f if isinstance(si, np.ndarray) else float(si) / f

    def to_si(self, quantity: str, shown: float | np.ndarray) -> float | np.ndarray:
        """Inverse of :meth:`value`."""
        f = _DISPLAY[self.system][quantity][1]
        return np.asarray(shown) * f if isinstance(shown, np.ndarray) else float(shown) * f
