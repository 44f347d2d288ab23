"""Unit spellings of file headers, LAS/WITSML unit fields and exact field-unit text.

``MD (ft)``, ``HKLD [klbf]``, ``md_m``: :func:`split_header` separates the
name and the unit, :func:`unit_factor` turns the unit into a factor to SI
for a quantity (length, force, torque, ...; :data:`UNIT_SPELLINGS`). Every
factor comes from :mod:`drillfatigue.units`; :func:`si_from_text` and
:func:`field_text` use the exact fractions of ``units.EXACT`` so that a value
written in a field unit reads back to the same SI float.
"""

from __future__ import annotations

import math
from decimal import Decimal, localcontext
from fractions import Fraction

from drillfatigue import units
from drillfatigue.errors import InputError

#: Unit spellings of file headers and WITSML/LAS unit fields, per quantity:
#: normalised spelling (lower case, no blanks, ``°`` -> ``deg``) -> factor to SI.
#: SI units of the quantities: length m, angle deg (the project's input angle
#: unit), dogleg deg/30m, force N, torque N m, speed m/s, rotary speed rpm,
#: pressure Pa, flow m^3/s, time s, density kg/m^3.
UNIT_SPELLINGS: dict[str, dict[str, float]] = {
    "length": {"m": 1.0, "meter": 1.0, "meters": 1.0, "metre": 1.0, "metres": 1.0,
               "ft": units.FT_M, "feet": units.FT_M, "foot": units.FT_M, "ft(intl)": units.FT_M,
               "usft": units.US_SURVEY_FT_M, "ftus": units.US_SURVEY_FT_M,
               "ft[us]": units.US_SURVEY_FT_M, "in": units.INCH_M, "inch": units.INCH_M,
               "mm": units.MM_M},
    "angle": {"deg": 1.0, "dega": 1.0, "degree": 1.0, "degrees": 1.0, "rad": 180.0 / math.pi},
    "dogleg": {"deg/30m": 1.0, "dega/30m": 1.0, "deg/100ft": units.DEG_PER_100FT_DEG_PER_30M,
               "dega/100ft": units.DEG_PER_100FT_DEG_PER_30M,
               "deg/100usft": units.DEG_PER_100USFT_DEG_PER_30M,
               "deg/10m": units.DEG_PER_10M_DEG_PER_30M,
               "dega/10m": units.DEG_PER_10M_DEG_PER_30M, "rad/m": 30.0 * 180.0 / math.pi},
    "force": {"n": 1.0, "kn": units.KN_N, "klbf": units.KLBF_N, "kip": units.KLBF_N,
              "lbf": units.LBF_N, "kdan": units.KDAN_N, "tf": units.TONNE_FORCE_N},
    "torque": {"n.m": 1.0, "nm": 1.0, "kn.m": units.KNM_NM, "knm": units.KNM_NM,
               "kft.lbf": units.KFT_LBF_NM, "kftlbf": units.KFT_LBF_NM,
               "kft-lbf": units.KFT_LBF_NM, "kft.lb": units.KFT_LBF_NM,
               "ft.lbf": units.LBF_FT_NM, "ftlbf": units.LBF_FT_NM, "ft-lbf": units.LBF_FT_NM,
               "ft.lb": units.LBF_FT_NM, "lbf.ft": units.LBF_FT_NM},
    "speed": {"m/s": 1.0, "m/h": units.M_PER_H_M_PER_S, "m/hr": units.M_PER_H_M_PER_S,
              "ft/h": units.FT_PER_H_M_PER_S, "ft/hr": units.FT_PER_H_M_PER_S,
              "ft/min": units.FT_PER_MIN_M_PER_S, "m/min": units.M_PER_MIN_M_PER_S},
    "rotary_speed": {"rpm": 1.0, "1/min": 1.0, "c/min": 1.0, "rev/min": 1.0},
    "pressure": {"pa": 1.0, "kpa": units.KPA_PA, "mpa": units.MPA_PA, "psi": units.PSI_PA,
                 "bar": units.BAR_PA},
    "flow": {"m3/s": 1.0, "m3/min": units.M3_PER_MIN_M3_PER_S, "l/min": units.L_PER_MIN_M3_PER_S,
             "lpm": units.L_PER_MIN_M3_PER_S, "gpm": units.US_GPM_M3_PER_S,
             "galus/min": units.US_GPM_M3_PER_S, "bbl/min": units.BBL_PER_MIN_M3_PER_S},
    "time": {"s": 1.0, "sec": 1.0, "ms": units.MS_S, "min": units.MINUTE_S,
             "h": units.HOUR_S, "hr": units.HOUR_S},
    "density": {"kg/m3": 1.0, "sg": units.SG_KG_PER_M3, "g/cm3": units.SG_KG_PER_M3,
                "ppg": units.PPG_KG_PER_M3, "lbm/galus": units.PPG_KG_PER_M3},
}


