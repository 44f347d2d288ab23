"""Boundaries of the string: the top drive and hoisting system at the top, the bit guide below.

Top (docs/model.md#top-boundary). A joint (:func:`drillfatigue.dynamics.core.joints.joint_force`)
ties the top segment's upper end to the top drive, a virtual body at
``anchor[0:3]`` with orientation ``anchor[3:7] * rot_z(phi_drive)`` turning at
the rpm table's speed about the downhole axis ``anchor[7:10]``
(:func:`top_joint`); its springs (``jp[n-1]``): axially the top held by a
spring (top fixed) or none (a hook-load force instead, the block following
the string), stiff lateral and tilt "parasitic" springs (or none with a free
top), a torsion spring to the driven angle (or none with an applied top
torque, ramped over ``bp[B_TRAMP]``). :func:`top_boundary` adds those loads,
the applied torque and the hook-load force, and writes the surface channels.

Bit (docs/model.md#bit). The bit face is guided along the well path: a stiff
isotropic spring-damper (``bp[B_KBIT]``, ``bp[B_CBIT]``) ties it laterally to
the path at its own depth and axially to the rock face (unilateral: WOB >= 0,
zero is bit bounce), which advances at the ROP and carries the lobed bit
motion s0 sin(n phi_bit); the torque on bit opposes the bit's rotation, from
the bit-rock law (:mod:`bitrock`) or TOB tanh(omega / omega_ref)
(:func:`bit_guide`).

Arrays: reads the state ``s`` (x, v, w), ``p.seg, p.jp, p.bp, p.anchor,
p.tab_t, p.tab_w, p.cpar`` and the path nodes, ``wk.R, wk.wW``; writes
``s.Fw, s.Mw, s.Mb`` (adds), ``wk.loads[n-1]`` (the top boundary's loads),
``wk.ch`` (surface torque, hook load, rpms, WOB, TOB, ROP, bit MD; adds the
boundary terms of the energy and power channels) and the scalar state
(``sc[C_HINT]``, ``sc[C_ROPNOW]``, bit bounce); scratch rows ``V_D_*``,
``V_B_*``, ``V_J_*`` of ``wk.vec`` and ``M_D_R`` of ``wk.mat``.
"""

from __future__ import annotations

import math

from numba import njit

from drillfatigue.dynamics.bit.laws.dispatch import rop_prescribed
from drillfatigue.dynamics.bit.laws.kernel import bit_response, bit_torque_slope
from drillfatigue.dynamics.bit.laws.registry import N_PARAMS as N_BIT_PARAMS
from drillfatigue.dynamics.top.connection import (
    CC_BLOCK_V, CC_RPM_FACTOR, CC_SLIPS, CC_TRAVEL_SHIFT, N_PHASES, PH_DRILL, connection_controls,
)
from drillfatigue.dynamics.contact.events import count_bounce
from drillfatigue.dynamics.core.joints import joint_force
from drillfatigue.dynamics.core.layout import (
    B_AXMODE, B_BITON, B_BLKMODE, B_IMPBIT, B_BLKP, B_CBIT, B_CONDUR, B_CONON, B_CONPICK, B_CONSTAND,
    B_CROCK, B_FREEZE, B_HL, B_KBIT, B_KROCK, B_LOBE, B_NLOBE, B_RIG, B_ROP, B_TDMODE, B_TDP,
    B_TOB, B_TOPMODE, B_TOPTQ, B_TRAMP, B_WREF, C_BLK, C_CON, C_CONP, C_CONPH, C_HINT, C_MDROCK,
    C_NSTAND, C_PHIB, C_PHID, C_ROPNOW, C_SHIFTED, C_TD, C_TSET, C_VGROW, H_BITMD, H_BITRPM,
    H_BLOCK, H_BLOCKV, H_CONPH, H_HOOK, H_PDISS, H_PE, H_PIN, H_ROP, H_TOB, H_TOPRPM, H_TOPSTR,
    H_TSURF, H_WOB, J_KA, P_BITLAW, P_BITMODEL, P_BP,
    S_H, S_IA, C_NACT, M_D_R, V_B_DV, V_B_DX, V_B_F, V_B_IMP, V_B_OUT, V_B_P2, V_B_POS, V_B_T2,
    V_B_TAN, V_D_P, V_D_Q, V_D_QZ, V_D_V, V_D_W, V_J_ED, V_J_F, V_J_MLO, V_J_MUP,
)
from drillfatigue.units import RPM_PER_RAD_S
from drillfatigue.dynamics.top.rig import (
    BLOCK_AT_FLOOR, BLOCK_BAD_MODE, BLOCK_NONFINITE, BLOCK_VELOCITY, BP_VSET, BS_V, BS_X,
    N_BLOCK_P, N_BLOCK_S, N_TD_P, N_TD_S, TD_BAD_MODE, TD_NONFINITE, TOP_DRIVE_PI, TS_OMEGA,
    TS_PHI, TS_T, block_step, top_drive_step,
)
from drillfatigue.dynamics.core.rigid import quat_mul, quat_to_rot
from drillfatigue.dynamics.bit.rockface import rock_face_contact
from drillfatigue.dynamics.core.status import NONFINITE, OK, UNKNOWN_RIG_MODE
from drillfatigue.well.kernels import path_point



