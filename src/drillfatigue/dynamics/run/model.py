"""Python layer: pack a validated case into kernel arrays and the initial state.

:func:`build_model` places the segments on the well path (parallel-transported
frames, so no spurious twist), packs the parameters (:mod:`layout`), solves the
hook load for the requested neutral point, pre-loads the joints axially and in
torsion so the run starts in static equilibrium for a straight hole, and picks
the step from :func:`stable_step`.

Wall contact, friction and the bit law are packed into ``cpar``
(:func:`pack_contact`). The per-segment arrays are allocated to the largest
size the run can reach (:func:`max_segments`: the initial count plus the
segments drilling or tripping in can add) and padded with inactive rows.

Initial state in curved wells: the segments are placed as chords of the well
path, which is where the hole keeps them; the joints then carry the bending
of the path (physical). With ``solver.relax_s > 0`` a damped pre-run (no
rotation, no ROP, lateral mud damping x ``RELAX_DAMPING``) lets the string
settle onto the low side of the hole before t = 0; time, energy counters and
contact statistics are reset after it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from drillfatigue.config import CaseConfig
from drillfatigue.dynamics.top.setup import block_params, rop_start_wob_N, top_drive_params
from drillfatigue.dynamics.bit.laws import registry as bitrock
from drillfatigue.dynamics.bit.laws.kernel import bit_response
from drillfatigue.dynamics.contact.friction import registry as friction
from drillfatigue.dynamics.core import layout as L
from drillfatigue.dynamics.core import status
from drillfatigue.dynamics.top import rig as R
from drillfatigue.dynamics.top.connection import N_PHASES
from drillfatigue.dynamics.core.bundles import Params, State, Work, new_records, new_work
from drillfatigue.dynamics.contact.wall import contact_damping
from drillfatigue.dynamics.step.forces import compute_forces
from drillfatigue.dynamics.top.growth import update_top
from drillfatigue.dynamics.step.integrator import advance, kinetic_energy
from drillfatigue.dynamics.core.rigid import quat_from_rot, quat_to_rot
from drillfatigue.dynamics.bit.rockface import ROP_FROM_WOB_MODELS, steady_wob_for_rop_N
from drillfatigue.errors import InputError, SimulationError
from drillfatigue.string import Segments, build_segments
from drillfatigue.string.segments import HoleFit
from drillfatigue.string.added_mass import lateral_mass_kg
from drillfatigue.string.contacts import contact_points
from drillfatigue.well.kernels import path_point

G = 9.80665
RAD_S_PER_RPM = 2.0 * math.pi / 60.0
#: TOB regularisation speed (rad/s): TOB(omega) = TOB tanh(omega / OMEGA_REF).
OMEGA_REF_RAD_S = 0.5


@dataclass(frozen=True)
class WellPath:
    """Well centre line as survey nodes: MD (m, shape (P,)), position (P, 3), unit tangent (P, 3),
    and the hole as cylinders ``wall`` (shape (P - 1, N_WALL), see :mod:`layout`) for contact."""

    node_md_m: np.ndarray
    node_pos_m: np.ndarray
    node_tan: np.ndarray
    wall: np.ndarray = field(default_factory=lambda: np.zeros((0, L.N_WALL)))

    def point_at_md(self, md: float) -> tuple[np.ndarray, np.ndarray]:
        """Position (m) and unit tangent of the path at ``md``."""
        pos = np.zeros(3)
        tan = np.zeros(3)
        path_point(float(md), self.node_md_m, self.node_pos_m, self.node_tan, 0, pos, tan)
        return pos, tan


def _wall(p0: np.ndarray, axis: np.ndarray, length: np.ndarray, radius: np.ndarray) -> np.ndarray:
    wall = np.zeros((length.size, L.N_WALL))
    wall[:, L.W_P0:L.W_P0 + 3] = p0
    wall[:, L.W_AX:L.W_AX + 3] = axis
    wall[:, L.W_LEN] = length
    wall[:, L.W_RAD] = radius
    return wall


def straight_path(length_m: float, inclination_deg: float = 0.0, azimuth_deg: float = 0.0,
                  n_nodes: int = 2, hole_diameter_m: float = 0.2159) -> WellPath:
    """A straight well from the origin (vertical when inclination is 0)."""
    inc = math.radians(inclination_deg)
    azi = math.radians(azimuth_deg)
    t = np.array([math.sin(inc) * math.cos(azi), math.sin(inc) * math.sin(azi), math.cos(inc)])
    md = np.linspace(0.0, length_m, n_nodes)
    pos = md[:, None] * t[None, :]
    seg_len = np.diff(md)
    return WellPath(md, pos, np.tile(t, (n_nodes, 1)),
                    _wall(pos[:-1], np.tile(t, (n_nodes - 1, 1)), seg_len,
                          np.full(n_nodes - 1, 0.5 * hole_diameter_m)))


def path_from_wellbore(wb: object) -> WellPath:
    """Path nodes and cylinders of a :class:`drillfatigue.well.Wellbore`."""
    def f(a: object) -> np.ndarray:
        return np.ascontiguousarray(a, dtype=np.float64)

    return WellPath(f(wb.node_md_m), f(wb.node_pos_m), f(wb.node_tan),  # type: ignore[attr-defined]
                    _wall(f(wb.p0_m), f(wb.axis), f(wb.length_m), f(wb.radius_m)))  # type: ignore[attr-defined]


@dataclass
class Model:
    """Packed parameters of one simulation (see :mod:`layout` for the columns)."""

    segments: Segments
    path: WellPath
    seg: np.ndarray
    jp: np.ndarray
    bp: np.ndarray
    topp: np.ndarray
    anchor: np.ndarray
    tab_t: np.ndarray
    tab_w: np.ndarray
    dt: float
    hook_load_N: float
    wob0_N: float
    neutral_point_s_from_bit_m: float | None
    top_length_m: float
    cpar: np.ndarray = field(default_factory=lambda: np.zeros(L.N_CPAR))
    work: Work | None = None
    n0: int = 0
    segment_length_m: float = 0.0
    cp_n: np.ndarray = field(default_factory=lambda: np.zeros(0))
    cp: np.ndarray = field(default_factory=lambda: np.zeros((0, L.MAX_TABLE_POINTS, 2)))
    ei: np.ndarray = field(default_factory=lambda: np.zeros(0))
    mlat: np.ndarray = field(default_factory=lambda: np.zeros(0))
    #: with the rig boundaries: what summary.json reports of their set-up
    rig_info: dict = field(default_factory=dict)
    #: block travel at t = 0 (m below the top of its travel)
    block_x0_m: float = 0.0
    #: a ``block_mode: rop`` run on bottom: it starts in steady drilling at the set-point
    rig_rop_start: bool = False

    @property
    def n(self) -> int:
        """Allocated segment rows (the largest count the run can reach)."""
        return int(self.seg.shape[0])

    @property
    def rig_on(self) -> bool:
        """Whether the rig boundaries drive the string (docs/rig.md)."""
        return bool(self.bp[L.B_RIG] == 1.0)

    @property
    def n_ch(self) -> int:
        """Channels a force evaluation writes: ``N_CH``, ``N_CH_RIG`` with the rig boundaries."""
        return L.N_CH_RIG if self.rig_on else L.N_CH

    def new_work(self) -> None:
        """Allocate the work arrays of the kernels."""
        self.work = new_work(self.n, self.n_ch)

    @property
    def params(self) -> Params:
        """The kernels' view of the model (the same arrays, no copies)."""
        p = self.path
        return Params(dt=self.dt, seg=self.seg, jp=self.jp, bp=self.bp, topp=self.topp,
                      anchor=self.anchor, tab_t=self.tab_t, tab_w=self.tab_w, cpar=self.cpar,
                      node_md=p.node_md_m, node_pos=p.node_pos_m, node_tan=p.node_tan,
                      wall=p.wall, cp_n=self.cp_n, cp=self.cp, ei=self.ei, mlat=self.mlat)


