"""Physical input bounds: values no rig, string or well can have.

A value outside these bounds is an input error (the one-line
:class:`~drillfatigue.errors.InputError` naming the field and the allowed
range). A value inside them but outside the data a surrogate was trained on
is not an input error: the surrogate refuses it with its own out-of-domain
answer, naming the variable and the range it was trained on
(:mod:`drillfatigue.surrogate.ood`). The bounds are wide on
purpose; they catch typing slips, sign errors and unit mix-ups (a depth in
feet given as metres beyond any well, an rpm of 1e9), not unusual operations.
Each bound and its reason is listed in ``docs/trust.md``.

All values SI except where the name says otherwise.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from drillfatigue.errors import InputError

#: Deepest measured depth accepted, m. The longest wells drilled are about
#: 15 km measured depth (extended-reach wells off Sakhalin and in Qatar); 20 km
#: leaves margin and equals the upper bound of ``operation.bit_md_m``.
MD_MAX_M = 20_000.0

#: Highest rotary speed accepted, rpm. Top drives turn the string at up to
#: about 250-300 rpm; a mud motor or turbine adds up to several hundred rpm at
#: the bit; no drilling system turns faster than 1000 rpm.
RPM_MAX = 1000.0


@dataclass(frozen=True)
class Bound:
    """Closed physical range ``lo <= value <= hi`` of one quantity (SI) and its reason."""

    lo: float
    hi: float
    reason: str

    def text(self, name: str, factor: float = 1.0) -> str:
        """``"0 <= rpm <= 1000"`` in the unit of ``name`` (``factor``: that unit to SI)."""
        return f"{_num(self.lo / factor)} <= {name} <= {_num(self.hi / factor)}"


def _num(v: float) -> str:
    return f"{v:.6g}"


#: Bounds of surrogate features and operating-log channels, by the last part of
#: the SI column name (``operation.rpm`` -> ``rpm``). Rotation is clockwise
#: seen from above (positive rpm): turning a right-hand-threaded string
#: backwards unscrews its connections, so a negative drilling rpm is an error.
FEATURE_BOUNDS: dict[str, Bound] = {
    "rpm": Bound(0.0, RPM_MAX, "string rotation: 0 (sliding) up to top drive plus motor "
                              "speed; negative would back off the connections"),
    "wob_N": Bound(0.0, 1.0e6, "weight on bit is a compression >= 0; 1000 kN (225 klbf) is "
                               "above the rating of the largest bits"),
    "wob_set_N": Bound(0.0, 1.0e6, "as wob_N: the autodriller's set-point"),
    "rop_m_per_s": Bound(0.0, 1.0, "rate of penetration >= 0; 1 m/s (3600 m/h) is an order of "
                                   "magnitude above the fastest top-hole drilling"),
    "mu_static": Bound(0.0, 1.5, "friction coefficients of steel on rock or casing in mud are "
                                 "0.1-0.6; the simulator accepts up to 1.5"),
    "mu_dynamic": Bound(0.0, 1.5, "as mu_static"),
    "mud_density_kg_per_m3": Bound(0.0, 3000.0, "from air or foam (about 0) to the heaviest "
                                                 "weighted muds (about 2.6 sg); negative is "
                                                 "impossible"),
    "lobe_amplitude_m": Bound(0.0, 0.05, "axial amplitude of the lobed bottom-hole pattern "
                                         "under the bit: >= 0; 50 mm is above any bit's "
                                         "bounce (the simulator's own limit)"),
    "amplitude_m": Bound(0.0, 0.05, "as lobe_amplitude_m"),
    "lobe_count": Bound(0.0, 20.0, "lobes of the bottom-hole pattern (a roller-cone bit "
                                   "makes 3); the simulator's own limit"),
    "lobes": Bound(0.0, 20.0, "as lobe_count"),
    "kop_m": Bound(0.0, MD_MAX_M, "a kick-off point lies within the deepest well"),
    "dls_deg_per_30m": Bound(0.0, 60.0, "dogleg severity >= 0; above 60 deg/30 m no drill "
                                        "string passes (the well profiles' limit)"),
    "local_dls_deg_per_30m": Bound(0.0, 60.0, "as dls_deg_per_30m"),
    "local_max_dls_deg_per_30m": Bound(0.0, 60.0, "as dls_deg_per_30m"),
    "bit_dls_deg_per_30m": Bound(0.0, 60.0, "as dls_deg_per_30m"),
    "build_to_bit_deg_per_30m": Bound(-60.0, 60.0, "a mean build (or drop, < 0) rate between "
                                                   "two points of the hole: within the "
                                                   "largest dogleg severity"),
    "inc_deg": Bound(0.0, 180.0, "hole inclination: 0 (vertical, down) to 180 (straight "
                                 "up); horizontal is 90"),
    "local_inc_deg": Bound(0.0, 180.0, "as inc_deg"),
    "bit_inc_deg": Bound(0.0, 180.0, "as inc_deg"),
    "md_m": Bound(0.0, MD_MAX_M, "measured depth of a location in the hole: 0 at the rig "
                                 "floor, at most the deepest well"),
    "s_from_bit_m": Bound(0.0, MD_MAX_M, "distance behind the bit along the string: >= 0, "
                                         "at most the longest string"),
    "bit_md_m": Bound(0.0, MD_MAX_M, "measured depth of the bit, at most the deepest well"),
    "od_m": Bound(0.025, 1.0, "outside diameter of a string item (tally OD): the thinnest "
                              "string, 1 in coiled tubing, is 25.4 mm; 1 m is above the "
                              "largest hole openers (the string model's limit)"),
    "tool_joint_od_m": Bound(0.025, 1.0, "as od_m"),
    "hook_load_N": Bound(0.0, 1.5e7, "the hook carries the string: >= 0; 15 MN (1500 t) is "
                                     "above the largest rigs' hoisting rating"),
    "off_bottom_hook_load_N": Bound(0.0, 1.5e7, "as hook_load_N"),
    "tortuosity_amplitude_deg": Bound(0.0, 10.0, "angular amplitude of the micro-doglegs "
                                                  "added to a plan (well.tortuosity): >= 0; "
                                                  "high-resolution surveys show tenths of a "
                                                  "degree to a few degrees, a larger tilt is a "
                                                  "feature of the plan"),
    "tortuosity_period_m": Bound(1.0, 1000.0, "length of one micro-dogleg wave "
                                              "(well.tortuosity): spiralled holes repeat every "
                                              "1-10 m, slide-rotate cycles every 10-100 m; "
                                              "a longer wave is a feature of the plan"),
    "rop_c1_m_per_N_sqrt_s": Bound(0.0, 1.0e-6, "drillability c1 of the bit law ROP = c1 WOB "
                                                "sqrt(Omega) + c2: >= 0; 1e-6 gives 1400 m/h at "
                                                "100 kN and 150 rpm, far above any rock"),
}


def feature_bound(column: str) -> Bound | None:
    """The physical bound of a surrogate column (``operation.rpm``), or None."""
    return FEATURE_BOUNDS.get(column.rsplit(".", 1)[-1])


def first_outside(column: str, values_si: np.ndarray | Sequence[float]) -> int | None:
    """Index of the first value of ``column`` (SI) outside its physical bound, or None."""
    bound = feature_bound(column)
    if bound is None:
        return None
    v = np.asarray(values_si, dtype=np.float64).reshape(-1)
    bad = ~((v >= bound.lo) & (v <= bound.hi))
    return int(np.argmax(bad)) if bad.any() else None


def check_feature_values(name: str, column: str, values_si: np.ndarray | Sequence[float],
                         factor: float = 1.0, *, field: str | None = None,
                         rows: bool | None = None, first_row: int = 1) -> None:
    """Raise InputError if a value of ``column`` (SI) lies outside its physical bound.

    ``name`` is what the user called the column (``rpm``, ``wob_kN``) and
    ``factor`` that unit's factor to SI; the message states the value and the
    allowed range in the user's unit: ``wob_kN: -5 is outside the physical
    range (row 2) (allowed: 0 <= wob_kN <= 1000)``.

    Parameters
    ----------
    field : str, optional
        The error's field (default ``name``), e.g. ``--x`` or ``rows[3].rpm``.
    rows : bool, optional
        Name the row of the first bad value (default: when more than one value
        is given). Rows count data rows from ``first_row`` (1: the first row
        after a table's header).
    """
    bound = feature_bound(column)
    if bound is None:
        return
    v = np.asarray(values_si, dtype=np.float64).reshape(-1)
    bad = ~((v >= bound.lo) & (v <= bound.hi))
    if bad.any():
        i = int(np.argmax(bad))
        named = v.size > 1 if rows is None else rows
        where = f" (row {i + first_row})" if named else ""
        raise InputError(field or name,
                         f"{_num(v[i] / factor)} is outside the physical range{where}",
                         bound.text(name, factor))


def check_value(field: str, column: str, value_si: float, name: str | None = None,
                factor: float = 1.0) -> None:
    """One value (a command-line option, a ``--set`` constant) against its bound.

    ``field`` names the option (``--rpm``), ``name`` the quantity in the
    user's unit (default: the last part of ``column``).
    """
    check_feature_values(name or column.rsplit(".", 1)[-1], column, [value_si], factor,
                         field=field, rows=False)


def check_recording_rates(recording: Any, dt_s: float) -> None:
    """Raise InputError if a recording rate exceeds the integrator rate ``1 / dt_s``.

    The recorder stores every k-th step, k >= 1; a faster rate cannot be
    recorded (it used to be clamped silently to one sample per step).
    """
    top = 1.0 / dt_s
    for field in ("loads_rate_hz", "channels_rate_hz", "kinematics_rate_hz"):
        rate = float(getattr(recording, field))
        if rate > top * (1.0 + 1e-9):
            raise InputError(f"recording.{field}", f"{_num(rate)} Hz is faster than the "
                             f"integrator step (dt = {dt_s:.4g} s) can record",
                             f"<= {math.floor(top * 1e3) / 1e3:.6g} Hz, the integrator rate "
                             "(set solver.dt_s smaller for more)")


def check_bit_in_well(bit_md_m: float, td_m: float, field: str = "operation.bit_md_m") -> None:
    """Raise InputError if the bit starts below the well's total depth ``td_m``."""
    if bit_md_m > td_m * (1.0 + 1e-12):
        raise InputError(field, f"{_num(bit_md_m)} m is beyond the well's total depth "
                         f"{_num(td_m)} m", f"0 < {field.rsplit('.', 1)[-1]} <= {_num(td_m)} "
                         "(the TD of the well profile)")


def check_run_inputs(config: Any, td_m: float, dt_s: float) -> None:
    """The checks a simulation needs once its well path and step are known.

    ``td_m``: the last measured depth of the well path; ``dt_s``: the
    integrator step. Raises InputError for a bit below TD or a recording
    rate above ``1 / dt_s``.
    """
    check_bit_in_well(float(config.operation.bit_md_m), float(td_m))
    check_recording_rates(config.recording, float(dt_s))