@njit(cache=True)
def drive_omega(t, tab_t, tab_w):
    """Top-drive angular speed (rad/s) at time t: piecewise linear table, held at the ends."""
    K = tab_t.size
    if t <= tab_t[0]:
        return tab_w[0]
    if t >= tab_t[K - 1]:
        return tab_w[K - 1]
    i = 0
    while tab_t[i + 1] < t:
        i += 1
    f = (t - tab_t[i]) / (tab_t[i + 1] - tab_t[i])
    return (1.0 - f) * tab_w[i] + f * tab_w[i + 1]


@njit(cache=True)
def drive_speed(t, s, p):
    """Top-drive speed (rad/s) at time t: the rpm table, or the top-drive state of the rig."""
    if p.bp[B_RIG] == 1.0:
        return s.sc[C_TD + TS_OMEGA]
    return drive_omega(t, p.tab_t, p.tab_w)


@njit(cache=True)
def rig_step(t0, s, p, wk):
    """One step of the rig boundaries from time ``t0`` (docs/rig.md).

    In this order: the measured hook load (axial load of the top boundary) and
    WOB of the last force evaluation; the connection controls at ``t0``
    (:func:`connection.connection_controls`; rpm factor, block velocity
    override, slips); the block (:func:`rig.block_step`) in its mode or at the
    connection's velocity; a connection scheduled when the block reaches the
    floor; the block travel shortened by a stand once the stand is in; the rate
    at which the string below the rotary grows, ``sc[C_VGROW]`` (the block's
    mean velocity over the step, 0 while the slips are set); the top drive
    (:func:`rig.top_drive_step`) on the set-point (rpm table x connection
    factor) against the string's torque, whose angle becomes the drive angle
    ``sc[C_PHID]``. During the relaxation pre-run nothing moves. Returns a
    status code.
    """
    sc = s.sc
    bp = p.bp
    dt = p.dt
    if bp[B_FREEZE] == 1.0:
        sc[C_VGROW] = 0.0
        sc[C_TD + TS_OMEGA] = 0.0
        return OK
    top = int(sc[C_NACT]) - 1
    hook = wk.loads[top, 0]
    wob = wk.ch[H_WOB]
    blk = sc[C_BLK:C_BLK + N_BLOCK_S]
    bpar = bp[B_BLKP:B_BLKP + N_BLOCK_P]
    cc = wk.rig.cc
    cst = sc[C_CON:C_CON + N_PHASES + 1]
    cpar = sc[C_CONP:C_CONP + 3]
    ph = connection_controls(t0, cst, cpar, cc)
    sc[C_CONPH] = ph
    x0 = blk[BS_X]
    if ph != PH_DRILL:
        bv = wk.rig.bpar
        for k in range(N_BLOCK_P):
            bv[k] = bpar[k]
        bv[BP_VSET] = cc[CC_BLOCK_V]
        st = block_step(BLOCK_VELOCITY, bv, blk, wob, hook, dt)
    else:
        st = block_step(int(bp[B_BLKMODE]), bpar, blk, wob, hook, dt)
    if st == BLOCK_BAD_MODE:
        return UNKNOWN_RIG_MODE
    if st == BLOCK_NONFINITE:
        return NONFINITE
    x1 = blk[BS_X]
    slips = cc[CC_SLIPS] == 1.0
    if st == BLOCK_AT_FLOOR and bp[B_CONON] == 1.0 and ph == PH_DRILL and t0 + dt >= cst[7]:
        # a connection: its phases start now
        t = t0 + dt
        cst[0] = t
        for k in range(7):
            t += bp[B_CONDUR + k]
            cst[k + 1] = t
        cpar[0] = bp[B_CONPICK]
        cpar[1] = bp[B_CONSTAND]
        sc[C_SHIFTED] = 0.0
    if cc[CC_TRAVEL_SHIFT] > 0.0 and sc[C_SHIFTED] == 0.0:
        # the stand is in: the block went back up by a stand while the string below the
        # rotary grew by it (slips set), so the top segment keeps its length
        blk[BS_X] -= cc[CC_TRAVEL_SHIFT]
        sc[C_SHIFTED] = 1.0
        sc[C_NSTAND] += 1.0
    sc[C_VGROW] = 0.0 if slips else (x1 - x0) / dt
    # top drive: set-point from the rpm table and the connection's factor, and its rate
    w0 = drive_omega(t0, p.tab_t, p.tab_w) * cc[CC_RPM_FACTOR]
    cc1 = wk.rig.cc1
    connection_controls(t0 + dt, cst, cpar, cc1)
    w1 = drive_omega(t0 + dt, p.tab_t, p.tab_w) * cc1[CC_RPM_FACTOR]
    td = sc[C_TD:C_TD + N_TD_S]
    tst = top_drive_step(int(bp[B_TDMODE]), bp[B_TDP:B_TDP + N_TD_P], td, w0, (w1 - w0) / dt,
                         wk.loads[top, 5], dt)
    if tst == TD_BAD_MODE:
        return UNKNOWN_RIG_MODE
    if tst == TD_NONFINITE:
        return NONFINITE
    sc[C_PHID] = td[TS_PHI]
    sc[C_TSET] = w1
    return OK