def _series(h1: np.ndarray, k1: np.ndarray, h2: np.ndarray, k2: np.ndarray) -> np.ndarray:
    """Stiffness of two half-segments in series: 1 / (h1/k1 + h2/k2)."""
    return 1.0 / (h1 / k1 + h2 / k2)


def stable_step(seg: np.ndarray, jp: np.ndarray, bp: np.ndarray,
                cpar: np.ndarray | None = None, cp_n: np.ndarray | None = None) -> float:
    """Largest stable velocity-Verlet step (s) before the safety factor.

    Gershgorin bound on the eigenvalues of M^-1/2 K M^-1/2 of the linearised
    chain: per segment and per kind of DOF, the sum over its joints of
    |K_ab| / sqrt(m_a m_b), including the shear lever arms h and the boundary
    springs; omega_max^2 <= the largest row sum. dt = 2 / omega_max times
    (sqrt(1 + zeta^2) - zeta) for the largest damping ratio.

    With wall contact (``cpar[P_ON] != 0``) every contact point adds its
    penalty spring k_c (translation, and tilt through the lever arm h), and the
    a stiction law (Karnopp) adds the limit dt < 2 m_eff v_min / (mu_s N) (a slip
    overshoot in one step must land inside the stick band; m_eff = m / 3 for
    rolling/spinning), with N estimated as twice the segment's buoyed weight;
    the smaller step is taken. The smooth friction laws need no such limit:
    the force kernel caps their tangential force so one step cannot reverse
    the slip (:func:`drillfatigue.dynamics.contact.wall.wall_contact`). ``cp_n``
    (n,): contact points of each segment when they come from the string
    (``cpar[P_CPTAB]``), else every segment has ``cpar[P_NPTS]``.

    Not counted: the bit law's own damping of the bit segment's spin, ``c =
    dTOB/dOmega`` (it depends on the WOB of the moment; 2.4e4 N m s/rad just above
    the Yigit-Christoforou speed threshold at 100 kN), whose explicit limit ``2 I_a /
    c`` can lie below this bound (2.8e-4 s against 3.65e-4 s on the paper string);
    ``solver.implicit_bit_torque`` takes it implicitly
    (:func:`drillfatigue.dynamics.top.boundaries.implicit_bit_damping`).
    """
    n = seg.shape[0]
    m = seg[:, L.S_M]
    it = seg[:, L.S_IT]
    ia = seg[:, L.S_IA]
    h = seg[:, L.S_H]
    rows = np.zeros((n, 4))  # lateral, axial, bending, torsion

    def add(a: int, b: int, row: int) -> None:
        ka, ks, kb, kt = jp[row, L.J_KA], jp[row, L.J_KS], jp[row, L.J_KB], jp[row, L.J_KT]
        for p, o in ((a, b), (b, a)):
            if o < 0:
                rows[p, 0] += ks / m[p] + ks * h[p] / math.sqrt(m[p] * it[p])
                rows[p, 1] += ka / m[p]
                rows[p, 2] += (kb + ks * h[p] ** 2) / it[p] + ks * h[p] / math.sqrt(it[p] * m[p])
                rows[p, 3] += kt / ia[p]
                continue
            if p < 0:
                continue
            rows[p, 0] += (ks / m[p] + ks / math.sqrt(m[p] * m[o])
                           + ks * h[p] / math.sqrt(m[p] * it[p]) + ks * h[o] / math.sqrt(m[p] * it[o]))
            rows[p, 1] += ka / m[p] + ka / math.sqrt(m[p] * m[o])
            rows[p, 2] += ((kb + ks * h[p] ** 2) / it[p] + (kb + ks * h[p] * h[o]) / math.sqrt(it[p] * it[o])
                           + ks * h[p] / math.sqrt(it[p] * m[p]) + ks * h[p] / math.sqrt(it[p] * m[o]))
            rows[p, 3] += kt / ia[p] + kt / math.sqrt(ia[p] * ia[o])

    for j in range(n - 1):
        add(j, j + 1, j)
    add(n - 1, -1, n - 1)
    if bp[L.B_BITON] == 1.0:
        kbit = bp[L.B_KBIT]
        rows[0, 0] += kbit / m[0] + kbit * h[0] / math.sqrt(m[0] * it[0])
        rows[0, 1] += kbit / m[0]
        rows[0, 2] += kbit * h[0] ** 2 / it[0] + kbit * h[0] / math.sqrt(m[0] * it[0])
    dt_f = math.inf
    zc = 0.0
    if cpar is not None and cpar[L.P_ON] != 0.0:
        fr = friction
        kc = cpar[L.P_KC]
        npts = cpar[L.P_NPTS]
        if cp_n is not None and cpar[L.P_CPTAB] != 0.0:
            npts = np.maximum(cp_n[:n], npts)
        rows[:, 0] += npts * kc / m + 2.0 * kc * h / np.sqrt(m * it)
        rows[:, 2] += 2.0 * kc * h ** 2 / it + 2.0 * kc * h / np.sqrt(m * it)
        fp = cpar[L.P_FP:L.P_FP + fr.N_PARAMS]
        law = int(cpar[L.P_FMODEL])
        vmin = fr.slip_scale_m_per_s(law, fp)
        mu = max(fp[fr.I_MU_S], fp[fr.I_MU_D] * max(fp[fr.I_AX_RATIO], 1.0))
        w_seg = np.abs(seg[:, L.S_W]) + 1e-12
        if mu > 0.0 and fr.has_stiction(law):
            dt_f = float((2.0 * (m / 3.0) * vmin / (mu * 2.0 * w_seg)).min())
        cc = seg[:, L.S_CC]
        zc = float((cc / (2.0 * np.sqrt(kc * m / npts))).max())
    omega_max = math.sqrt(float(rows.max()))
    zeta = max(bp[L.B_ZB], bp[L.B_ZJ], zc)
    return min(2.0 / omega_max * (math.sqrt(1.0 + zeta * zeta) - zeta), dt_f)


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


