"""The string as segments and joints: placement on the well path, the ``seg``, ``jp`` and
lateral-mass rows of a case (the core kernels read them)."""

from __future__ import annotations


import math
from dataclasses import dataclass

import numpy as np

from drillfatigue.config import CaseConfig
from drillfatigue.dynamics.core import layout as L
from drillfatigue.errors import InputError
from drillfatigue.string import Segments
from drillfatigue.string.added_mass import lateral_mass_kg

from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from drillfatigue.dynamics.run.model import WellPath


def _series(h1: np.ndarray, k1: np.ndarray, h2: np.ndarray, k2: np.ndarray) -> np.ndarray:
    """Stiffness of two half-segments in series: 1 / (h1/k1 + h2/k2)."""
    return 1.0 / (h1 / k1 + h2 / k2)


def _frames(e3s: np.ndarray) -> np.ndarray:
    """Parallel-transported body frames (n, 3, 3), columns e1, e2, e3."""
    n = e3s.shape[0]
    out = np.zeros((n, 3, 3))
    e3 = e3s[0]
    ref = np.array([1.0, 0.0, 0.0]) if abs(e3[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    e1 = ref - (ref @ e3) * e3
    e1 /= np.linalg.norm(e1)
    out[0] = np.column_stack([e1, np.cross(e3, e1), e3])
    for i in range(1, n):
        a, b = e3s[i - 1], e3s[i]
        axis = np.cross(a, b)
        s = np.linalg.norm(axis)
        c = float(np.clip(a @ b, -1.0, 1.0))
        if s < 1e-15:
            rot = np.eye(3)
        else:
            k = axis / s
            K = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
            rot = np.eye(3) + s * K + (1.0 - c) * K @ K
        out[i] = rot @ out[i - 1]
    return out


def _rotz(psi: float) -> np.ndarray:
    c, s = math.cos(psi), math.sin(psi)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


@dataclass
class Placement:
    """Where the segments start: lengths (m), half lengths, ends' distance from the bit
    (``s_top_end``), unit axes ``e3s`` and centres (n, 3), parallel-transported frames."""

    lengths: np.ndarray
    h: np.ndarray
    s_top_end: np.ndarray
    e3s: np.ndarray
    centres: np.ndarray
    frames: np.ndarray
    top_len: float


def place_segments(config: CaseConfig, segs: Segments, path: WellPath) -> Placement:
    """Segments as chords of the well path between the bit and the top MD; the top
    segment takes the length left over (checked against half a nominal segment)."""
    op = config.operation
    s_top_end = np.cumsum(segs.length_m)
    s_bot_end = s_top_end - segs.length_m
    top_len = op.bit_md_m - op.top_md_m - s_bot_end[-1]
    if top_len < 0.5 * segs.length_m[-1] or top_len <= 0.0:
        raise InputError("operation.bit_md_m",
                         f"the string below its top segment ({s_bot_end[-1]:.1f} m) leaves "
                         f"{top_len:.1f} m for the top segment between bit_md_m and top_md_m",
                         f"bit_md_m - top_md_m >= {s_bot_end[-1] + 0.5 * segs.length_m[-1]:.1f} m")
    lengths = segs.length_m.copy()
    lengths[-1] = top_len
    s_top_end = np.cumsum(lengths)
    s_bot_end = s_top_end - lengths
    md_lo = op.bit_md_m - s_bot_end
    md_up = op.bit_md_m - s_top_end
    p_lo = np.array([path.point_at_md(md)[0] for md in md_lo])
    p_up = np.array([path.point_at_md(md)[0] for md in md_up])
    chord = p_lo - p_up
    e3s = chord / np.linalg.norm(chord, axis=1)[:, None]
    return Placement(lengths=lengths, h=0.5 * lengths, s_top_end=s_top_end, e3s=e3s,
                     centres=0.5 * (p_lo + p_up), frames=_frames(e3s), top_len=float(top_len))


def pack_segments(config: CaseConfig, segs: Segments, lengths: np.ndarray) -> np.ndarray:
    """``seg`` (n, N_SEG): rigid bodies (mass, inertias, half length), buoyed weight, mud
    damping and the contact radius at the ends (read by :mod:`rigid`, :mod:`forces`)."""
    op = config.operation
    n = segs.n_segments
    seg = np.zeros((n, L.N_SEG))
    m = segs.mass_per_length_kg_per_m * lengths
    ro2 = (0.5 * segs.od_m) ** 2 + (0.5 * segs.id_m) ** 2
    wpl = segs.buoyed_weight_N / segs.length_m
    seg[:, L.S_M] = m
    seg[:, L.S_IA] = 0.5 * m * ro2
    seg[:, L.S_IT] = m * (3.0 * ro2 + lengths ** 2) / 12.0
    seg[:, L.S_H] = 0.5 * lengths
    seg[:, L.S_W] = wpl * lengths
    seg[:, L.S_CL] = op.mud_damping_lateral_N_s_per_m2 * lengths
    seg[:, L.S_CA] = op.mud_damping_axial_N_s_per_m2 * lengths
    seg[:, L.S_CRL] = op.mud_damping_torsional_N_m_s_per_m * lengths
    seg[:, L.S_CRA] = op.mud_damping_torsional_N_m_s_per_m * lengths
    seg[:, L.S_RC] = segs.contact_radius_m
    return seg


def pack_joints(config: CaseConfig, segs: Segments, seg: np.ndarray
                ) -> tuple[np.ndarray, tuple[float, float, float]]:
    """``jp`` (n, N_JP): the joints' springs (half-segment springs in series) and dampers
    (read by :mod:`joints`); and the stiffest shear, bending and axial joint springs
    (references for the boundary springs)."""
    n = segs.n_segments
    h = seg[:, L.S_H]
    m = seg[:, L.S_M]
    zj = config.solver.joint_damping_ratio
    jp = np.zeros((n, L.N_JP))
    if n > 1:
        a, b = slice(0, n - 1), slice(1, n)
        jp[a, L.J_KA] = _series(h[a], segs.ea_N[a], h[b], segs.ea_N[b])
        jp[a, L.J_KS] = _series(h[a], segs.kga_N[a], h[b], segs.kga_N[b])
        jp[a, L.J_KB] = _series(h[a], segs.ei_Nm2[a], h[b], segs.ei_Nm2[b])
        jp[a, L.J_KT] = _series(h[a], segs.gj_Nm2[a], h[b], segs.gj_Nm2[b])
        me = m[a] * m[b] / (m[a] + m[b])
        ite = seg[a, L.S_IT] * seg[b, L.S_IT] / (seg[a, L.S_IT] + seg[b, L.S_IT])
        iae = seg[a, L.S_IA] * seg[b, L.S_IA] / (seg[a, L.S_IA] + seg[b, L.S_IA])
        jp[a, L.J_CA] = 2 * zj * np.sqrt(jp[a, L.J_KA] * me)
        jp[a, L.J_CS] = 2 * zj * np.sqrt(jp[a, L.J_KS] * me)
        jp[a, L.J_CB] = 2 * zj * np.sqrt(jp[a, L.J_KB] * ite)
        jp[a, L.J_CT] = 2 * zj * np.sqrt(jp[a, L.J_KT] * iae)
        refs = (jp[a, L.J_KS].max(), jp[a, L.J_KB].max(), jp[a, L.J_KA].max())
    else:
        refs = (config.string.shear_coefficient * segs.kga_N[0] / h[0], segs.ei_Nm2[0] / h[0],
                segs.ea_N[0] / h[0])
    return jp, refs


def pack_lateral_mass(config: CaseConfig, segs: Segments, path: WellPath, cpar: np.ndarray,
                      nmax: int) -> np.ndarray:
    """Ratio of lateral to steel mass of every row (``Params.mlat``) and the switch
    ``cpar[P_LATMASS]`` (in place) from ``string.lateral_mud_mass``: steel + mud inside +
    confined added mass (:func:`drillfatigue.string.added_mass.lateral_mass_kg`, hole
    diameter from the largest hole radius); rows split off the top later take the top's
    ratio. All ones when off."""
    ratio = np.ones(nmax)
    sc = config.string
    if not sc.lateral_mud_mass or path.wall.shape[0] == 0:
        return ratio
    hole_d = 2.0 * float(path.wall[:, L.W_RAD].max())
    ml = lateral_mass_kg(segs, config.operation.mud_density_kg_per_m3, hole_d,
                         sc.added_mass_coefficient)
    r = ml / segs.mass_kg
    n = r.size
    ratio[:n] = r
    ratio[n:] = r[-1]
    cpar[L.P_LATMASS] = 1.0
    return np.ascontiguousarray(ratio)