@njit(cache=True, inline="always")
def top_joint(t, top, s, p, wk, loads_row):
    """Loads of the top boundary: the top segment's upper end tied to the top drive.

    ``top`` is the row of the top segment. Writes ``wk.vec[V_J_F]`` (force on the
    top segment, world), ``wk.vec[V_J_MLO]`` (its moment), ``wk.vec[V_J_MUP]``
    (moment on the drive), ``wk.vec[V_D_W]`` (drive angular velocity),
    ``loads_row`` and ``wk.vec[V_J_ED]``. Returns the drive speed (rad/s).

    With the hook-load force at the top (no axial spring, ``jp[top, J_KA] == 0``)
    the drive follows the top of the string axially, as a travelling block does:
    the attachment point slides along the drive axis to the axial position of
    the segment's upper end. Otherwise an axial drift of the string (drag,
    growth, bit vibration) would put a lever arm between the lateral hold and
    the segment's end, coupling the stiff lateral spring into the tilt with a
    stiffness ~ k_s * gap^2 that outgrows the stable step.
    """
    x = s.x
    v = s.v
    R = wk.R
    wW = wk.wW
    seg = p.seg
    jp = p.jp
    anchor = p.anchor
    vec = wk.vec
    omega_d = drive_speed(t, s, p)
    phid = s.sc[C_PHID]
    qz = vec[V_D_QZ]
    qz[0] = math.cos(0.5 * phid)
    qz[1] = 0.0
    qz[2] = 0.0
    qz[3] = math.sin(0.5 * phid)
    qa = vec[V_D_Q]
    quat_mul(anchor[3:7], qz, qa)
    Ra = wk.mat[M_D_R]
    quat_to_rot(qa, Ra)
    wa = vec[V_D_W]
    va = vec[V_D_V]
    for k in range(3):
        wa[k] = omega_d * anchor[7 + k]
        va[k] = 0.0
    pa = vec[V_D_P]
    for k in range(3):
        pa[k] = anchor[k]
    if jp[top, J_KA] == 0.0:
        h = seg[top, S_H]
        s_ax = 0.0
        for k in range(3):
            r_k = -h * R[top, k, 2]
            s_ax += (x[top, k] + r_k - anchor[k]) * anchor[7 + k]
        # velocity of the upper end along the axis: v + w x r, r = -h e3
        r0 = -h * R[top, 0, 2]
        r1 = -h * R[top, 1, 2]
        r2 = -h * R[top, 2, 2]
        v_ax = ((v[top, 0] + wW[top, 1] * r2 - wW[top, 2] * r1) * anchor[7]
                + (v[top, 1] + wW[top, 2] * r0 - wW[top, 0] * r2) * anchor[8]
                + (v[top, 2] + wW[top, 0] * r1 - wW[top, 1] * r0) * anchor[9])
        for k in range(3):
            pa[k] = anchor[k] + s_ax * anchor[7 + k]
            va[k] = v_ax * anchor[7 + k]
    joint_force((x[top], v[top], R[top], s.q[top], wW[top], seg[top, S_H]),
                (pa, va, Ra, qa, wa, 0.0), jp[top],
                (vec[V_J_F], vec[V_J_MLO], vec[V_J_MUP], loads_row, vec[V_J_ED]))
    return omega_d