def rpm_table(cfg: CaseConfig) -> tuple[np.ndarray, np.ndarray]:
    """Top-drive speed table: times (s) and speeds (rad/s)."""
    op = cfg.operation
    if op.rpm_table is not None:
        t = np.array([p[0] for p in op.rpm_table], dtype=np.float64)
        r = np.array([p[1] for p in op.rpm_table], dtype=np.float64)
    elif op.rpm_ramp_s > 0.0:
        t = np.array([0.0, op.rpm_ramp_s])
        r = np.array([0.0, op.rpm])
    else:
        t = np.array([0.0])
        r = np.array([op.rpm])
    return t, r * RAD_S_PER_RPM


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


def pack_boundaries(config: CaseConfig, segs: Segments, seg: np.ndarray,
                    refs: tuple[float, float, float], top_len: float
                    ) -> tuple[np.ndarray, np.ndarray]:
    """``bp`` (N_BP,): top drive / block and bit guide scalars, growth limits, event window
    (read by :mod:`boundaries`, :mod:`growth`, :mod:`events`); ``topp`` (N_TOPP,): the top
    section's per-length properties (read by :func:`growth.update_top`)."""
    op = config.operation
    sv = config.solver
    n = segs.n_segments
    ks_ref, kb_ref, ka_ref = refs
    zb = sv.boundary_damping_ratio
    m = seg[:, L.S_M]
    h = seg[:, L.S_H]
    ro2 = (0.5 * segs.od_m) ** 2 + (0.5 * segs.id_m) ** 2
    bp = np.zeros(L.N_BP)
    # with the rig the block holds the top axially (its spring to the top anchor)
    bp[L.B_AXMODE] = 1.0 if op.top_axial == "fixed" or config.rig is not None else 0.0
    bp[L.B_BITON] = 1.0 if op.bit_on_bottom else 0.0
    bp[L.B_KBIT] = ka_ref
    bp[L.B_CBIT] = 2.0 * zb * math.sqrt(ka_ref * m[0])
    bp[L.B_TOB] = op.tob_Nm if op.bit_on_bottom else 0.0
    bp[L.B_WREF] = OMEGA_REF_RAD_S
    bp[L.B_ROP] = op.rop_m_per_s if op.bit_on_bottom else 0.0
    bp[L.B_NLOBE] = op.lobe_count
    bp[L.B_LOBE] = op.lobe_amplitude_m if op.bit_on_bottom else 0.0
    bp[L.B_EXT] = op.rop_m_per_s if op.bit_on_bottom else op.trip_speed_m_per_s
    bp[L.B_G] = G
    bp[L.B_TOPAUTO_A] = 1.0 if sv.top_axial_stiffness_N_per_m is None else 0.0
    bp[L.B_TOPAUTO_T] = 1.0 if sv.top_torsional_stiffness_N_m_per_rad is None else 0.0
    bp[L.B_ZB] = zb
    bp[L.B_ZJ] = sv.joint_damping_ratio
    bp[L.B_MD0] = op.bit_md_m
    bp[L.B_GROWTRAP] = 1.0 if sv.growth_work_trapezoid or config.rig is not None else 0.0
    bp[L.B_IMPBIT] = 1.0 if sv.implicit_bit_torque else 0.0
    topp = np.zeros(L.N_TOPP)
    t_ = n - 1
    topp[L.T_MPL] = segs.mass_per_length_kg_per_m[t_]
    topp[L.T_EA] = segs.ea_N[t_]
    topp[L.T_EI] = segs.ei_Nm2[t_]
    topp[L.T_GJ] = segs.gj_Nm2[t_]
    topp[L.T_KGA] = segs.kga_N[t_]
    topp[L.T_R2] = ro2[t_]
    topp[L.T_WPL] = (segs.buoyed_weight_N / segs.length_m)[t_]
    topp[L.T_CLPL] = op.mud_damping_lateral_N_s_per_m2
    topp[L.T_CAPL] = op.mud_damping_axial_N_s_per_m2
    topp[L.T_CRLPL] = op.mud_damping_torsional_N_m_s_per_m
    topp[L.T_CRAPL] = op.mud_damping_torsional_N_m_s_per_m
    topp[L.T_H0] = h[t_]
    t2 = max(n - 2, 0)
    topp[L.T_EA2] = segs.ea_N[t2]
    topp[L.T_EI2] = segs.ei_Nm2[t2]
    topp[L.T_GJ2] = segs.gj_Nm2[t2]
    topp[L.T_KGA2] = segs.kga_N[t2]
    topp[L.T_KPAR_S] = sv.parasitic_stiffness_scale * ks_ref
    topp[L.T_KPAR_B] = sv.parasitic_stiffness_scale * kb_ref
    topp[L.T_KA_TOP] = sv.top_axial_stiffness_N_per_m or 0.0
    topp[L.T_KT_TOP] = sv.top_torsional_stiffness_N_m_per_rad or 0.0
    bp[L.B_TOPMODE] = 1.0 if op.top_mode == "torque" else 0.0
    bp[L.B_TOPTQ] = op.top_torque_Nm
    bp[L.B_TRAMP] = op.rpm_ramp_s
    bp[L.B_TOPLAT] = 1.0 if op.top_lateral == "held" else 0.0
    comp_top = config.string.components[-1]
    n_top = int((segs.component_index == len(config.string.components) - 1).sum())
    # the nominal length of the top component's segments (more than n_segments when
    # the hole-fit rule split it; a jointed component keeps its historical value)
    lnom = comp_top.length_m / (n_top if n_top > comp_top.n_segments
                                and comp_top.joints_per_segment is None else comp_top.n_segments)
    bp[L.B_LNOM] = lnom
    bp[L.B_LSPLIT] = max(2.0 * lnom, top_len + lnom)
    bp[L.B_LMIN] = min(0.5 * lnom, 0.5 * top_len)
    if op.rpm_table is not None:
        bp[L.B_TWIN] = float(op.rpm_table[-1][0]) if len(op.rpm_table) > 1 else 0.0
    else:
        bp[L.B_TWIN] = op.rpm_ramp_s
    if config.recording.events_start_s is not None:
        bp[L.B_TWIN] = config.recording.events_start_s
    return bp, topp


