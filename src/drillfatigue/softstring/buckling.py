"""Buckling of a compressed string in the hole: onset loads and margins along the string.

Onset loads (effective compression ``F > 0``; SI: N, m, N/m, N m^2)
-------------------------------------------------------------------
A pipe of bending stiffness ``EI`` and buoyed weight ``w`` per length lies in a
hole with radial clearance ``r_c``. It stays straight on the wall until the
compression exceeds a critical load proportional to ``sqrt(EI q / r_c)``, with
``q`` the lateral load per length that presses it onto the wall:

* sinusoidal (lateral) onset, straight inclined hole, ``q = w sin I``:
  ``F_s = 2 sqrt(EI w sin I / r_c)`` (Dawson & Paslay, JPT 1984,
  SPE 11167);
* helical onset, straight inclined hole: ``F_h = 2 sqrt(2) sqrt(EI w sin I / r_c)``
  (Chen, Lin & Cheatham, SPE Drilling Engineering 1990, SPE 19176; the default)
  or ``F_h = 2 (2 sqrt(2) - 1) sqrt(EI w sin I / r_c)`` (Wu & Juvkam-Wold,
  SPE 25503, 1993: the load at which the helix is fully developed);
* vertical hole (``w sin I -> 0``), where the weight itself sets the scale:
  sinusoidal ``1.94 (EI w^2)^(1/3)`` (Lubinski, API Drilling and Production
  Practice 1950) and helical ``5.55 (EI w^2)^(1/3)`` (Wu, Juvkam-Wold & Lu,
  J. Energy Resour. Technol., 1993). The onset used along a string is the larger of the
  vertical value and the inclined/curved value, so that near-vertical cells
  are not reported as buckling at zero load;
* curved hole (curvature ``kappa`` with unit normal ``n`` towards the centre of
  curvature): the compression pushes the pipe away from the centre of
  curvature with ``F kappa`` per length (docs/rig.md), so the wall load
  is ``q(F) = | w g_perp - F kappa n |`` (``g_perp`` the part of the downward
  vertical normal to the axis, length sin I) and the onset solves
  ``F^2 r_c / (c^2 EI) = q(F)`` with ``c = 2`` (sinusoidal) or the helical
  constant. In the vertical plane this gives closed forms

      build (centre of curvature on the high side):
          F = (c^2 EI kappa / (2 r_c)) [ sqrt(1 + 4 r_c w sin I / (c^2 EI kappa^2)) + 1 ]
      drop (centre of curvature on the low side):
          F = (c^2 EI kappa / (2 r_c)) [ sqrt(1 + 4 r_c w sin I / (c^2 EI kappa^2)) - 1 ]

  derived here from that balance (He & Kyllingstad, SPE Drilling & Completion
  1995, and Mitchell, SPE Journal 1999, treat curved hole by
  adding the same curvature term; the coefficients here follow from the
  Dawson-Paslay constant and are not copied from those papers): a build raises the onset,
  a drop lowers it; ``kappa -> 0`` recovers the straight-hole forms. In a
  general 3-D bend ``q(F)`` is a vector sum; :func:`onset_load_N` solves the
  resulting quartic and takes its smallest positive root.

Helix (Lubinski & Althouse, JPT 1962; Mitchell, SPE Production Engineering 1986):
pitch ``p = pi sqrt(8 EI / F)``, wall contact force per length
``N = r_c F^2 / (4 EI)``.

Detection in a simulated run (the lateral offsets of its segments) is
:mod:`drillfatigue.dynamics.run.buckling`.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, Literal

import numpy as np

from drillfatigue.dynamics.run.buckling import STATE_NAMES, true_runs
from drillfatigue.softstring.march import TorqueDrag, path_tangents, resample_path
from drillfatigue.string import build_segments
from drillfatigue.well import build_survey

if TYPE_CHECKING:
    from drillfatigue.config import CaseConfig

#: Constant c of F = c sqrt(EI q / r_c): sinusoidal onset (Dawson & Paslay 1984).
C_SINUSOIDAL = 2.0
#: Helical onset, Chen, Lin & Cheatham (1990).
C_HELICAL_CHEN = 2.0 * math.sqrt(2.0)
#: Helical onset, Wu & Juvkam-Wold (1993), fully developed helix.
C_HELICAL_WU = 2.0 * (2.0 * math.sqrt(2.0) - 1.0)
#: Vertical hole, F = c_v (EI w^2)^(1/3): sinusoidal (Lubinski 1950), helical (Wu et al. 1993).
CV_SINUSOIDAL = 1.94
CV_HELICAL = 5.55

HelicalForm = Literal["chen", "wu"]


def _helical_constant(form: HelicalForm) -> float:
    if form == "chen":
        return C_HELICAL_CHEN
    if form == "wu":
        return C_HELICAL_WU
    raise ValueError(f"helical form must be 'chen' or 'wu', got {form!r}")


def sinusoidal_onset_straight_N(ei_Nm2: float | np.ndarray, w_N_per_m: float | np.ndarray,
                                inc_rad: float | np.ndarray, clearance_m: float | np.ndarray):
    """Dawson-Paslay sinusoidal onset ``2 sqrt(EI w sin I / r_c)`` in a straight hole, N."""
    return C_SINUSOIDAL * np.sqrt(ei_Nm2 * w_N_per_m * np.abs(np.sin(inc_rad)) / clearance_m)


def helical_onset_straight_N(ei_Nm2: float | np.ndarray, w_N_per_m: float | np.ndarray,
                             inc_rad: float | np.ndarray, clearance_m: float | np.ndarray,
                             form: HelicalForm = "chen"):
    """Helical onset in a straight inclined hole, N (``form``: Chen et al. 1990 or Wu 1993)."""
    c = _helical_constant(form)
    return c * np.sqrt(ei_Nm2 * w_N_per_m * np.abs(np.sin(inc_rad)) / clearance_m)


def vertical_onset_N(ei_Nm2: float | np.ndarray, w_N_per_m: float | np.ndarray,
                     kind: Literal["sinusoidal", "helical"] = "sinusoidal"):
    """Onset in a vertical hole, ``c_v (EI w^2)^(1/3)`` (Lubinski 1950; Wu et al. 1993), N."""
    cv = CV_SINUSOIDAL if kind == "sinusoidal" else CV_HELICAL
    return cv * np.cbrt(ei_Nm2 * np.asarray(w_N_per_m, float) ** 2)


def onset_curved_plane_N(ei_Nm2: float, w_N_per_m: float, inc_rad: float, clearance_m: float,
                         curvature_rad_per_m: float, section: Literal["build", "drop"],
                         c: float = C_SINUSOIDAL) -> float:
    """Onset in a build or drop of the vertical plane (closed forms of the module docstring), N."""
    ws = w_N_per_m * abs(math.sin(inc_rad))
    k = abs(curvature_rad_per_m)
    if k == 0.0:
        return c * math.sqrt(ei_Nm2 * ws / clearance_m)
    head = c * c * ei_Nm2 * k / (2.0 * clearance_m)
    root = math.sqrt(1.0 + 4.0 * clearance_m * ws / (c * c * ei_Nm2 * k * k))
    if section == "build":
        return head * (root + 1.0)
    if section == "drop":
        return head * (root - 1.0)
    raise ValueError(f"section must be 'build' or 'drop', got {section!r}")


def onset_load_N(ei_Nm2: float, clearance_m: float, g_perp_N_per_m: np.ndarray,
                 curvature_vec_per_m: np.ndarray, c: float = C_SINUSOIDAL) -> float:
    """Smallest compression F > 0 with ``F^2 r_c / (c^2 EI) = |g - F k|``, N.

    Parameters
    ----------
    ei_Nm2, clearance_m : float
        Bending stiffness (N m^2) and radial clearance (m).
    g_perp_N_per_m : ndarray, shape (3,)
        Lateral weight per length: ``w (z - (z . t) t)``, N/m.
    curvature_vec_per_m : ndarray, shape (3,)
        ``dt/ds`` = kappa n (towards the centre of curvature), 1/m.
    c : float
        ``C_SINUSOIDAL`` or a helical constant.

    Returns
    -------
    float
        The onset load; ``inf`` for a weightless pipe in a straight hole.
    """
    a = clearance_m / (c * c * ei_Nm2)
    g = np.asarray(g_perp_N_per_m, float)
    kv = np.asarray(curvature_vec_per_m, float)
    gg = float(g @ g)
    gk = float(g @ kv)
    kk = float(kv @ kv)
    if gg == 0.0 and kk == 0.0:
        return math.inf
    # a^2 F^4 = |g|^2 - 2 F (g . k) + F^2 |k|^2
    roots = np.roots([a * a, 0.0, -kk, 2.0 * gk, -gg])
    real = roots[np.abs(roots.imag) <= 1e-9 * np.maximum(1.0, np.abs(roots))].real
    pos = real[real > 0.0]
    if pos.size == 0:
        return math.inf
    f = float(pos.min())
    # one Newton polish on the quartic (np.roots is accurate to ~1e-12 relative)
    p = a * a * f**4 - kk * f * f + 2.0 * gk * f - gg
    dp = 4.0 * a * a * f**3 - 2.0 * kk * f + 2.0 * gk
    if dp != 0.0 and abs(p / dp) < 1e-6 * f:
        f -= p / dp
    return f


def helix_pitch_m(compression_N: float | np.ndarray, ei_Nm2: float | np.ndarray):
    """Pitch of a helically buckled pipe, ``pi sqrt(8 EI / F)``, m (Lubinski & Althouse 1962)."""
    return math.pi * np.sqrt(8.0 * ei_Nm2 / compression_N)


def helical_contact_force_N_per_m(compression_N: float | np.ndarray, ei_Nm2: float | np.ndarray,
                                  clearance_m: float | np.ndarray):
    """Wall contact force per length of a helix, ``r_c F^2 / (4 EI)``, N/m (Mitchell 1986)."""
    return clearance_m * np.asarray(compression_N, float) ** 2 / (4.0 * ei_Nm2)


@dataclass(frozen=True)
class BucklingProfile:
    """Buckling onsets and margins per soft-string cell, ordered by increasing MD.

    Cell arrays, shape (n_cell,): ``md_mid_m``; ``sinusoidal_onset_N`` and
    ``helical_onset_N`` (compression at which the cell buckles, with the
    cell's curvature and inclination); per T&D mode (``slackoff``,
    ``drilling``): ``compression_<mode>_N`` (effective compression, 0 in
    tension), ``margin_<mode>_N`` (sinusoidal onset minus compression; < 0
    means buckled) and ``state_<mode>`` (0 none, 1 sinusoidal, 2 helical; see
    :data:`STATE_NAMES`).
    """

    md_mid_m: np.ndarray
    ei_Nm2: np.ndarray
    clearance_m: np.ndarray
    sinusoidal_onset_N: np.ndarray
    helical_onset_N: np.ndarray
    compression_slackoff_N: np.ndarray
    compression_drilling_N: np.ndarray
    margin_slackoff_N: np.ndarray
    margin_drilling_N: np.ndarray
    state_slackoff: np.ndarray
    state_drilling: np.ndarray
    helical_form: str

    def summary(self) -> dict[str, Any]:
        """Smallest margin (N) and where (MD, m), buckled lengths (m) and sections per mode.

        ``buckled_sections_<mode>``: the runs of buckled cells, each ``md_start_m``,
        ``md_end_m``, ``mode`` (the worst state in it) and ``min_margin_N``; the simulator's
        summary.json reports its detections with the same mode names and lengths
        (:meth:`BucklingTracker.summary`).
        """
        out: dict[str, Any] = {}
        edges = _cell_edges(self.md_mid_m)
        dl = np.diff(edges)
        for mode in ("slackoff", "drilling"):
            margin = getattr(self, f"margin_{mode}_N")
            state = getattr(self, f"state_{mode}")
            k = int(np.argmin(margin))
            out[f"buckling_min_margin_{mode}_N"] = float(margin[k])
            out[f"buckling_min_margin_{mode}_md_m"] = float(self.md_mid_m[k])
            out[f"buckled_sinusoidal_{mode}_m"] = float(dl[state == 1].sum())
            out[f"buckled_helical_{mode}_m"] = float(dl[state == 2].sum())
            out[f"buckled_sections_{mode}"] = [
                {"md_start_m": float(edges[a]), "md_end_m": float(edges[b + 1]),
                 "mode": STATE_NAMES[int(state[a: b + 1].max())],
                 "min_margin_N": float(margin[a: b + 1].min())}
                for a, b in true_runs(state > 0)]
        return out


def _cell_edges(md_mid: np.ndarray) -> np.ndarray:
    """Cell boundaries (MD, m): half-way between centres, extended by half a cell at the ends."""
    if md_mid.size == 1:
        return np.array([md_mid[0] - 0.5, md_mid[0] + 0.5])
    return np.concatenate([[1.5 * md_mid[0] - 0.5 * md_mid[1]], 0.5 * (md_mid[1:] + md_mid[:-1]),
                           [1.5 * md_mid[-1] - 0.5 * md_mid[-2]]])


def _cell_lengths(md_mid: np.ndarray) -> np.ndarray:
    return np.diff(_cell_edges(md_mid))


def buckling_along_string(
    md_m: np.ndarray,
    tangent: np.ndarray,
    ei_Nm2: np.ndarray,
    w_N_per_m: np.ndarray,
    clearance_m: np.ndarray,
    tension_slackoff_N: np.ndarray,
    tension_drilling_N: np.ndarray,
    helical_form: HelicalForm = "chen",
) -> BucklingProfile:
    """Onset loads and margins per cell of a soft-string result.

    Parameters
    ----------
    md_m : ndarray, shape (n,)
        Station MDs (top of the string first), m.
    tangent : ndarray, shape (n, 3)
        Unit tangents at the stations, world frame with z down.
    ei_Nm2, w_N_per_m, clearance_m : ndarray, shape (n-1,)
        Per cell: bending stiffness (N m^2), buoyed weight per length (N/m),
        radial clearance hole radius - contact radius (m).
    tension_slackoff_N, tension_drilling_N : ndarray, shape (n,)
        Effective tension at the stations of the two modes (compression < 0).
    helical_form : {"chen", "wu"}

    Returns
    -------
    BucklingProfile
    """
    md = np.asarray(md_m, float)
    t = np.asarray(tangent, float)
    n = md.size
    ch = _helical_constant(helical_form)
    tm = t[1:] + t[:-1]
    tm /= np.linalg.norm(tm, axis=1, keepdims=True)
    z = np.array([0.0, 0.0, 1.0])
    g = w_N_per_m[:, None] * (z[None, :] - tm[:, 2:3] * tm)
    kv = (t[1:] - t[:-1]) / np.diff(md)[:, None]
    f_s = np.empty(n - 1)
    f_h = np.empty(n - 1)
    for k in range(n - 1):
        f_s[k] = onset_load_N(ei_Nm2[k], clearance_m[k], g[k], kv[k], C_SINUSOIDAL)
        f_h[k] = onset_load_N(ei_Nm2[k], clearance_m[k], g[k], kv[k], ch)
    # a cell with no lateral load at all (exactly vertical and straight) gives inf: the
    # vertical form is its onset; elsewhere the larger of the two
    f_s = np.maximum(np.where(np.isinf(f_s), 0.0, f_s), vertical_onset_N(ei_Nm2, w_N_per_m, "sinusoidal"))
    f_h = np.maximum(np.where(np.isinf(f_h), 0.0, f_h), vertical_onset_N(ei_Nm2, w_N_per_m, "helical"))
    res = {}
    for mode, ten in (("slackoff", tension_slackoff_N), ("drilling", tension_drilling_N)):
        comp = np.maximum(-0.5 * (ten[1:] + ten[:-1]), 0.0)
        res[f"compression_{mode}_N"] = comp
        res[f"margin_{mode}_N"] = f_s - comp
        res[f"state_{mode}"] = np.where(comp > f_h, 2, np.where(comp > f_s, 1, 0)).astype(np.int8)
    return BucklingProfile(md_mid_m=0.5 * (md[1:] + md[:-1]), ei_Nm2=np.asarray(ei_Nm2, float),
                           clearance_m=np.asarray(clearance_m, float), sinusoidal_onset_N=f_s,
                           helical_onset_N=f_h, helical_form=helical_form, **res)


def buckling_for_case(case: CaseConfig, td: TorqueDrag,
                      helical_form: HelicalForm = "chen") -> BucklingProfile:
    """Buckling margins along the string of a case for its soft-string result ``td``.

    Cells are those of ``td`` (from :func:`drillfatigue.softstring.march.torque_drag_for_case`);
    per cell, EI, buoyed weight and contact radius are those of the string
    component there (extended at the top like the T&D), the clearance is the
    hole radius at the cell's MD minus the contact radius (tool joints for
    drill pipe: they hold the body off the wall, as in the T&D torque arm).
    """
    op = case.operation
    sv = build_survey(case.well)
    seg = build_segments(case.string, op.mud_density_kg_per_m3)
    top_end = np.cumsum(seg.length_m)
    md = td.md_m
    s_mid = op.bit_md_m - 0.5 * (md[1:] + md[:-1])
    j = np.minimum(np.searchsorted(top_end, s_mid), seg.length_m.size - 1)
    w = seg.buoyed_weight_N[j] / seg.length_m[j]
    r = seg.contact_radius_m[j]
    hole_top = np.array([h.md_top_m for h in case.well.hole])
    hole_r = 0.5 * np.array([h.diameter_m for h in case.well.hole])
    md_mid = 0.5 * (md[1:] + md[:-1])
    r_hole = hole_r[np.clip(np.searchsorted(hole_top, md_mid, side="right") - 1, 0, hole_r.size - 1)]
    inc, azi = resample_path(sv.md_m, sv.inc_rad, sv.azi_rad, md)
    return buckling_along_string(md, path_tangents(inc, azi), seg.ei_Nm2[j], w, r_hole - r,
                                 td.tension_slackoff_N, td.tension_drilling_N, helical_form)