@njit(cache=True, inline="always")
def top_boundary(t, n, s, p, wk):
    """Top drive and hoisting system on the top segment (row n-1); see the module docstring."""
    x = s.x
    w = s.w
    Fw = s.Fw
    Mw = s.Mw
    Mb = s.Mb
    R = wk.R
    ch = wk.ch
    loads = wk.loads
    bp = p.bp
    anchor = p.anchor
    vec = wk.vec
    top = n - 1
    omega_d = top_joint(t, top, s, p, wk, loads[top])
    Fl = vec[V_J_F]
    Ml = vec[V_J_MLO]
    Mu = vec[V_J_MUP]
    wa = vec[V_D_W]
    ch[H_PE] += vec[V_J_ED, 0]
    ch[H_PDISS] += vec[V_J_ED, 1]
    for k in range(3):
        Fw[top, k] += Fl[k]
        Mw[top, k] += Ml[k]
    if bp[B_TOPMODE] == 1.0:
        # applied torque about the top segment's axis (no drive spring)
        tq = bp[B_TOPTQ]
        if bp[B_TRAMP] > 0.0 and t < bp[B_TRAMP]:
            tq *= t / bp[B_TRAMP]
        Mb[top, 2] += tq
        ch[H_PIN] += tq * w[top, 2]
        ch[H_TSURF] = tq
        ch[H_TOPRPM] = w[top, 2] * RPM_PER_RAD_S
    else:
        # the drive works on the string: minus the reaction moment on the drive times its speed
        ch[H_PIN] -= Mu[0] * wa[0] + Mu[1] * wa[1] + Mu[2] * wa[2]
        ch[H_TSURF] = loads[top, 5]
        ch[H_TOPRPM] = omega_d * RPM_PER_RAD_S
    h = p.seg[top, S_H]
    if bp[B_RIG] == 1.0:
        sc = s.sc
        if bp[B_TDMODE] == TOP_DRIVE_PI:
            # the surface torque is the controller's output
            ch[H_TSURF] = sc[C_TD + TS_T]
        ch[H_BLOCK] = sc[C_BLK + BS_X]
        ch[H_BLOCKV] = sc[C_BLK + BS_V]
        up = 0.0
        for k in range(3):
            up -= (x[top, k] - h * R[top, k, 2] - anchor[k]) * anchor[7 + k]
        ch[H_TOPSTR] = up
        ch[H_CONPH] = sc[C_CONPH]
    if bp[B_AXMODE] == 0.0:
        hl = bp[B_HL]
        # force -HL * axis at the top end B = x - h e3; potential HL * (axis . B)
        bx = x[top, 0] - h * R[top, 0, 2]
        by = x[top, 1] - h * R[top, 1, 2]
        bz = x[top, 2] - h * R[top, 2, 2]
        f0 = -hl * anchor[7]
        f1 = -hl * anchor[8]
        f2 = -hl * anchor[9]
        r0 = -h * R[top, 0, 2]
        r1 = -h * R[top, 1, 2]
        r2 = -h * R[top, 2, 2]
        Fw[top, 0] += f0
        Fw[top, 1] += f1
        Fw[top, 2] += f2
        Mw[top, 0] += r1 * f2 - r2 * f1
        Mw[top, 1] += r2 * f0 - r0 * f2
        Mw[top, 2] += r0 * f1 - r1 * f0
        ch[H_PE] += hl * (anchor[7] * bx + anchor[8] * by + anchor[9] * bz)
        ch[H_HOOK] = hl
    else:
        ch[H_HOOK] = loads[top, 0]