def pack_rig(config: CaseConfig, bp: np.ndarray, seg: np.ndarray, hook_off_N: float) -> dict:
    """Rig boundaries into ``bp`` (docs/rig.md; read by :func:`boundaries.rig_step`,
    :func:`boundaries.bit_guide`): block and top-drive modes and parameter vectors, the
    connection durations, the rock face (lobes, contact stiffness and damping). Returns the
    top-drive gains used and the autodriller's zero, for ``summary.json``.

    The rock contact stiffness defaults to the bit guide's (``bp[B_KBIT]``, the bit
    segment's axial joint stiffness) and its damping is ``contact_damping_ratio`` of
    critical for the bit segment's mass.
    """
    rig = config.rig
    assert rig is not None
    bp[L.B_RIG] = 1.0
    bmode, bpar = block_params(rig, hook_off_N)
    tmode, tpar, tinfo = top_drive_params(rig, config)
    bp[L.B_BLKMODE] = bmode
    bp[L.B_BLKP:L.B_BLKP + R.N_BLOCK_P] = bpar
    bp[L.B_TDMODE] = tmode
    bp[L.B_TDP:L.B_TDP + R.N_TD_P] = tpar
    con = rig.connection
    bp[L.B_CONON] = 1.0 if con.enabled else 0.0
    bp[L.B_CONDUR:L.B_CONDUR + N_PHASES] = [con.pickup_s, con.rotation_stop_s, con.slips_s, con.stand_s,
                                     con.slips_out_s, con.ramp_s, con.tag_s]
    bp[L.B_CONPICK] = con.pickup_m
    bp[L.B_CONSTAND] = con.stand_length_m
    rock = rig.rock
    on = config.operation.bit_on_bottom
    bp[L.B_NLOBE] = rock.lobe_count
    bp[L.B_LOBE] = rock.lobe_amplitude_m if on else 0.0
    k = rock.contact_stiffness_N_per_m if rock.contact_stiffness_N_per_m is not None \
        else float(bp[L.B_KBIT])
    bp[L.B_KROCK] = k
    bp[L.B_CROCK] = 2.0 * rock.contact_damping_ratio * math.sqrt(k * float(seg[0, L.S_M]))
    info = {"top_drive": tinfo, "rock_contact_stiffness_N_per_m": k,
            "rock_contact_damping_N_s_per_m": float(bp[L.B_CROCK])}
    if rig.block_mode == "autodriller":
        info["autodriller_hook_off_bottom_N"] = hook_off_N
    return info


def init_rig_state(model: Model, state: State, omega0: float, phi0: float) -> None:
    """Rig part of the scalar state at t = 0 (in place; docs/rig.md).

    Block at ``rig.block.initial_travel_m``; the autodriller starts at its steady
    state (integral giving the ROP of the bit law at the set-point WOB and the
    start speed, capped at its ROP limit, the block lowering at that ROP; the
    measurement at the starting WOB, :func:`static_preload`); a ``rop`` block on
    bottom starts lowering at its set-point, with the bit cutting the law's ROP at
    the initial (steady) WOB and the start speed; the top drive at the start speed
    and the initial drive angle, its PI integral holding the string's torque now
    (no start-up kick); no connection scheduled.
    """
    sc = state.sc
    bp = model.bp
    blk = sc[L.C_BLK:L.C_BLK + R.N_BLOCK_S]
    blk[:] = R.new_block_state(model.block_x0_m)
    rop0 = 0.0
    if int(bp[L.B_BLKMODE]) in (R.BLOCK_AUTODRILLER_WOB, R.BLOCK_AUTODRILLER_HOOK):
        out = np.zeros(2)
        bit_response(int(model.cpar[L.P_BITMODEL]),
                     model.cpar[L.P_BP:L.P_BP + bitrock.N_PARAMS],
                             float(bp[L.B_BLKP + R.BP_WOBSET]), omega0, out)
        rop0 = min(float(out[1]), float(bp[L.B_BLKP + R.BP_ROPLIM]))
        ki = float(bp[L.B_BLKP + R.BP_KI])
        blk[R.BS_I] = rop0 / ki if ki > 0.0 else 0.0
        blk[R.BS_VCMD] = rop0
        blk[R.BS_V] = rop0
        # the measurement starts at the WOB the string starts with (static_preload)
        wob0 = float(model.wob0_N)
        blk[R.BS_MEAS] = wob0 if int(bp[L.B_BLKMODE]) == R.BLOCK_AUTODRILLER_WOB \
            else float(bp[L.B_BLKP + R.BP_HOFF]) - wob0
    v_block = rop0
    if model.rig_rop_start:
        out = np.zeros(2)
        bit_response(int(model.cpar[L.P_BITMODEL]),
                     model.cpar[L.P_BP:L.P_BP + bitrock.N_PARAMS], model.wob0_N, omega0, out)
        rop0 = float(out[1])
        v_block = float(bp[L.B_BLKP + R.BP_VSET])
        blk[R.BS_V] = v_block
    sc[L.C_CON:L.C_CON + N_PHASES + 1] = -np.inf  # no connection yet: the drilling phase
    sc[L.C_TD + R.TS_OMEGA] = omega0
    sc[L.C_TD + R.TS_PHI] = phi0
    sc[L.C_PHID] = phi0
    sc[L.C_ROPNOW] = rop0
    sc[L.C_VGROW] = v_block