def normalise_unit(unit: str) -> str:
    """``'°/100 ft'`` -> ``'deg/100ft'``: lower case, no blanks, degree sign spelled out."""
    u = unit.strip().lower().replace("°", "deg").replace(" ", "").replace("·", ".")
    u = u.replace("^", "").replace("³", "3").replace("hour", "h")
    return u


def unit_factor(quantity: str, unit: str, field: str) -> float:
    """Factor to SI of ``unit`` for ``quantity``; InputError naming ``field`` otherwise."""
    table = UNIT_SPELLINGS[quantity]
    f = table.get(normalise_unit(unit))
    if f is None:
        shown = sorted({k for k in table if "(" not in k})
        raise InputError(field, f"unit {unit!r} is not a {quantity.replace('_', ' ')} unit",
                         ", ".join(shown))
    return f


def split_header(text: str) -> tuple[str, str | None]:
    """A column header as (normalised name, unit or None).

    ``'MD (ft)'``, ``'MD [ft]'``, ``'Measured Depth(usft)'`` give the unit in
    brackets; ``'md_ft'`` a trailing unit suffix (``_m``, ``_ft``, ``_deg``,
    ...). The name is lower case with runs of blanks, ``_`` and ``-`` turned
    into one blank (``'Measured_Depth'`` -> ``'measured depth'``).
    """
    raw = text.strip().lstrip("\ufeff")
    unit: str | None = None
    for a, b in (("(", ")"), ("[", "]")):
        if raw.endswith(b) and a in raw:
            i = raw.rindex(a)
            unit, raw = raw[i + 1:-1].strip(), raw[:i]
            break
    name = " ".join(raw.replace("_", " ").replace("-", " ").lower().split())
    if unit is None:
        for suffix in _HEADER_SUFFIXES:
            if name.endswith(" " + suffix):
                name, unit = name[: -len(suffix) - 1], _HEADER_SUFFIXES[suffix]
                break
    return name, (unit or None)


#: Trailing words of snake_case headers that are units (``md_ft``, ``dls_deg_per_100ft``).
_HEADER_SUFFIXES: dict[str, str] = {
    "m": "m", "ft": "ft", "usft": "usft", "deg": "deg", "rad": "rad",
    "deg per 30m": "deg/30m", "deg per 100ft": "deg/100ft",
}


#: Exact value of each factor of :data:`UNIT_SPELLINGS` that has one (all but radians).
_EXACT_OF: dict[float, Fraction] = {1.0: Fraction(1)} | {
    getattr(units, name): value for name, value in units.EXACT.items()}


def exact_factor(quantity: str, unit: str, field: str) -> Fraction | None:
    """The exact factor to SI of ``unit`` (None for units without one, e.g. ``rad``)."""
    return _EXACT_OF.get(unit_factor(quantity, unit, field))


def si_from_text(text: str, quantity: str, unit: str, field: str) -> float:
    """SI value of a number written in ``unit``: the exact product, correctly rounded.

    Raises InputError naming ``field`` for a non-numeric or non-finite cell.
    """
    t = text.strip()
    try:
        v = float(t)
    except ValueError:
        raise InputError(field, f"not a number: {text!r}", "a finite number") from None
    if not math.isfinite(v):
        raise InputError(field, f"{text!r} is not finite", "a finite number")
    f = exact_factor(quantity, unit, field)
    if f is None:
        return v * unit_factor(quantity, unit, field)
    return float(Fraction(t) * f)


#: Significant digits of :func:`field_text`: the written value is within
#: 5e-21 relative of the exact quotient, far below half an ulp (1.1e-16), so
#: :func:`si_from_text` rounds it back to the same float.
FIELD_TEXT_DIGITS = 21


def field_text(value_si: float, quantity: str, unit: str, field: str = "value") -> str:
    """``value_si`` written in ``unit`` so that :func:`si_from_text` returns it bit for bit."""
    f = exact_factor(quantity, unit, field)
    if f is None:
        return repr(value_si / unit_factor(quantity, unit, field))
    q = Fraction(value_si) / f
    with localcontext() as ctx:
        ctx.prec = FIELD_TEXT_DIGITS
        d = Decimal(q.numerator) / Decimal(q.denominator)
    return format(d.normalize(), "f") if d == d.to_integral_value() else str(d)