@njit(cache=True, inline="always")
def bit_guide(s, p, wk):
    """The bit boundary on segment 0; see the module docstring. Returns a status code."""
    x = s.x
    v = s.v
    w = s.w
    sc = s.sc
    Fw = s.Fw
    Mw = s.Mw
    Mb = s.Mb
    R = wk.R
    wW = wk.wW
    ch = wk.ch
    bp = p.bp
    cpar = p.cpar
    seg = p.seg
    node_md = p.node_md
    node_pos = p.node_pos
    node_tan = p.node_tan
    md_bit = sc[C_MDROCK]
    ch[H_BITMD] = md_bit
    ch[H_BITRPM] = w[0, 2] * RPM_PER_RAD_S
    if bp[B_BITON] != 1.0:
        ch[H_ROP] = 0.0
        ch[H_WOB] = 0.0
        ch[H_TOB] = 0.0
        return OK
    vec = wk.vec
    pos = vec[V_B_POS]
    tan = vec[V_B_TAN]
    sc[C_HINT] = path_point(md_bit, node_md, node_pos, node_tan, int(sc[C_HINT]), pos, tan)
    nl = bp[B_NLOBE]
    s0 = bp[B_LOBE]
    phib = sc[C_PHIB]
    lob = s0 * math.sin(nl * phib)
    vl = (0.0 if bp[B_FREEZE] == 1.0 else sc[C_ROPNOW]) + s0 * nl * math.cos(nl * phib) * w[0, 2]
    h0 = seg[0, S_H]
    kb = bp[B_KBIT]
    cb = bp[B_CBIT]
    # bit face A = x0 + h0 e3 relative to the rock target (face + lobe), and its velocity
    dx = vec[V_B_DX]
    dv = vec[V_B_DV]
    for k in range(3):
        r = h0 * R[0, k, 2]
        dx[k] = x[0, k] + r - (pos[k] + lob * tan[k])
        dv[k] = v[0, k] + (wW[0, (k + 1) % 3] * h0 * R[0, (k + 2) % 3, 2]
                           - wW[0, (k + 2) % 3] * h0 * R[0, (k + 1) % 3, 2]) - vl * tan[k]
    s_ax = dx[0] * tan[0] + dx[1] * tan[1] + dx[2] * tan[2]
    sdot = dv[0] * tan[0] + dv[1] * tan[1] + dv[2] * tan[2]
    # lateral guide: the bit in its own pilot hole (stiff spring-damper),
    # measured from the path at the bit's own depth. On bottom that is the
    # rock target; a bit lifted off by s_ax < 0 is guided by the path s_ax
    # above it, not pulled towards the tangent line at the rock face (in a
    # curved hole that line leaves the hole a few metres above the face).
    fb = vec[V_B_F]
    if s_ax < 0.0:
        p2 = vec[V_B_P2]
        t2 = vec[V_B_T2]
        # the bit's own depth: the path point whose normal plane holds the bit
        # face, by Newton steps on the arc length from the tangent estimate
        md_b = md_bit + lob + s_ax
        hb = int(sc[C_HINT])
        for _it in range(6):
            hb = path_point(md_b, node_md, node_pos, node_tan, hb, p2, t2)
            ds = 0.0
            for k in range(3):
                ds += (x[0, k] + h0 * R[0, k, 2] - p2[k]) * t2[k]
            md_b += ds
            if abs(ds) < 1e-9:
                break
        hb = path_point(md_b, node_md, node_pos, node_tan, hb, p2, t2)
        s2 = 0.0
        sv2 = 0.0
        for k in range(3):
            p2[k] = x[0, k] + h0 * R[0, k, 2] - p2[k]   # bit face - path point
            s2 += p2[k] * t2[k]
            sv2 += (dv[k] + vl * tan[k]) * t2[k]        # bit face velocity . t2
        for k in range(3):
            dp = p2[k] - s2 * t2[k]
            dvp = dv[k] + vl * tan[k] - sv2 * t2[k]
            fb[k] = -kb * dp - cb * dvp
            ch[H_PE] += 0.5 * kb * dp * dp
            ch[H_PDISS] += cb * dvp * dvp
    else:
        for k in range(3):
            dp = dx[k] - s_ax * tan[k]
            dvp = dv[k] - sdot * tan[k]
            fb[k] = -kb * dp - cb * dvp
            ch[H_PE] += 0.5 * kb * dp * dp
            ch[H_PDISS] += cb * dvp * dvp
    # axial: unilateral rock contact; WOB >= 0, zero is bit bounce
    wob_f = 0.0
    if bp[B_RIG] == 1.0:
        # the lobed rock face (rockface.rock_face_contact): u is the bit face beyond the
        # mean face, its rate relative to the face advancing at the ROP
        kr = bp[B_KROCK]
        cr = bp[B_CROCK]
        ro = vec[V_B_OUT]
        rock_face_contact(s_ax + lob, sdot + (vl - sc[C_ROPNOW]), phib, w[0, 2], s0, nl, kr, cr, ro)
        wob_f = ro[0]
        if s_ax > 0.0:
            ch[H_PE] += 0.5 * kr * s_ax * s_ax
            ch[H_PDISS] += (wob_f - kr * s_ax) * sdot
    elif s_ax > 0.0:
        wob_f = kb * s_ax + cb * sdot
        if wob_f < 0.0:
            wob_f = 0.0
        ch[H_PE] += 0.5 * kb * s_ax * s_ax
        ch[H_PDISS] += (wob_f - kb * s_ax) * sdot
    ch[H_PIN] -= wob_f * vl
    count_bounce(wob_f, s_ax, sc)
    for k in range(3):
        fb[k] -= wob_f * tan[k]
    r0 = h0 * R[0, 0, 2]
    r1 = h0 * R[0, 1, 2]
    r2 = h0 * R[0, 2, 2]
    Fw[0, 0] += fb[0]
    Fw[0, 1] += fb[1]
    Fw[0, 2] += fb[2]
    Mw[0, 0] += r1 * fb[2] - r2 * fb[1]
    Mw[0, 1] += r2 * fb[0] - r0 * fb[2]
    Mw[0, 2] += r0 * fb[1] - r1 * fb[0]
    ch[H_WOB] = wob_f
    # torque on bit, opposing the bit rotation
    if cpar.size > P_BITLAW and cpar[P_BITLAW] == 1.0:
        out2 = vec[V_B_OUT]
        st = bit_response(int(cpar[P_BITMODEL]), cpar[P_BP:P_BP + N_BIT_PARAMS], wob_f, w[0, 2], out2)
        if st != OK:
            return st
        tob = out2[0]
        # prescribed ROP: the rock face is kinematic and keeps advancing through a
        # bounce (the string catches up); computed ROP: the law's, 0 off bottom
        sc[C_ROPNOW] = bp[B_ROP] if rop_prescribed(int(cpar[P_BITMODEL])) else out2[1]
    else:
        tob = bp[B_TOB] * math.tanh(w[0, 2] / bp[B_WREF])
        sc[C_ROPNOW] = bp[B_ROP]
    if bp[B_IMPBIT] == 1.0:
        # the law's own damping of the bit's spin, for implicit_bit_damping
        if cpar.size > P_BITLAW and cpar[P_BITLAW] == 1.0:
            slope = bit_torque_slope(int(cpar[P_BITMODEL]), cpar[P_BP:P_BP + N_BIT_PARAMS], wob_f, w[0, 2])
        else:
            th = math.tanh(w[0, 2] / bp[B_WREF])
            slope = bp[B_TOB] * (1.0 - th * th) / bp[B_WREF]
        vec[V_B_IMP, 0] = slope if slope > 0.0 else 0.0
    Mb[0, 2] -= tob
    ch[H_PDISS] += tob * w[0, 2]
    ch[H_TOB] = tob
    ch[H_ROP] = sc[C_ROPNOW]
    return OK