def start_rig_drive(model: Model, state: State) -> None:
    """The top drive's torque and PI integral from the string's torque at the current state."""
    assert model.work is not None
    top = state.n_active - 1
    t0 = float(model.work.loads[top, 5])
    sc = state.sc
    sc[L.C_TD + R.TS_T] = t0
    ki = float(model.bp[L.B_TDP + R.TP_KI])
    sc[L.C_TD + R.TS_I] = t0 / ki if ki > 0.0 else 0.0


@dataclass
class Preload:
    """Static start: hook load and WOB (N), neutral point (m from the bit or None), axial
    shift of each segment along its axis (m), twist of each segment (rad), drive angle."""

    hook_N: float
    wob_N: float
    s_np_m: float | None
    shift_m: np.ndarray
    psi_rad: np.ndarray
    phi_drive_rad: float
    total_axial_weight_N: float


def static_preload(config: CaseConfig, seg: np.ndarray, jp: np.ndarray, bp: np.ndarray,
                   place: Placement, omega0: float) -> Preload:
    """Hook load for the requested neutral point, and the axial and torsional pre-load of a
    straight hole (the run starts in static equilibrium there)."""
    op = config.operation
    n = seg.shape[0]
    s_top_end = place.s_top_end
    w_ax = seg[:, L.S_W] * place.e3s[:, 2]  # axial (downhole) component of the buoyed weight
    total_ax = float(w_ax.sum())
    s_np: float | None = None
    if not op.bit_on_bottom:
        wob = 0.0
        hook = total_ax
    elif config.rig is not None and config.rig.block_mode == "autodriller":
        # the autodriller starts in steady drilling: at its set-point, or, where the bit
        # law cuts faster than the ROP limit there, at the WOB that cuts the ROP limit
        ad = config.rig.effective_autodriller
        wob = ad.wob_set_N
        if config.bit.model in ROP_FROM_WOB_MODELS:
            w_lim, _, _ = steady_wob_for_rop_N(config.bit, ad.rop_limit_m_per_s,
                                               omega0 * 30.0 / math.pi, ad.wob_set_N)
            if math.isfinite(w_lim):  # NaN: the set-point cuts no faster than the limit
                wob = min(w_lim, ad.wob_set_N)
        hook = total_ax - wob
    elif config.rig is not None and config.rig.block_mode == "rop":
        # the block lowers at the ROP set-point: start in steady drilling, at the bit
        # law's WOB for that ROP, with the neutral point where the string's axial
        # weight from the bit up equals it (none when the WOB is above the string's
        # axial weight: the block pushes, the hook load is negative)
        wob = rop_start_wob_N(config.rig, config)
        hook = total_ax - wob
        cum = np.cumsum(w_ax)
        if 0.0 < wob <= total_ax and bool(np.all(np.diff(cum) >= 0.0)):
            s_np = float(np.interp(wob, np.concatenate([[0.0], cum]),
                                   np.concatenate([[0.0], s_top_end])))
    elif op.top_axial == "hook_load":
        hook = op.hook_load_N
        wob = total_ax - hook
    elif op.top_axial == "neutral_point":
        s_np = op.neutral_point_s_from_bit_m
        if s_np is None:
            collars = [k for k, c in enumerate(config.string.components) if c.type == "collar"]
            if not collars:
                raise InputError("operation.neutral_point_s_from_bit_m",
                                 "no collar component to put the neutral point at the top of",
                                 "a distance from the bit (m)")
            s_np = float(sum(c.length_m for c in config.string.components[:collars[-1] + 1]))
        if s_np >= s_top_end[-1]:
            raise InputError("operation.neutral_point_s_from_bit_m",
                             f"{s_np} m is above the top of the string",
                             f"< {s_top_end[-1]:.1f} m")
        cum = np.concatenate([[0.0], np.cumsum(w_ax)])
        wob = float(np.interp(s_np, np.concatenate([[0.0], s_top_end]), cum))
        hook = total_ax - wob
    else:  # fixed top, bit on bottom: no preload target; start with zero WOB
        wob = 0.0
        hook = total_ax
    if op.bit_on_bottom and wob < 0.0:
        raise InputError("operation.hook_load_N", f"hook load {hook:.0f} N exceeds the buoyed "
                         f"weight {total_ax:.0f} N (negative WOB)", f"<= {total_ax:.0f} N")
    # tension at each joint (straight-hole statics) and axial shifts from the bit up
    tension = np.cumsum(w_ax)[:-1] - wob if n > 1 else np.zeros(0)
    shift = np.zeros(n)
    shift[0] = wob / bp[L.B_KBIT] if op.bit_on_bottom else 0.0
    for j in range(n - 1):
        shift[j + 1] = shift[j] - tension[j] / jp[j, L.J_KA]
    # torsional pre-load: the TOB at the start speed, transmitted to the top
    tob0 = bp[L.B_TOB] * math.tanh(omega0 / OMEGA_REF_RAD_S)
    if op.bit_on_bottom and config.bit.model != "given_tob" and wob > 0.0:
        # the bit law's torque at the initial WOB and speed (no start-up kick)
        bid, bpar = bitrock.pack_bit_params(config.bit, op.rop_m_per_s)
        out2 = np.zeros(2)
        bit_response(bid, bpar, wob, omega0, out2)
        tob0 = float(out2[0])
    torque0 = tob0 + float((seg[:, L.S_CRA] * omega0).sum())
    psi = np.zeros(n)
    for j in range(n - 1):
        # the mud torque of the segments below joint j adds to the TOB
        tq = tob0 + float((seg[: j + 1, L.S_CRA] * omega0).sum())
        psi[j + 1] = psi[j] + tq / jp[j, L.J_KT]
    kt_top = jp[n - 1, L.J_KT]
    phi0 = psi[-1] + (torque0 / kt_top if kt_top > 0.0 else 0.0)
    return Preload(hook_N=hook, wob_N=wob, s_np_m=s_np, shift_m=shift, psi_rad=psi,
                   phi_drive_rad=phi0, total_axial_weight_N=total_ax)


