"""The top and the rig of a case: the rpm table, the boundary scalars ``bp``, the rig's blocks
and state, the static preload, the top anchor and the growth allowance."""

from __future__ import annotations


import math
from dataclasses import dataclass

import numpy as np

from drillfatigue.units import RAD_S_PER_RPM, STANDARD_GRAVITY_M_PER_S2, rpm_from_rad_per_s

from drillfatigue.config import CaseConfig
from drillfatigue.dynamics.top.setup import block_params, rop_start_wob_N, top_drive_params
from drillfatigue.dynamics.bit.laws import registry as bitrock
from drillfatigue.dynamics.bit.laws.kernel import bit_response
from drillfatigue.dynamics.core import layout as L
from drillfatigue.dynamics.top import rig as R
from drillfatigue.dynamics.top.connection import N_PHASES
from drillfatigue.dynamics.core.bundles import State
from drillfatigue.dynamics.core.rigid import quat_from_rot
from drillfatigue.dynamics.bit.rockface import ROP_FROM_WOB_MODELS, steady_wob_for_rop_N
from drillfatigue.errors import InputError
from drillfatigue.string import Segments

from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from drillfatigue.dynamics.core.pack import Placement
    from drillfatigue.dynamics.run.model import Model

#: TOB regularisation speed (rad/s): TOB(omega) = TOB tanh(omega / OMEGA_REF).
OMEGA_REF_RAD_S = 0.5




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
    bp[L.B_G] = STANDARD_GRAVITY_M_PER_S2
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
                                               rpm_from_rad_per_s(omega0), ad.wob_set_N)
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

