"""Small reference cases for the validation tests and benchmarks.

:func:`uniform_chain_case` is the textbook chain of docs/validation.md: one uniform
tube (6 3/4 in collar section by default) cut into ``n`` equal segments, hanging
in a straight hole, top held, bit free (off bottom), no mud, damping optional.
"""

from __future__ import annotations

import math
from typing import Any

from drillfatigue.config import CaseConfig, case_from_dict

COLLAR_OD_M = 0.17145
COLLAR_ID_M = 0.0714


def uniform_chain_case(n: int, length_m: float, *, od_m: float = COLLAR_OD_M,
                       id_m: float = COLLAR_ID_M, damping: bool = False,
                       chain_top_spring: bool = False, mud_density_kg_per_m3: float = 0.0,
                       contact: bool = False,
                       extra: dict[str, Any] | None = None) -> CaseConfig:
    """A uniform string of ``n`` segments, total ``length_m``, top fixed, bit off bottom.

    Wall contact is off unless ``contact`` (the textbook chain has no wall).

    ``chain_top_spring`` sets the top axial and torsional springs to EA/L and
    GJ/L (L = length / n), the wall spring of the discrete-chain formula;
    otherwise the physical half-segment value EA/(L/2) is used.
    ``extra`` is merged section by section into the case dictionary.
    """
    seg_len = length_m / n
    e, nu = 207e9, 0.3
    area = math.pi / 4 * (od_m ** 2 - id_m ** 2)
    j_polar = math.pi / 32 * (od_m ** 4 - id_m ** 4)
    g_mod = e / (2 * (1 + nu))
    solver: dict[str, Any] = {}
    if not damping:
        solver.update(joint_damping_ratio=0.0, boundary_damping_ratio=0.0)
    if chain_top_spring:
        solver.update(top_axial_stiffness_N_per_m=e * area / seg_len,
                      top_torsional_stiffness_N_m_per_rad=g_mod * j_polar / seg_len)
    op: dict[str, Any] = {
        "bit_md_m": length_m, "top_md_m": 0.0, "top_axial": "fixed", "bit_on_bottom": False,
        "rpm": 0.0, "rpm_ramp_s": 0.0, "mud_density_kg_per_m3": mud_density_kg_per_m3,
    }
    if not damping:
        op.update(mud_damping_lateral_N_s_per_m2=0.0, mud_damping_axial_N_s_per_m2=0.0,
                  mud_damping_torsional_N_m_s_per_m=0.0)
    data: dict[str, Any] = {
        "string": {"components": [{"type": "collar", "od_m": od_m, "id_m": id_m,
                                   "length_m": length_m, "n_segments": n}]},
        "operation": op,
        "solver": solver,
        "contact": {"enabled": contact},
    }
    for key, val in (extra or {}).items():
        data.setdefault(key, {}).update(val)
    return case_from_dict(data)


def j_well_rotating_case(*, kop_m: float = 60.0, dls_deg_per_30m: float = 3.0,
                         inc_deg: float = 30.0, top_md_m: float = 0.0, bit_md_m: float = 300.0,
                         n_segments: int = 30, rpm: float = 60.0, duration_s: float = 3.0,
                         extra: dict[str, Any] | None = None) -> CaseConfig:
    """5 in drill pipe (no tool joints) rotating off bottom in a J-well, top held.

    The stiff-string vs soft-string check of docs/validation.md: vertical to
    ``kop_m``, build at ``dls_deg_per_30m`` to ``inc_deg``, hold to 500 m; the
    string spans ``top_md_m`` .. ``bit_md_m`` in ``n_segments`` segments,
    rotates at ``rpm`` (ramped over 0.5 s) after a 0.5 s relaxation, wall
    contact with the default penalty and tanh-exponential friction. With
    ``kop_m`` ~ 0 and a 60 deg/30 m build the string from 50 m down lies in a
    straight hole at ``inc_deg`` (closed forms of docs/validation.md). Sizes: 5 in
    19.5 ppf pipe body (OD 127 mm, ID 108.6 mm) in an 8 1/2 in hole.
    """
    data: dict[str, Any] = {
        "well": {"profiles": {"j": {"kind": "j", "kop_m": kop_m,
                                    "dls_deg_per_30m": dls_deg_per_30m, "inc_deg": inc_deg,
                                    "td_m": 500.0}}},
        "string": {"components": [{"type": "drill_pipe", "od_m": 0.127, "id_m": 0.1086,
                                   "length_m": bit_md_m - top_md_m, "n_segments": n_segments}]},
        "operation": {"duration_s": duration_s, "bit_md_m": bit_md_m, "top_md_m": top_md_m,
                      "bit_on_bottom": False, "top_axial": "fixed", "rpm": rpm,
                      "rpm_ramp_s": 0.5},
        "solver": {"relax_s": 0.5},
        "recording": {"channels_rate_hz": 100.0, "kinematics_rate_hz": 20.0,
                      "loads_rate_hz": 10.0},
    }
    for key, val in (extra or {}).items():
        data.setdefault(key, {}).update(val)
    return case_from_dict(data)
