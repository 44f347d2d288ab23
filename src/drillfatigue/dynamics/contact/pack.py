"""Wall contact of a case: ``cpar`` (penalty, friction and bit laws, switches), the hole
as cylinders, the hole fit, each segment's contact points and their first hints."""

from __future__ import annotations



import numpy as np

from drillfatigue.config import CaseConfig
from drillfatigue.dynamics.bit.laws import registry as bitrock
from drillfatigue.dynamics.contact.friction import registry as friction
from drillfatigue.dynamics.core import layout as L
from drillfatigue.dynamics.core.bundles import State
from drillfatigue.dynamics.contact.wall import contact_damping
from drillfatigue.dynamics.core.rigid import quat_to_rot
from drillfatigue.errors import InputError
from drillfatigue.string import Segments
from drillfatigue.string.segments import HoleFit
from drillfatigue.string.contacts import contact_points

from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from drillfatigue.dynamics.core.pack import Placement
    from drillfatigue.dynamics.run.model import Model, WellPath


def pack_contact(config: CaseConfig) -> np.ndarray:
    """``cpar`` (shape (N_CPAR,)): wall contact, friction and bit-law parameters (see :mod:`layout`)."""
    cpar = np.zeros(L.N_CPAR)
    c = config.contact
    cpar[L.P_ON] = 1.0 if c.enabled else 0.0
    cpar[L.P_KC] = c.k_c_N_per_m
    fid, fp = friction.pack_friction_params(config.friction)
    cpar[L.P_FMODEL] = fid
    cpar[L.P_FP:L.P_FP + friction.N_PARAMS] = fp
    cpar[L.P_NPTS] = 3.0 if c.points == "ends_and_middle" else 2.0
    cpar[L.P_CPTAB] = 1.0 if c.points == "string" else 0.0
    cpar[L.P_SPAN] = 1.0 if c.span_bending and c.enabled else 0.0
    cpar[L.P_DEEP] = 1.0 if c.deepest_point else 0.0
    b = config.bit
    if b.model == "given_tob":
        cpar[L.P_BITLAW] = 0.0
    else:
        cpar[L.P_BITLAW] = 1.0
        bid, bpar = bitrock.pack_bit_params(b, config.operation.rop_m_per_s)
        cpar[L.P_BITMODEL] = bid
        cpar[L.P_BP:L.P_BP + bitrock.N_PARAMS] = bpar
    return cpar


def pack_wall(config: CaseConfig, segs: Segments, seg: np.ndarray, cpar: np.ndarray,
              cp_n: np.ndarray | None = None) -> None:
    """Contact radii (ends: tool joints or body; middle: body) and the per-point contact
    dash-pot of ``seg`` (read by :mod:`contact`), in place. ``cp_n``: points of each
    segment when they come from the string (the dash-pot is per point)."""
    seg[:, L.S_RB] = 0.5 * segs.od_m
    if not config.contact.tool_joints:
        seg[:, L.S_RC] = 0.5 * segs.od_m
    if cpar[L.P_ON] != 0.0:
        npts = np.full(seg.shape[0], cpar[L.P_NPTS])
        if cp_n is not None and cpar[L.P_CPTAB] != 0.0:
            npts[:-1] = cp_n[:seg.shape[0] - 1]
        seg[:, L.S_CC] = [contact_damping(config.contact, float(mi) / float(k))
                          for mi, k in zip(seg[:, L.S_M], npts, strict=True)]


def _max_curvature(path: WellPath) -> float:
    """Largest curvature (rad/m) between neighbouring path nodes (angle between tangents / dMD)."""
    t = path.node_tan
    if t.shape[0] < 2:
        return 0.0
    dmd = np.diff(path.node_md_m)
    cosang = np.clip((t[1:] * t[:-1]).sum(axis=1), -1.0, 1.0)
    ok = dmd > 1e-9
    if not ok.any():
        return 0.0
    return float((np.arccos(cosang[ok]) / dmd[ok]).max())


def hole_fit(config: CaseConfig, path: WellPath) -> HoleFit | None:
    """The hole the string can meet during the run, for the hole-fit rule of
    :func:`drillfatigue.string.build_segments` (None without a wall: contact off).

    The bit moves from ``bit_md_m`` by the prescribed ROP on bottom and the trip
    speed over ``duration_s``; the top component reaches ``operation.top_md_m``.
    Curvature of a path interval: the angle between its node tangents / its MD
    length.
    """
    wall = path.wall
    if wall.shape[0] == 0 or path.node_tan.shape[0] < 2:
        return None
    op = config.operation
    t = path.node_tan
    md = path.node_md_m
    dmd = np.diff(md)
    cosang = np.clip((t[1:] * t[:-1]).sum(axis=1), -1.0, 1.0)
    k_int = np.where(dmd > 1e-9, np.arccos(cosang) / np.maximum(dmd, 1e-9), 0.0)
    travel = op.duration_s * ((op.rop_m_per_s if op.bit_on_bottom else 0.0)
                              + op.trip_speed_m_per_s)
    lo, hi = sorted((op.bit_md_m, op.bit_md_m + travel))
    return HoleFit(md_m=md, curvature_rad_per_m=k_int,
                   radius_m=np.ascontiguousarray(wall[:dmd.size, L.W_RAD]),
                   bit_md_lo_m=lo, bit_md_hi_m=hi, top_md_m=op.top_md_m)