@njit(cache=True, inline="always")
def implicit_bit_damping(s, p, wk):
    """The bit torque's own damping taken linearly implicit (``solver.implicit_bit_torque``).

    Near zero bit speed the bit laws are steep: the regularised stick and the fade-in of
    the cutting term make the torque on bit a damper ``c = dTOB/dOmega`` on the bit
    segment's spin (``c`` = WOB b0 (b1 + b2) = 2.5e4 N m s/rad at 100 kN for the
    Yigit-Christoforou law above its speed threshold, up to 3e5 N m s/rad in the
    fade-in band), which an explicit step resolves only for ``dt < 2 I_a / c`` (2.7e-4 s
    and 2.2e-5 s on a 3.3 kg m^2 bit segment), a limit the joint springs' stable step
    does not see. Here the spin's velocity change over the step is taken with the torque
    at the new speed, linearised: ``(I_a + dt c) dOmega = dt M_z`` (the Rosenbrock-Euler
    step for this one degree of freedom, ``c`` the law's slope at the step's speed where
    positive, :func:`drillfatigue.dynamics.bit.laws.bit_torque_slope`), i.e. the whole
    axial body moment ``M_z`` of segment 0 scaled by ``1 / (1 + dt c / I_a)``. The
    difference is the bit's: the torque on bit channel and the dissipated power carry
    it. It changes nothing where the law is flat (``c = 0``), and its effect vanishes
    with ``dt`` (first order, as the half-step velocity of every damper here).
    Runs after :func:`drillfatigue.dynamics.step.forces.moments_to_body`.
    """
    c = wk.vec[V_B_IMP, 0]
    if c <= 0.0:
        return
    a = p.dt * c / p.seg[0, S_IA]
    Mb = s.Mb
    dm = -Mb[0, 2] * a / (1.0 + a)
    Mb[0, 2] += dm
    wk.ch[H_TOB] -= dm
    wk.ch[H_PDISS] -= dm * s.w[0, 2]
    wk.vec[V_B_IMP, 0] = 0.0