def top_anchor(config: CaseConfig, jp: np.ndarray, place: Placement, centres: np.ndarray,
               hook_N: float) -> np.ndarray:
    """``anchor`` (10,): the top drive's position (the top end, offset by the top spring's
    stretch with the top fixed), orientation at zero drive angle and downhole axis."""
    n = jp.shape[0]
    e3s = place.e3s
    b_top = centres[-1] - place.h[-1] * e3s[-1]
    anchor = np.zeros(10)
    ka_top = jp[n - 1, L.J_KA]
    fixed = config.operation.top_axial == "fixed" or config.rig is not None
    anchor[0:3] = b_top - (hook_N / ka_top * e3s[-1] if fixed and ka_top > 0 else 0.0)
    anchor[3:7] = quat_from_rot(place.frames[-1])
    anchor[7:10] = e3s[-1]
    return anchor


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


def choose_step(config: CaseConfig, seg: np.ndarray, jp: np.ndarray, bp: np.ndarray,
                topp: np.ndarray, cpar: np.ndarray, cp_n: np.ndarray | None = None) -> float:
    """The step (s): ``solver.dt_s`` if given (checked against the stable step), else the
    largest step below safety x stable that divides the loads recording interval."""
    op = config.operation
    sv = config.solver
    n = seg.shape[0]
    dt_stable = stable_step(seg, jp, bp, cpar, cp_n)
    if not op.bit_on_bottom and op.trip_speed_m_per_s < 0.0 and n >= 2:
        # tripping out shortens the top segment to B_LMIN before it merges: a
        # lighter body on stiffer springs; take the step for that shortest top too
        seg_s, jp_s = seg.copy(), jp.copy()
        update_top(0.5 * bp[L.B_LMIN], n, seg_s, jp_s, topp, bp)
        dt_stable = min(dt_stable, stable_step(seg_s, jp_s, bp, cpar, cp_n))
    if sv.dt_s is not None:
        dt = sv.dt_s
        if dt > dt_stable:
            raise InputError("solver.dt_s", f"{dt} s exceeds the stable step {dt_stable:.3g} s",
                             f"<= {dt_stable:.3g} s")
        return dt
    t_rec = 1.0 / config.recording.loads_rate_hz
    return t_rec / math.ceil(t_rec / (sv.safety_factor * dt_stable) - 1e-9)


def energy_scale(config: CaseConfig, seg: np.ndarray, bp: np.ndarray, tab_w: np.ndarray,
                 total_ax: float, length_m: float) -> float:
    """Blow-up limit of the kinetic energy (J): ``solver.energy_blowup_factor`` x (weight x
    length + spin energy at the top speed + translation at the ROP + 1 J)."""
    op = config.operation
    omega_max = float(np.abs(tab_w).max())
    if op.top_mode == "torque":
        # steady spin under the applied torque against the mud: omega = T / sum(c_rot)
        c_rot = float(seg[:, L.S_CRA].sum()) + 1e-9
        omega_max = max(omega_max, abs(op.top_torque_Nm) / c_rot)
    e_scale = (abs(total_ax) * length_m + 0.5 * float(seg[:, L.S_IA].sum()) * omega_max ** 2
               + 0.5 * float(seg[:, L.S_M].sum()) * (bp[L.B_ROP] ** 2) + 1.0)
    return config.solver.energy_blowup_factor * e_scale


def record_every(rate_hz: float, dt_s: float) -> int:
    """Steps between two records at ``rate_hz`` with the step ``dt_s`` (at least 1): the
    grid of the recorder (:class:`drillfatigue.dynamics.run.simulation.Runner`) and of the span
    filter."""
    return max(1, round(1.0 / (rate_hz * dt_s)))