def pack_contact_points(config: CaseConfig, segs: Segments, place: Placement,
                        path: WellPath) -> tuple[np.ndarray, np.ndarray]:
    """Contact points of the segments below the top, from the string's components.

    :func:`drillfatigue.string.contacts.contact_points` lists them (tool joints
    at the tool-joint radius, stabilizer blades, centre upsets, extra body
    points spaced by the chord/sag rule for the largest curvature each segment
    can meet during the run (:func:`hole_fit`) and the largest hole radius,
    chord fraction ``contact.chord_fraction``). Returns ``cp_n`` (n,) and ``cp`` (n, MAX_TABLE_POINTS,
    2): [offset from the centre along e3 (> 0 towards the bit), radius], m. The
    top segment's row stays empty (it keeps its end points while it grows).
    """
    n = segs.n_segments
    cp_n = np.zeros(n)
    cp = np.zeros((n, L.MAX_TABLE_POINTS, 2))
    wall = path.wall
    if wall.shape[0] == 0:
        return cp_n, cp
    hole_d = 2.0 * float(wall[:, L.W_RAD].max())
    # each segment's points are spaced for the largest curvature it can meet during
    # the run (pipe in the vertical needs no chord points)
    hole = hole_fit(config, path)
    top = np.cumsum(segs.length_m)
    kappa = np.array([hole.over(float(a), float(b))[0] if hole is not None
                      else _max_curvature(path) for a, b in zip(top - segs.length_m, top,
                                                                strict=True)])
    pts = contact_points(config.string, segs, hole_d, kappa,
                         chord_fraction=config.contact.chord_fraction)
    for i in range(n - 1):
        s_m, r_m, _ = pts.of_segment(i)
        if s_m.size > L.MAX_TABLE_POINTS:
            raise InputError("contact.points",
                             f"segment {i} needs {s_m.size} contact points, more than "
                             f"{L.MAX_TABLE_POINTS}", f"segments shorter than "
                             f"{L.MAX_TABLE_POINTS - 1} x {float(pts.max_spacing_m[i]):.2f} m")
        cp_n[i] = s_m.size
        cp[i, :s_m.size, 0] = place.h[i] - s_m
        cp[i, :s_m.size, 1] = r_m
    return cp_n, cp


def _pad_points(cp_n: np.ndarray, cp: np.ndarray, n: int, nmax: int, lnom: float,
                r_top: float) -> tuple[np.ndarray, np.ndarray]:
    """Contact points of all ``nmax`` rows: rows from n - 1 on become pieces split off the
    top (length ``lnom``); they take the points of segment n - 2 when it has that length
    (a whole number of the same joints), else their two ends at the top's end radius."""
    out_n = np.zeros(nmax)
    out = np.zeros((nmax, L.MAX_TABLE_POINTS, 2))
    out_n[:n] = cp_n
    out[:n] = cp
    if n >= 2 and cp_n[n - 2] > 0 and abs(cp[n - 2, 0, 0] - 0.5 * lnom) < 1e-9:
        row_n, row = cp_n[n - 2], cp[n - 2]
    else:
        row_n = 2.0
        row = np.zeros((L.MAX_TABLE_POINTS, 2))
        row[0] = (0.5 * lnom, r_top)
        row[1] = (-0.5 * lnom, r_top)
    out_n[n - 1:] = row_n
    out[n - 1:] = row
    return np.ascontiguousarray(out_n), np.ascontiguousarray(out)


def _init_hints(model: Model, state: State) -> None:
    """Cylinder hints of every contact point: the nearest cylinder start (O(n_cyl) once);
    the string's own points of rows not yet in use: -1 (located from the row's first hint)."""
    wall = model.path.wall
    if wall.shape[0] == 0:
        return
    p0 = wall[:, L.W_P0:L.W_P0 + 3]
    n = model.n0
    R = np.zeros((3, 3))
    tbase = L.MAX_CONTACT_POINTS * model.n
    table = model.cpar[L.P_CPTAB] != 0.0
    if table:
        state.hint[tbase:] = -1
    for i in range(n):
        quat_to_rot(state.q[i], R)
        h = model.seg[i, L.S_H]
        for p, off in enumerate((h, -h, 0.0)):
            X = state.x[i] + off * R[:, 2]
            state.hint[L.MAX_CONTACT_POINTS * i + p] = int(np.argmin(((p0 - X) ** 2).sum(axis=1)))
        if table and i < n - 1:
            for p in range(int(model.cp_n[i])):
                X = state.x[i] + model.cp[i, p, 0] * R[:, 2]
                state.hint[tbase + L.MAX_TABLE_POINTS * i + p] = int(
                    np.argmin(((p0 - X) ** 2).sum(axis=1)))

