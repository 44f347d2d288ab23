"""Soft-string torque and drag of a case: the case's well, string and operation packed for
the soft-string kernel (:mod:`drillfatigue.softstring.march`) and the result.
"""

from __future__ import annotations

import math

import numpy as np

from drillfatigue.config import CaseConfig
from drillfatigue.config.string import JOINTED_TYPES
from drillfatigue.dynamics.bit.laws import bit_response, pack_bit_params
from drillfatigue.softstring.march import (
    TorqueDrag, path_tangents, resample_path, soft_string_torque_drag,
)
from drillfatigue.errors import InputError
from drillfatigue.string import build_segments
from drillfatigue.well import build_survey
from drillfatigue.units import rad_per_s_from_rpm

__all__ = ["TorqueDrag", "torque_drag_for_case"]


def torque_drag_for_case(
    case: CaseConfig,
    cell_m: float = 10.0,
    wob_N: float | None = None,
    tob_Nm: float | None = None,
) -> TorqueDrag:
    """Soft-string torque and drag for a case file's well, string and operation.

    The string spans ``operation.top_md_m`` .. ``operation.bit_md_m``; its
    per-length buoyed weight and contact radius come from
    :func:`drillfatigue.string.build_segments` (index 0 at the bit); if the
    string is shorter than that span, its top component is extended (as the
    simulator's extensible top segment does), if longer, the part above the
    rig floor is dropped. Friction: ``friction.mu_dynamic`` for torque,
    ``friction.mu_axial`` (default ``mu_dynamic``) for drag.

    Drilling-mode WOB, unless given: with ``operation.top_axial`` =
    ``neutral_point``, the axial buoyed weight of the string below the neutral
    point (default the top of the collars: the last non drill-pipe/HWDP
    component); with ``hook_load``, rotating hook load minus
    ``operation.hook_load_N``; with ``fixed`` or off bottom, 0. TOB, unless
    given: ``operation.tob_Nm`` if non-zero, else the bit law
    (:mod:`drillfatigue.dynamics.bit.laws`) at that WOB and ``operation.rpm``.

    Raises
    ------
    InputError
        The bit lies beyond the end of the well path, or the derived WOB is negative.
    """
    op = case.operation
    sv = build_survey(case.well)
    if op.bit_md_m > sv.md_m[-1] + 1e-6:
        raise InputError("operation.bit_md_m", f"{op.bit_md_m} m is beyond the well's TD "
                         f"{sv.md_m[-1]:.1f} m", f"<= {sv.md_m[-1]:.1f}")
    seg = build_segments(case.string, op.mud_density_kg_per_m3)
    top_end = np.cumsum(seg.length_m)  # distance bit -> top of each segment
    span = op.bit_md_m - op.top_md_m
    # stations: uniform cells plus segment boundaries and survey stations inside the span
    n_cell = max(1, math.ceil(span / cell_m))
    md = np.linspace(op.top_md_m, op.bit_md_m, n_cell + 1)
    extra = [op.bit_md_m - top_end[top_end < span],
             sv.md_m[(sv.md_m > op.top_md_m) & (sv.md_m < op.bit_md_m)]]
    md = np.unique(np.concatenate([md, *extra]))
    md = md[np.concatenate([[True], np.diff(md) > 1e-9])]
    inc, azi = resample_path(sv.md_m, sv.inc_rad, sv.azi_rad, md)
    s_mid = op.bit_md_m - 0.5 * (md[1:] + md[:-1])
    j = np.minimum(np.searchsorted(top_end, s_mid), seg.length_m.size - 1)
    w = seg.buoyed_weight_N[j] / seg.length_m[j]
    r = seg.contact_radius_m[j]
    mu_t = case.friction.mu_dynamic
    mu_d = case.friction.mu_axial if case.friction.mu_axial is not None else mu_t

    if wob_N is None:
        wob_N = 0.0
        if op.bit_on_bottom and op.top_axial == "neutral_point":
            if op.neutral_point_s_from_bit_m is not None:
                s_np = op.neutral_point_s_from_bit_m
            else:
                comps = case.string.components
                k = len(comps)
                while k > 0 and comps[k - 1].type in JOINTED_TYPES:
                    k -= 1
                s_np = float(sum(c.length_m for c in comps[:k]))
            below = s_mid < s_np
            t = path_tangents(inc, azi)
            tm = t[1:] + t[:-1]  # the march's mean cell tangent, so WOB matches it exactly
            tz = tm[:, 2] / np.linalg.norm(tm, axis=1)
            wob_N = float(np.sum((w * np.diff(md) * tz)[below]))
        elif op.bit_on_bottom and op.top_axial == "hook_load":
            rot = soft_string_torque_drag(md, inc, azi, w, r, mu_t, mu_d)
            wob_N = float(rot.tension_rotating_N[0] - op.hook_load_N)
            if wob_N < 0.0:
                raise InputError("operation.hook_load_N", f"{op.hook_load_N:.0f} N exceeds the "
                                 f"rotating off-bottom hook load {rot.tension_rotating_N[0]:.0f} N "
                                 "(the bit would be lifted)",
                                 f"<= {rot.tension_rotating_N[0]:.0f}")
    if tob_Nm is None:
        tob_Nm = op.tob_Nm
        if tob_Nm == 0.0 and wob_N > 0.0:
            mid, p = pack_bit_params(case.bit, op.rop_m_per_s)
            out = np.empty(2)
            bit_response(mid, p, wob_N, rad_per_s_from_rpm(op.rpm), out)
            tob_Nm = float(out[0])
    return soft_string_torque_drag(md, inc, azi, w, r, mu_t, mu_d, wob_N, tob_Nm)