def build_model(config: CaseConfig, path: WellPath) -> tuple[Model, State]:
    """Pack a case into kernel arrays and the initial (pre-loaded) state.

    One packer per submodel: :func:`place_segments`, :func:`pack_segments`
    (rigid bodies, weight, mud), :func:`pack_joints`, :func:`pack_boundaries`
    (top drive and block, bit guide, growth, events), :func:`static_preload`,
    :func:`top_anchor`, :func:`pack_contact` and :func:`pack_wall` (wall contact,
    friction, bit law), :func:`choose_step`, :func:`energy_scale`.

    Parameters
    ----------
    config : CaseConfig
        Validated case.
    path : WellPath
        Well centre line.

    Returns
    -------
    (Model, State)
    """
    op = config.operation
    segs = build_segments(config.string, op.mud_density_kg_per_m3, hole_fit(config, path))
    n = segs.n_segments
    place = place_segments(config, segs, path)
    seg = pack_segments(config, segs, place.lengths)
    jp, refs = pack_joints(config, segs, seg)
    bp, topp = pack_boundaries(config, segs, seg, refs, place.top_len)
    update_top(place.h[n - 1], n, seg, jp, topp, bp)
    tab_t, tab_w = rpm_table(config)
    omega0 = float(tab_w[0])
    pre = static_preload(config, seg, jp, bp, place, omega0)
    bp[L.B_HL] = pre.hook_N
    rig_info: dict = {}
    if config.rig is not None:
        # the autodriller's zero: the rotating off-bottom hook load, here the string's
        # axial buoyed weight (pure rotation: no axial drag in the soft-string limit)
        rig_info = pack_rig(config, bp, seg, pre.total_axial_weight_N)
        if op.bit_on_bottom:
            # the rock spring carries the initial WOB
            pre.shift_m += pre.wob_N / bp[L.B_KROCK] - pre.shift_m[0]
    centres = place.centres + pre.shift_m[:, None] * place.e3s
    q = np.array([quat_from_rot(place.frames[i] @ _rotz(pre.psi_rad[i])) for i in range(n)])
    anchor = top_anchor(config, jp, place, centres, pre.hook_N)
    # the string below the top moves down with the bit at the ROP; the top
    # segment's top end stays at the rig floor (its growth is kinematic)
    v = bp[L.B_ROP] * place.e3s.copy()
    v[-1] = 0.0
    w = np.zeros((n, 3))
    w[:, 2] = omega0
    cpar = pack_contact(config)
    cp_n = cp = None
    if cpar[L.P_CPTAB] != 0.0:
        cp_n, cp = pack_contact_points(config, segs, place, path)
    pack_wall(config, segs, seg, cpar, cp_n)
    dt = choose_step(config, seg, jp, bp, topp, cpar, cp_n)
    bp[L.B_DT] = dt
    if cpar[L.P_SPAN] != 0.0 and config.contact.span_dynamic:
        # the span filter steps on the loads record's grid
        cpar[L.P_SPANDYN] = float(record_every(config.recording.loads_rate_hz, dt))
        cpar[L.P_SPANZ] = config.contact.span_damping_min
    bp[L.B_ESCALE] = energy_scale(config, seg, bp, tab_w, pre.total_axial_weight_N,
                                  float(place.s_top_end[-1]))
    sc = np.zeros(L.N_SC_RIG if config.rig is not None else L.N_SC)
    sc[L.C_PHID] = pre.phi_drive_rad
    sc[L.C_NACT] = n
    sc[L.C_MDROCK] = op.bit_md_m
    sc[L.C_ROPNOW] = bp[L.B_ROP]
    lnom = float(bp[L.B_LNOM])
    nmax = max_segments(config, n, lnom, float(np.abs(tab_w).max()), pre.total_axial_weight_N)

    def pad(a: np.ndarray, fill: float = 0.0) -> np.ndarray:
        out = np.full((nmax,) + a.shape[1:], fill, dtype=a.dtype)
        out[: a.shape[0]] = a
        return np.ascontiguousarray(out)

    model = Model(segments=segs, path=path, seg=pad(seg), jp=pad(jp), bp=bp, topp=topp,
                  anchor=anchor, tab_t=tab_t, tab_w=tab_w, dt=dt, hook_load_N=pre.hook_N,
                  wob0_N=pre.wob_N, neutral_point_s_from_bit_m=pre.s_np_m,
                  top_length_m=place.top_len, cpar=cpar, n0=n, segment_length_m=lnom,
                  rig_info=rig_info,
                  block_x0_m=config.rig.block.initial_travel_m if config.rig is not None else 0.0,
                  rig_rop_start=(config.rig is not None and config.rig.block_mode == "rop"
                                 and op.bit_on_bottom))
    # bending stiffness per row for the span correction; rows split off the top later
    # have the top's section
    model.ei = np.ascontiguousarray(np.r_[segs.ei_Nm2, np.full(nmax - n, segs.ei_Nm2[-1])])
    model.mlat = pack_lateral_mass(config, segs, path, cpar, nmax)
    n_hint = L.MAX_CONTACT_POINTS * nmax
    if cp_n is not None and cp is not None:
        model.cp_n, model.cp = _pad_points(cp_n, cp, n, nmax, lnom, seg[n - 1, L.S_RC])
        n_hint += L.MAX_TABLE_POINTS * nmax
    else:
        model.cp_n, model.cp = np.zeros(nmax), np.zeros((nmax, L.MAX_TABLE_POINTS, 2))
    qp = pad(q)
    qp[n:, 0] = 1.0
    cst = np.zeros((nmax, L.N_CST))
    cst[:, L.CS_ONT] = -1.0
    state = State(x=pad(np.ascontiguousarray(centres)), v=pad(v), q=qp, w=pad(w),
                  Fw=np.zeros((nmax, 3)), Mw=np.zeros((nmax, 3)), Mb=np.zeros((nmax, 3)), sc=sc,
                  hint=np.zeros(n_hint, dtype=np.int64), cst=cst)
    _init_hints(model, state)
    model.new_work()
    if model.rig_on:
        init_rig_state(model, state, omega0, pre.phi_drive_rad)
        # the string below the top moves down with the block
        v_block = float(state.sc[L.C_VGROW])
        state.v[: n - 1] = v_block * place.e3s[: n - 1]
    evaluate_forces(model, state)
    if config.solver.relax_s > 0.0:
        relax_state(model, state, config.solver.relax_s)
    if model.rig_on:
        start_rig_drive(model, state)
    return model, state


#: Damping rate (1/s) of the relaxation pre-run: c = RELAX_RATE_PER_S x mass
#: (or inertia) on every segment, translation and rotation; heavily damps the
#: low modes (a 40 mm drop onto the low side settles in ~0.1 s) and, as
#: RELAX_RATE_PER_S dt << 2, keeps the explicit step stable.
RELAX_RATE_PER_S = 20.0


def relax_state(model: Model, state: State, relax_s: float) -> None:
    """Damped pre-run that settles the string in the hole before t = 0 (in place).

    The string starts as chords of the well path with straight-hole axial and
    torsional pre-loads; in a curved hole with wall contact it is not in
    equilibrium (it sags onto the low side, the build section pushes on the
    wall). For ``relax_s`` seconds the model runs with the top drive at rest
    (rpm table and top torque zero), no ROP or tripping (``bp[B_FREEZE]``),
    and extra viscous damping ``RELAX_RATE_PER_S`` x mass / inertia on every
    segment. Afterwards the damping, drive and ROP are restored, the initial
    translational / angular velocities of the case are put back, and time,
    energy counters, bit-bounce count and contact statistics start from zero.
    """
    n = model.n0
    cols = (L.S_CL, L.S_CA, L.S_CRL, L.S_CRA)
    saved = model.seg[:, cols].copy()
    tab_w = model.tab_w.copy()
    tq = float(model.bp[L.B_TOPTQ])
    v0, w0 = state.v.copy(), state.w.copy()
    seg = model.seg
    b = RELAX_RATE_PER_S
    seg[:n, L.S_CL] += b * seg[:n, L.S_M]
    seg[:n, L.S_CA] += b * seg[:n, L.S_M]
    seg[:n, L.S_CRL] += b * seg[:n, L.S_IT]
    seg[:n, L.S_CRA] += b * seg[:n, L.S_IA]
    model.tab_w[:] = 0.0
    model.bp[L.B_TOPTQ] = 0.0
    model.bp[L.B_FREEZE] = 1.0
    state.w[:n, 2] = 0.0
    try:
        steps = max(1, int(round(relax_s / model.dt)))
        advance_model(model, state, steps, every=steps)
    finally:
        model.seg[:, cols] = saved
        model.tab_w[:] = tab_w
        model.bp[L.B_TOPTQ] = tq
        model.bp[L.B_FREEZE] = 0.0
    state.v[...] = v0
    state.w[...] = w0
    sc = state.sc
    if model.rig_on:
        sc[L.C_TD + R.TS_OMEGA] = tab_w[0]
        sc[L.C_VGROW] = sc[L.C_BLK + R.BS_V]
    for k in (L.C_STEP, L.C_WIN, L.C_DISS, L.C_BOUNCE, L.C_OFFB):
        sc[k] = 0.0
    state.cst[...] = 0.0
    state.cst[:, L.CS_ONT] = -1.0
    evaluate_forces(model, state)


