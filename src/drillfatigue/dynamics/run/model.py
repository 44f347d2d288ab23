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
from drillfatigue.dynamics.core import layout as L
from drillfatigue.dynamics.core import status
from drillfatigue.dynamics.top import rig as R
from drillfatigue.dynamics.core.bundles import Params, State, Work, new_records, new_work
from drillfatigue.dynamics.step.forces import compute_forces
from drillfatigue.dynamics.top.growth import update_top
from drillfatigue.dynamics.step.integrator import advance, kinetic_energy
from drillfatigue.dynamics.core.rigid import quat_from_rot
from drillfatigue.errors import SimulationError
from drillfatigue.string import Segments, build_segments
from drillfatigue.well.kernels import path_point
from drillfatigue.dynamics.contact.pack import (
    _init_hints, _pad_points, hole_fit, pack_contact, pack_contact_points, pack_wall,
)
from drillfatigue.dynamics.core.pack import (
    _rotz, pack_joints, pack_lateral_mass, pack_segments, place_segments,
)
from drillfatigue.dynamics.step.pack import choose_step, energy_scale
from drillfatigue.dynamics.top.pack import (
    init_rig_state, max_segments, pack_boundaries, pack_rig, rpm_table, start_rig_drive,
    static_preload, top_anchor,
)


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
    assert model.work is not None  # built with the model
    return model.work.ch


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