def raise_for_status(st: int, info: np.ndarray, model: Model) -> None:
    """Turn a kernel status code into :class:`SimulationError` (nothing for ``OK``).

    ``info`` = [step, segment (-1 unknown), value] as :func:`integrator.advance`
    writes it. The message names the time, the segment (and its distance from
    the bit), what went wrong and the likely causes.
    """
    if st == status.OK:
        return
    t = info[0] * model.dt
    i = int(info[1])
    if 0 <= i < model.n:
        h = model.seg[: i + 1, L.S_H]
        where = f"segment {i} ({2.0 * float(h[:i].sum()) + float(h[i]):.1f} m from the bit)"
    else:
        where = "an unknown segment"
    if st == status.SPEED:
        why = (f"a speed above the divergence bound ({status.MAX_SPEED_M_PER_S:g} m/s or "
               f"{status.MAX_SPIN_RAD_S:g} rad/s, {math.sqrt(info[2]):.3g} x the bound)")
    elif st == status.NONFINITE:
        why = "a non-finite state"
    elif st == status.BLOWUP:
        why = f"kinetic energy {info[2]:.3g} J above the blow-up limit {model.bp[L.B_ESCALE]:.3g} J"
    elif st in (status.UNKNOWN_FRICTION, status.UNKNOWN_BIT):
        raise SimulationError(f"the force evaluation failed at t = {t:.6g} s: "
                              f"{status.MESSAGES[st]} (friction id {int(model.cpar[L.P_FMODEL])}, "
                              f"bit id {int(model.cpar[L.P_BITMODEL])})")
    else:
        why = f"status {st}"
    raise SimulationError(
        f"simulation diverged at t = {t:.6g} s in {where}: {why}; likely cause: a step too large "
        f"for the stiffest element (dt = {model.dt:.3g} s; lower solver.safety_factor or "
        "solver.dt_s) or an unphysical input (stiffness, contact penalty, speed, torque)")


def evaluate_forces(model: Model, state: State) -> np.ndarray:
    """Fill ``state.Fw/Mw/Mb`` and ``model.work.loads/ch`` at the current state; return ch."""
    st = compute_forces(state, model.params, model.work)
    raise_for_status(st, np.array([state.sc[L.C_STEP], -1.0, 0.0]), model)
    return model.work.ch


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


def max_segments(config: CaseConfig, n0: int, lnom: float, omega_max: float,
                 weight_N: float) -> int:
    """Rows to allocate: n0 plus the segments drilling / tripping in can add over the run.

    Growth rate bound: the prescribed ROP, the trip speed, or for the computed
    ROP the Sarker law at the whole buoyed weight and the largest speed; capped
    by ``solver.max_segments`` when set.
    """
    op = config.operation
    if op.bit_on_bottom:
        rate = op.rop_m_per_s
        law = bitrock.LAWS[bitrock.MODEL_IDS[config.bit.model]]
        bound = law.rop_bound_m_per_s(config.bit, abs(weight_N), omega_max)
        if bound is not None:
            rate = max(rate, bound)
    else:
        rate = max(op.trip_speed_m_per_s, 0.0)
    extra = int(math.ceil(rate * op.duration_s / max(lnom, 1e-6))) + 2 if rate > 0 else 0
    cap = config.solver.max_segments
    nmax = n0 + extra
    if cap is not None:
        nmax = max(n0, min(nmax, cap))
    return nmax


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


def advance_model(model: Model, state: State, n_steps: int, *, joints: np.ndarray | None = None,
                  every: int = 1, chunk: int = 100_000) -> dict[str, np.ndarray]:
    """Advance ``state`` by ``n_steps`` steps in memory, recording every ``every`` steps.

    A thin loop over :func:`drillfatigue.dynamics.step.integrator.advance` for tests,
    benchmarks and the surrogate: returns ``time_s`` (n_rec,), ``loads``
    (n_rec, n_joint, 6) of the selected ``joints`` (default all), ``channels``
    (n_rec, N_CH + 4) = [time, ch..., kinetic energy, work in, dissipated] and
    ``xv`` (n_rec, n, 6) positions and velocities.

    Raises
    ------
    SimulationError
        When the kernel reports a non-finite state or an energy blow-up.
    """
    n = model.n
    sel = np.arange(model.n0 - 1, dtype=np.int64) if joints is None else np.asarray(joints, dtype=np.int64)
    rows = min(chunk, n_steps) // every + 2
    out_l, out_c, out_k = [], [], []
    done = 0
    params = model.params
    while done < n_steps:
        k = min(chunk, n_steps - done)
        rec = new_records(sel, (every, every, every), (rows, rows, rows), n, model.n_ch,
                          span=model.cpar[L.P_SPAN] != 0.0)
        st = advance(k, state, params, model.work, rec)
        raise_for_status(st, rec.info, model)
        out_l.append(rec.buf_l[: rec.counts[0]])
        out_c.append(rec.buf_c[: rec.counts[1]])
        out_k.append(rec.buf_k[: rec.counts[2]])
        done += k
    bl = np.concatenate(out_l)
    bc = np.concatenate(out_c)
    bk = np.concatenate(out_k)
    k8 = bk[:, 1:].reshape(-1, n, 8)
    nl = 6 * sel.size
    out = {"time_s": bl[:, 0], "loads": bl[:, 1:1 + nl].reshape(-1, sel.size, 6), "channels": bc,
           "xv": k8[:, :, :6], "contact": k8[:, :, 6:]}
    if bl.shape[1] > 1 + nl:
        out["span_bending"] = bl[:, 1 + nl:].reshape(-1, sel.size, 2)
    return out


def total_energy(model: Model, state: State) -> float:
    """Kinetic + spring + boundary + gravity potential energy (J) at the current state."""
    saved = state.sc.copy()
    ch = evaluate_forces(model, state)
    state.sc[...] = saved
    return float(kinetic_energy(state.v, state.w, model.seg) + ch[L.H_PE] + ch[L.H_PG])
