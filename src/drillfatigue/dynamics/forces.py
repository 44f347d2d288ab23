"""Force assembly: every force and moment on every segment at one instant.

One kernel, :func:`compute_forces`, sums (docs/model.md):

* gravity and buoyancy, ``seg[:, S_W]`` along +z (world z = TVD, down);
* viscous mud damping, lateral / axial / rotational, proportional to length;
* the joint spring-dampers (:mod:`drillfatigue.dynamics.joints`);
* the top boundary: a joint between the top segment's upper end and the top
  drive (axial spring or hook-load force, stiff lateral and tilt "parasitic"
  springs, torsion spring to the driven angle);
* the bit boundary: the bit face guided along the well path at the ROP with a
  lobed axial motion s0 sin(n phi_bit) (stiff isotropic spring-damper; bending
  rotations free), and a torque on bit TOB tanh(omega_bit / omega_ref);
* **wall contact and friction: the marked block below**, empty in this issue.

Its output (F world, M body frame) feeds the integrator, which never needs to
change when a force kind is added: new forces are added here, per contact point,
with one kernel signature per kind (contact, friction, bit-rock).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from drillfatigue.dynamics.bitrock import PRESCRIBED_ROP, bit_response
from drillfatigue.dynamics.contact import wall_force
from drillfatigue.dynamics.friction import KARNOPP
from drillfatigue.dynamics.joints import joint_force
from drillfatigue.dynamics.layout import (
    B_FREEZE, B_LNOM, B_TOPLAT, B_TOPMODE, B_TOPTQ, B_TRAMP, B_TWIN,
    C_BOUNCE, C_GUARD, C_MDROCK, C_NACT, C_OFFB, C_ROPNOW,
    CS_D, CS_FMAX, CS_IMP, CS_N, CS_ONMD, CS_ONT, CS_ORB, CS_ORBABS, CS_SPIN, CS_TCON, CS_TH,
    CS_THOK, H_FCMAX, H_NCON, H_NSEG, P_BITLAW, P_BITMODEL, P_BP, P_FMODEL, P_FP, P_KC, P_NPTS,
    S_CC, S_RB, S_RC,
    B_AXMODE, B_BITON, B_CBIT, B_EXT, B_HL, B_KBIT, B_LOBE, B_MD0, B_NLOBE, B_ROP, B_TOB,
    B_TOPAUTO_A, B_TOPAUTO_T, B_WREF, B_ZB, B_ZJ,
    C_HINT, C_PHIB, C_PHID, C_STEP,
    H_BITMD, H_BITRPM, H_HOOK, H_PDISS, H_PE, H_PG, H_PIN, H_ROP, H_TOB, H_TOPRPM, H_TSURF,
    H_WOB,
    J_CA, J_CB, J_CS, J_CT, J_KA, J_KB, J_KS, J_KT, P_ON,
    S_CA, S_CL, S_CRA, S_CRL, S_H, S_IA, S_IT, S_M, S_W,
    T_CAPL, T_CLPL, T_CRAPL, T_CRLPL, T_EA, T_EA2, T_EI, T_EI2, T_GJ, T_GJ2, T_H0, T_KA_TOP,
    T_KGA, T_KGA2, T_KPAR_B, T_KPAR_S, T_KT_TOP, T_MPL, T_R2, T_WPL,
)
from drillfatigue.well.kernels import path_point
from drillfatigue.dynamics.rigid import quat_conj_mul, quat_exp_mul, quat_log, quat_mul, quat_to_rot

RPM_PER_RAD_S = 60.0 / (2.0 * math.pi)


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
def _seg_row(i, h, seg, topp):
    """Fill seg[i] for a segment of the top section (per-length properties ``topp``), half length h."""
    L = 2.0 * h
    m = topp[T_MPL] * L
    seg[i, S_M] = m
    seg[i, S_H] = h
    seg[i, S_IA] = 0.5 * m * topp[T_R2]
    seg[i, S_IT] = m * (3.0 * topp[T_R2] + L * L) / 12.0
    seg[i, S_W] = topp[T_WPL] * L
    seg[i, S_CL] = topp[T_CLPL] * L
    seg[i, S_CA] = topp[T_CAPL] * L
    seg[i, S_CRL] = topp[T_CRLPL] * L
    seg[i, S_CRA] = topp[T_CRAPL] * L


@njit(cache=True)
def update_top(h, n, seg, jp, topp, bp):
    """Rebuild the parameters of the extensible top segment for half length h (m).

    Mass, inertia, weight and mud damping scale with the length; the stiffness of
    the joint below it and (when automatic) of the top boundary follow 1/length.
    Writes seg[n-1, :], jp[n-2, :] and jp[n-1, :] (n active segments). Top
    mode 1 (applied torque) has no torsion spring; lateral restraint off
    (``bp[B_TOPLAT] == 0``) no parasitic springs.
    """
    top = n - 1
    _seg_row(top, h, seg, topp)
    m = seg[top, S_M]
    zj = bp[B_ZJ]
    zb = bp[B_ZB]
    if n >= 2:
        j = n - 2
        h2 = seg[j, S_H]
        ka = 1.0 / (h2 / topp[T_EA2] + h / topp[T_EA])
        ks = 1.0 / (h2 / topp[T_KGA2] + h / topp[T_KGA])
        kb = 1.0 / (h2 / topp[T_EI2] + h / topp[T_EI])
        kt = 1.0 / (h2 / topp[T_GJ2] + h / topp[T_GJ])
        m2 = seg[j, S_M]
        me = m * m2 / (m + m2)
        it = seg[top, S_IT] * seg[j, S_IT] / (seg[top, S_IT] + seg[j, S_IT])
        ia = seg[top, S_IA] * seg[j, S_IA] / (seg[top, S_IA] + seg[j, S_IA])
        jp[j, J_KA] = ka
        jp[j, J_KS] = ks
        jp[j, J_KB] = kb
        jp[j, J_KT] = kt
        jp[j, J_CA] = 2.0 * zj * math.sqrt(ka * me)
        jp[j, J_CS] = 2.0 * zj * math.sqrt(ks * me)
        jp[j, J_CB] = 2.0 * zj * math.sqrt(kb * it)
        jp[j, J_CT] = 2.0 * zj * math.sqrt(kt * ia)
    # top boundary row
    if bp[B_AXMODE] == 1.0:
        ka = topp[T_EA] / h if bp[B_TOPAUTO_A] == 1.0 else topp[T_KA_TOP]
    else:
        ka = 0.0
    kt = topp[T_GJ] / h if bp[B_TOPAUTO_T] == 1.0 else topp[T_KT_TOP]
    ks = topp[T_KPAR_S]
    kb = topp[T_KPAR_B]
    if bp[B_TOPMODE] == 1.0:
        kt = 0.0
    if bp[B_TOPLAT] == 0.0:
        ks = 0.0
        kb = 0.0
    jp[top, J_KA] = ka
    jp[top, J_KS] = ks
    jp[top, J_KB] = kb
    jp[top, J_KT] = kt
    jp[top, J_CA] = 2.0 * zb * math.sqrt(ka * m)
    jp[top, J_CS] = 2.0 * zb * math.sqrt(ks * m)
    jp[top, J_CB] = 2.0 * zb * math.sqrt(kb * seg[top, S_IT])
    jp[top, J_CT] = 2.0 * zb * math.sqrt(kt * seg[top, S_IA])


@njit(cache=True)
def top_joint(t, top, x, v, q, wW, R, seg, jp, anchor, tab_t, tab_w, sc, scq, scm, scv, loads_row, ed):
    """Loads of the top boundary: the top segment's upper end tied to the top drive.

    The drive is a virtual body at ``anchor[0:3]`` with orientation
    ``anchor[3:7] * rot_z(phi_drive)`` turning at the table speed about the
    downhole axis ``anchor[7:10]``. Writes scv[0] (force on the top segment),
    scv[1] (its moment), scv[2] (moment on the drive), scv[3] (drive angular
    velocity), ``loads_row`` and ``ed``. Returns the drive speed (rad/s).
    ``top`` is the row of the top segment.

    With the hook-load force at the top (no axial spring, ``jp[top, J_KA] == 0``)
    the drive follows the top of the string axially, as a travelling block does:
    the attachment point slides along the drive axis to the axial position of
    the segment's upper end (``scv[5]`` is its scratch). Otherwise an axial drift
    of the string (drag, growth, bit vibration) would put a lever arm between the
    lateral hold and the segment's end, coupling the stiff lateral spring into
    the tilt with a stiffness ~ k_s * gap^2 that outgrows the stable step.
    """
    omega_d = drive_omega(t, tab_t, tab_w)
    phid = sc[C_PHID]
    qz = scq[3]
    qz[0] = math.cos(0.5 * phid)
    qz[1] = 0.0
    qz[2] = 0.0
    qz[3] = math.sin(0.5 * phid)
    qa = scq[4]
    quat_mul(anchor[3:7], qz, qa)
    Ra = scm[1]
    quat_to_rot(qa, Ra)
    wa = scv[3]
    va = scv[4]
    for k in range(3):
        wa[k] = omega_d * anchor[7 + k]
        va[k] = 0.0
    pa = scv[5]
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
    joint_force(x[top], v[top], R[top], q[top], wW[top], seg[top, S_H],
                pa, va, Ra, qa, wa, 0.0,
                jp[top, J_KA], jp[top, J_KS], jp[top, J_KB], jp[top, J_KT],
                jp[top, J_CA], jp[top, J_CS], jp[top, J_CB], jp[top, J_CT],
                scq[0], scq[1], scq[2], scm[0], scv[0], scv[1], scv[2], loads_row, ed)
    return omega_d


@njit(cache=True)
def top_energy(t, x, v, q, w, seg, jp, anchor, tab_t, tab_w, sc, R, wW, scq, scm, scv,
               loads, ed):
    """Energy (J) held by the top segment: its kinetic and gravity energy and the
    springs of the joint below it and of the top boundary (:func:`tail_energy`
    from the top segment)."""
    n = int(sc[C_NACT])
    return tail_energy(n - 1, t, x, v, q, w, seg, jp, anchor, tab_t, tab_w, sc, R, wW, scq, scm,
                       scv, loads, ed)


@njit(cache=True)
def tail_energy(lo, t, x, v, q, w, seg, jp, anchor, tab_t, tab_w, sc, R, wW, scq, scm, scv,
                loads, ed):
    """Energy (J) of segments lo..n-1 (kinetic + gravity), the joints lo-1..n-2 and the top boundary.

    Used to book the work of feeding pipe when the top segment grows, is split
    (drilling) or merged (tripping out): the difference before/after. Refreshes
    R and wW of segments lo-1..n-1.
    """
    n = int(sc[C_NACT])
    top = n - 1
    first = max(lo - 1, 0)
    for i in range(first, n):
        quat_to_rot(q[i], R[i])
        for k in range(3):
            wW[i, k] = R[i, k, 0] * w[i, 0] + R[i, k, 1] * w[i, 1] + R[i, k, 2] * w[i, 2]
    e = 0.0
    for i in range(lo, n):
        e += 0.5 * seg[i, S_M] * (v[i, 0] ** 2 + v[i, 1] ** 2 + v[i, 2] ** 2)
        e += 0.5 * seg[i, S_IT] * (w[i, 0] ** 2 + w[i, 1] ** 2) + 0.5 * seg[i, S_IA] * w[i, 2] ** 2
        e -= seg[i, S_W] * x[i, 2]
    for j in range(first, n - 1):
        joint_force(x[j], v[j], R[j], q[j], wW[j], seg[j, S_H],
                    x[j + 1], v[j + 1], R[j + 1], q[j + 1], wW[j + 1], seg[j + 1, S_H],
                    jp[j, J_KA], jp[j, J_KS], jp[j, J_KB], jp[j, J_KT],
                    jp[j, J_CA], jp[j, J_CS], jp[j, J_CB], jp[j, J_CT],
                    scq[0], scq[1], scq[2], scm[0], scv[0], scv[1], scv[2], loads[j], ed)
        e += ed[0]
    top_joint(t, top, x, v, q, wW, R, seg, jp, anchor, tab_t, tab_w, sc, scq, scm, scv, loads[top], ed)
    e += ed[0]
    return e


@njit(cache=True)
def compute_forces(dt, x, v, q, w, seg, jp, bp, anchor, tab_t, tab_w,
                   node_md, node_pos, node_tan, wall, cpar, hint, cst, sc, R, wW, Fw, Mw, Mb,
                   loads, ch, scq, scm, scv, ed, cw):
    """All forces at the current state.

    Parameters
    ----------
    dt : float                    step (s); the time is sc[C_STEP] * dt
    x, v : ndarray, shape (n, 3)  segment centres (m) and velocities (m/s), world
    q : ndarray, shape (n, 4)     orientations (unit quaternions, body -> world)
    w : ndarray, shape (n, 3)     angular velocities, body frame (rad/s)
    seg, jp, bp                   packed parameters (see :mod:`layout`)
    anchor : ndarray, shape (10,) top anchor: position (3), quaternion at zero drive angle (4),
                                  downhole unit axis (3)
    tab_t, tab_w : ndarray, shape (K,)  top-drive speed table: time (s), speed (rad/s)
    node_md, node_pos, node_tan   well path nodes (see :func:`drillfatigue.well.kernels.path_point`)
    wall : ndarray, shape (n_cyl, N_WALL)  hole cylinders (see :mod:`layout`)
    cpar : ndarray, shape (N_CPAR,) contact / friction / bit-law parameters; cpar[P_ON] == 0: no wall
    hint : ndarray of int64, shape (3 n,)  cylinder hint of contact point p of segment i at 3 i + p
    cst : ndarray, shape (n, N_CST)  contact and whirl statistics (state), updated
    sc : ndarray, shape (N_SC,)   scalar state (path hint, bit-bounce state, ROP) updated
    R : ndarray, shape (n, 3, 3)  written: rotation matrices
    wW : ndarray, shape (n, 3)    written: angular velocities, world frame
    Fw, Mw : ndarray, shape (n, 3)  written: world force (N), world moment about the centre (N m)
    Mb : ndarray, shape (n, 3)    written: total body-frame moment (N m)
    loads : ndarray, shape (n, 6) written: joint loads, rows 0..n-2 joints, row n-1 top boundary
    ch : ndarray, shape (N_CH,)   written: channels and energy terms
    scq, scm, scv, ed, cw         scratch, shapes (5, 4), (2, 3, 3), (12, 3), (2,), (32,)

    Returns
    -------
    int
        0; 2 for an unknown friction model; 3 for an unknown bit model.

    Notes
    -----
    Karnopp needs the "other" tangential force at a contact point. In this
    explicit scheme it is estimated in a first pass: the acceleration the
    contact point would have from all non-wall forces and moments on the
    segment (gravity, mud, joints, boundaries), times the share of the
    segment's mass carried by the point (m / points). Friction is then computed
    point by point against that estimate.

    Slip cap (smooth models, all but Karnopp). Near zero slip a regularised
    friction law is a viscous damper of slope mu N / v_reg, which an explicit
    step resolves only for dt < 2 m_eff v_reg / (mu N) -- far below the joint
    step at large normal forces. Instead, the tangential force at a point is
    capped at m_eff |v_slip| / dt with m_eff = m / (3 points) (translation, spin
    and tilt of the segment all move the surface point; the factor 3 keeps the
    combined velocity change of one step below the slip, so friction can stop
    a slip within a step but never reverse it). Where the cap binds the point
    is effectively stuck (creep ~ F_other dt / m_eff), as it would be with the
    true law; elsewhere the law is untouched. Karnopp keeps its own stick band
    and the step limit of :func:`drillfatigue.dynamics.model.stable_step`.
    """
    n = int(sc[C_NACT])
    t = sc[C_STEP] * dt
    pe = 0.0
    pg = 0.0
    pdiss = 0.0
    pin = 0.0
    for i in range(n):
        quat_to_rot(q[i], R[i])
        for k in range(3):
            wW[i, k] = R[i, k, 0] * w[i, 0] + R[i, k, 1] * w[i, 1] + R[i, k, 2] * w[i, 2]
    # --- body forces: gravity + buoyancy, mud damping ---------------------------------
    for i in range(n):
        e0 = R[i, 0, 2]
        e1 = R[i, 1, 2]
        e2 = R[i, 2, 2]
        vax = v[i, 0] * e0 + v[i, 1] * e1 + v[i, 2] * e2
        cl = seg[i, S_CL]
        ca = seg[i, S_CA]
        Fw[i, 0] = -cl * (v[i, 0] - vax * e0) - ca * vax * e0
        Fw[i, 1] = -cl * (v[i, 1] - vax * e1) - ca * vax * e1
        Fw[i, 2] = -cl * (v[i, 2] - vax * e2) - ca * vax * e2 + seg[i, S_W]
        pg -= seg[i, S_W] * x[i, 2]
        vv = v[i, 0] ** 2 + v[i, 1] ** 2 + v[i, 2] ** 2
        pdiss += cl * (vv - vax * vax) + ca * vax * vax
        Mw[i, 0] = 0.0
        Mw[i, 1] = 0.0
        Mw[i, 2] = 0.0
        Mb[i, 0] = -seg[i, S_CRL] * w[i, 0]
        Mb[i, 1] = -seg[i, S_CRL] * w[i, 1]
        Mb[i, 2] = -seg[i, S_CRA] * w[i, 2]
        pdiss += seg[i, S_CRL] * (w[i, 0] ** 2 + w[i, 1] ** 2) + seg[i, S_CRA] * w[i, 2] ** 2
    # --- joints ---------------------------------------------------------------------------
    Fl = scv[0]
    Ml = scv[1]
    Mu = scv[2]
    # growth rate (m/s) of the top segment along its axis: its lower end moves at
    # this rate on top of its rigid motion (kinematic growth, see the integrator),
    # which the damper of the joint below it must see
    if bp[B_FREEZE] == 1.0:
        growth = 0.0
    elif bp[B_BITON] == 1.0:
        growth = sc[C_ROPNOW]
    else:
        growth = bp[B_EXT]
        if sc[C_GUARD] == 1.0 and growth < 0.0:
            growth = 0.0
    vtop = scv[4]
    for j in range(n - 1):
        vu = v[j + 1]
        if j == n - 2 and growth != 0.0:
            for k in range(3):
                vtop[k] = v[j + 1, k] + growth * R[j + 1, k, 2]
            vu = vtop
        joint_force(x[j], v[j], R[j], q[j], wW[j], seg[j, S_H],
                    x[j + 1], vu, R[j + 1], q[j + 1], wW[j + 1], seg[j + 1, S_H],
                    jp[j, J_KA], jp[j, J_KS], jp[j, J_KB], jp[j, J_KT],
                    jp[j, J_CA], jp[j, J_CS], jp[j, J_CB], jp[j, J_CT],
                    scq[0], scq[1], scq[2], scm[0], Fl, Ml, Mu, loads[j], ed)
        pe += ed[0]
        pdiss += ed[1]
        for k in range(3):
            Fw[j, k] += Fl[k]
            Fw[j + 1, k] -= Fl[k]
            Mw[j, k] += Ml[k]
            Mw[j + 1, k] += Mu[k]
    # --- top boundary: top drive and rig -------------------------------------------------
    top = n - 1
    omega_d = top_joint(t, top, x, v, q, wW, R, seg, jp, anchor, tab_t, tab_w, sc, scq, scm, scv,
                        loads[top], ed)
    wa = scv[3]
    pe += ed[0]
    pdiss += ed[1]
    for k in range(3):
        Fw[top, k] += Fl[k]
        Mw[top, k] += Ml[k]
    if bp[B_TOPMODE] == 1.0:
        # applied torque about the top segment's axis (no drive spring)
        tq = bp[B_TOPTQ]
        if bp[B_TRAMP] > 0.0 and t < bp[B_TRAMP]:
            tq *= t / bp[B_TRAMP]
        Mb[top, 2] += tq
        pin += tq * w[top, 2]
        ch[H_TSURF] = tq
        ch[H_TOPRPM] = w[top, 2] * RPM_PER_RAD_S
    else:
        # the drive works on the string: minus the reaction moment on the drive times its speed
        pin -= Mu[0] * wa[0] + Mu[1] * wa[1] + Mu[2] * wa[2]
        ch[H_TSURF] = loads[top, 5]
        ch[H_TOPRPM] = omega_d * RPM_PER_RAD_S
    h = seg[top, S_H]
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
        pe += hl * (anchor[7] * bx + anchor[8] * by + anchor[9] * bz)
        ch[H_HOOK] = hl
    else:
        ch[H_HOOK] = loads[top, 0]
    # --- bit boundary ----------------------------------------------------------------------
    md_bit = sc[C_MDROCK]
    ch[H_BITMD] = md_bit
    ch[H_BITRPM] = w[0, 2] * RPM_PER_RAD_S
    if bp[B_BITON] == 1.0:
        pos = scv[5]
        tan = scv[6]
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
        dx = scv[7]
        dv = scv[8]
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
        fb = scv[9]
        if s_ax < 0.0:
            p2 = scv[10]
            t2 = scv[11]
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
                pe += 0.5 * kb * dp * dp
                pdiss += cb * dvp * dvp
        else:
            for k in range(3):
                dp = dx[k] - s_ax * tan[k]
                dvp = dv[k] - sdot * tan[k]
                fb[k] = -kb * dp - cb * dvp
                pe += 0.5 * kb * dp * dp
                pdiss += cb * dvp * dvp
        # axial: unilateral rock contact; WOB >= 0, zero is bit bounce
        wob_f = 0.0
        if s_ax > 0.0:
            wob_f = kb * s_ax + cb * sdot
            if wob_f < 0.0:
                wob_f = 0.0
            pe += 0.5 * kb * s_ax * s_ax
            pdiss += (wob_f - kb * s_ax) * sdot
        pin -= wob_f * vl
        if wob_f <= 0.0:
            if sc[C_OFFB] == 0.0:
                sc[C_BOUNCE] += 1.0
                sc[C_OFFB] = 1.0
        elif s_ax > 1e-6:  # re-armed once the bit is back on bottom by > 1 micron
            sc[C_OFFB] = 0.0
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
            out2 = cw[20:22]
            if bit_response(int(cpar[P_BITMODEL]), cpar[P_BP:P_BP + 10], wob_f, w[0, 2], out2) != 0:
                return 3
            tob = out2[0]
            # prescribed ROP: the rock face is kinematic and keeps advancing through a
            # bounce (the string catches up); computed ROP: the law's, 0 off bottom
            sc[C_ROPNOW] = bp[B_ROP] if int(cpar[P_BITMODEL]) == PRESCRIBED_ROP else out2[1]
        else:
            tob = bp[B_TOB] * math.tanh(w[0, 2] / bp[B_WREF])
            sc[C_ROPNOW] = bp[B_ROP]
        Mb[0, 2] -= tob
        pdiss += tob * w[0, 2]
        ch[H_TOB] = tob
        ch[H_ROP] = sc[C_ROPNOW]
    else:
        ch[H_ROP] = 0.0
        ch[H_WOB] = 0.0
        ch[H_TOB] = 0.0
    # --- wall contact and friction ---------------------------------------------------------
    ncon = 0
    fcmax = 0.0
    if cpar[P_ON] != 0.0:
        kc = cpar[P_KC]
        fmodel = int(cpar[P_FMODEL])
        npts = int(cpar[P_NPTS])
        fp = cpar[P_FP:P_FP + 10]
        p0 = wall[:, 0:3]
        axc = wall[:, 3:6]
        lnc = wall[:, 6]
        rad = wall[:, 7]
        info = cw[0:14]
        X = scv[7]
        tax = scv[8]
        fo = scv[9]
        force = scv[10]
        moment = scv[11]
        alin = scq[3]
        alpha = scq[4]
        t_win = bp[B_TWIN]
        for i in range(n):
            h = seg[i, S_H]
            m = seg[i, S_M]
            for k in range(3):
                tax[k] = R[i, k, 2]
                fo[k] = 0.0
            karn = fmodel == KARNOPP
            if karn:
                # acceleration from the non-wall loads (first pass, see Notes)
                mb0 = R[i, 0, 0] * Mb[i, 0] + R[i, 0, 1] * Mb[i, 1] + R[i, 0, 2] * Mb[i, 2] + Mw[i, 0]
                mb1 = R[i, 1, 0] * Mb[i, 0] + R[i, 1, 1] * Mb[i, 1] + R[i, 1, 2] * Mb[i, 2] + Mw[i, 1]
                mb2 = R[i, 2, 0] * Mb[i, 0] + R[i, 2, 1] * Mb[i, 1] + R[i, 2, 2] * Mb[i, 2] + Mw[i, 2]
                max_ = mb0 * tax[0] + mb1 * tax[1] + mb2 * tax[2]
                it = seg[i, S_IT]
                ia = seg[i, S_IA]
                alpha[0] = (mb0 - max_ * tax[0]) / it + max_ * tax[0] / ia
                alpha[1] = (mb1 - max_ * tax[1]) / it + max_ * tax[1] / ia
                alpha[2] = (mb2 - max_ * tax[2]) / it + max_ * tax[2] / ia
                for k in range(3):
                    alin[k] = Fw[i, k] / m
            nsum = 0.0
            dmax = 0.0
            m_cap = m / (3.0 * npts)
            for p in range(npts):
                if p == 0:
                    off = h
                    rc = seg[i, S_RC]
                elif p == 1:
                    off = -h
                    rc = seg[i, S_RC]
                else:
                    off = 0.0
                    rc = seg[i, S_RB]
                for k in range(3):
                    X[k] = x[i, k] + off * tax[k]
                if karn:
                    share = m / npts
                    fo[0] = share * (alin[0] + alpha[1] * off * tax[2] - alpha[2] * off * tax[1])
                    fo[1] = share * (alin[1] + alpha[2] * off * tax[0] - alpha[0] * off * tax[2])
                    fo[2] = share * (alin[2] + alpha[0] * off * tax[1] - alpha[1] * off * tax[0])
                ih = 3 * i + p
                ic = wall_force(X, x[i], v[i], wW[i], tax, rc, p0, axc, lnc, rad, hint[ih],
                                kc, seg[i, S_CC], fmodel, fp, fo, dt, info, force, moment)
                if ic == -2:
                    return 2
                if ic >= 0:
                    hint[ih] = ic
                d = info[5]
                if d > dmax:
                    dmax = d
                delta = info[0]
                if delta > 0.0:
                    nrm = info[6]
                    nsum += nrm
                    nx = info[1]
                    ny = info[2]
                    nz = info[3]
                    # velocity of the surface contact point Y = X + r n
                    ax_ = X[0] + rc * nx - x[i, 0]
                    ay_ = X[1] + rc * ny - x[i, 1]
                    az_ = X[2] + rc * nz - x[i, 2]
                    vy0 = v[i, 0] + wW[i, 1] * az_ - wW[i, 2] * ay_
                    vy1 = v[i, 1] + wW[i, 2] * ax_ - wW[i, 0] * az_
                    vy2 = v[i, 2] + wW[i, 0] * ay_ - wW[i, 1] * ax_
                    vn = vy0 * nx + vy1 * ny + vy2 * nz
                    if not karn and nrm > 0.0:
                        # slip cap (see Notes): |F_t| <= m_eff |v_slip| / dt
                        ft0 = force[0] + nrm * nx
                        ft1 = force[1] + nrm * ny
                        ft2 = force[2] + nrm * nz
                        ftm = math.sqrt(ft0 * ft0 + ft1 * ft1 + ft2 * ft2)
                        cap = m_cap * info[7] / dt
                        if ftm > cap:
                            sf = cap / ftm
                            force[0] = sf * ft0 - nrm * nx
                            force[1] = sf * ft1 - nrm * ny
                            force[2] = sf * ft2 - nrm * nz
                            moment[0] = ay_ * force[2] - az_ * force[1]
                            moment[1] = az_ * force[0] - ax_ * force[2]
                            moment[2] = ax_ * force[1] - ay_ * force[0]
                    pe += 0.5 * kc * delta * delta
                    pdiss += -(force[0] * vy0 + force[1] * vy1 + force[2] * vy2) - kc * delta * vn
                    for k in range(3):
                        Fw[i, k] += force[k]
                        Mw[i, k] += moment[k]
            cst[i, CS_N] = nsum
            cst[i, CS_D] = dmax
            if nsum > 0.0:
                ncon += 1
                if cst[i, CS_ONT] < 0.0:
                    cst[i, CS_ONT] = t
                    cst[i, CS_ONMD] = md_bit
                if nsum > cst[i, CS_FMAX]:
                    cst[i, CS_FMAX] = nsum
                if nsum > fcmax:
                    fcmax = nsum
                cst[i, CS_IMP] += nsum * dt
                cst[i, CS_TCON] += dt
            # whirl: orbit angle of the centre about the hole axis, after the ramp
            if t >= t_win:
                # the centre's radial offset from the axis of the cylinder its first
                # contact point was last found in (no search: a direct projection)
                out6 = cw[22:28]
                ic = hint[3 * i]
                a0 = wall[ic, 3]
                a1 = wall[ic, 4]
                a2 = wall[ic, 5]
                r0 = x[i, 0] - wall[ic, 0]
                r1 = x[i, 1] - wall[ic, 1]
                r2 = x[i, 2] - wall[ic, 2]
                sa = r0 * a0 + r1 * a1 + r2 * a2
                r0 -= sa * a0
                r1 -= sa * a1
                r2 -= sa * a2
                out6[5] = math.sqrt(r0 * r0 + r1 * r1 + r2 * r2)
                if out6[5] > 0.0:
                    out6[1] = r0 / out6[5]
                    out6[2] = r1 / out6[5]
                    out6[3] = r2 / out6[5]
                spin = wW[i, 0] * a0 + wW[i, 1] * a1 + wW[i, 2] * a2
                cst[i, CS_SPIN] += spin * dt
                clr = rad[ic] - seg[i, S_RC]
                if out6[5] > 0.25 * clr:
                    # reference u: the world z (or x in a vertical hole) normal to the axis
                    if abs(a2) < 0.9:
                        u0 = -a2 * a0
                        u1 = -a2 * a1
                        u2 = 1.0 - a2 * a2
                    else:
                        u0 = 1.0 - a0 * a0
                        u1 = -a0 * a1
                        u2 = -a0 * a2
                    un = math.sqrt(u0 * u0 + u1 * u1 + u2 * u2)
                    u0 /= un
                    u1 /= un
                    u2 /= un
                    w0 = a1 * u2 - a2 * u1
                    w1 = a2 * u0 - a0 * u2
                    w2 = a0 * u1 - a1 * u0
                    th = math.atan2(out6[1] * w0 + out6[2] * w1 + out6[3] * w2,
                                    out6[1] * u0 + out6[2] * u1 + out6[3] * u2)
                    if cst[i, CS_THOK] == 1.0:
                        dth = th - cst[i, CS_TH]
                        if dth > math.pi:
                            dth -= 2.0 * math.pi
                        elif dth < -math.pi:
                            dth += 2.0 * math.pi
                        cst[i, CS_ORB] += dth
                        cst[i, CS_ORBABS] += abs(dth)
                    cst[i, CS_TH] = th
                    cst[i, CS_THOK] = 1.0
                else:
                    cst[i, CS_THOK] = 0.0
    ch[H_NCON] = ncon
    ch[H_FCMAX] = fcmax
    ch[H_NSEG] = n
    # --- world moments to the body frame -------------------------------------------------
    for i in range(n):
        m0 = Mw[i, 0]
        m1 = Mw[i, 1]
        m2 = Mw[i, 2]
        Mb[i, 0] += R[i, 0, 0] * m0 + R[i, 1, 0] * m1 + R[i, 2, 0] * m2
        Mb[i, 1] += R[i, 0, 1] * m0 + R[i, 1, 1] * m1 + R[i, 2, 1] * m2
        Mb[i, 2] += R[i, 0, 2] * m0 + R[i, 1, 2] * m1 + R[i, 2, 2] * m2
    ch[H_PE] = pe
    ch[H_PG] = pg
    ch[H_PDISS] = pdiss
    ch[H_PIN] = pin
    return 0


@njit(cache=True)
def _rigid_point_velocity(v, wW, r, out):
    out[0] = v[0] + wW[1] * r[2] - wW[2] * r[1]
    out[1] = v[1] + wW[2] * r[0] - wW[0] * r[2]
    out[2] = v[2] + wW[0] * r[1] - wW[1] * r[0]


@njit(cache=True)
def split_top(x, v, q, w, seg, jp, topp, bp, hint, cst, sc, R, scv, growth):
    """Drilling: split a segment of length ``bp[B_LNOM]`` off the bottom of the top segment.

    The top segment (row n-1) is cut rigidly into a lower piece of the nominal
    length (kept in row n-1, now an ordinary segment) and a new, shorter top
    segment (row n). Both parts keep the rigid-body motion of the whole (velocity
    of each centre = v + omega x r), so momentum and kinetic energy are
    unchanged.

    Load continuity. The old top's compliance was split between the joint below
    it (half length h) and the top boundary spring (h); afterwards it is the
    joint below the piece (h1), the new joint (h1 + h2) and the top spring
    (h2) -- the same total. So that the axial force and the torque do not jump,
    the piece is shifted along and turned about its axis until the joint below
    it carries the old axial force T_b and torque Q, and the new top until the
    new joint carries T_b + the piece's axial weight and Q (quasi-static
    equilibrium of the piece); the top spring then carries its old load again
    (the total stretch and twist are unchanged). Shear and bending at the new
    joint start at zero (the top of the string is short and nearly straight).
    The caller books the energy difference as work put in.
    ``growth`` is the rate (m/s) at which the top segment's lower end moves
    along its axis by growth (ROP); the piece, now an ordinary segment, takes it
    as velocity. Requires n < the allocated rows. Returns the new active count.
    """
    n = int(sc[C_NACT])
    top = n - 1
    new = n
    h = seg[top, S_H]
    ln = bp[B_LNOM]
    quat_to_rot(q[top], R[top])
    # axial gap and twist of the joint below the top, before the split
    lo = top - 1
    d_old = 0.0
    tw_old = 0.0
    ka_old = 0.0
    kt_old = 0.0
    qt = np.empty(4)
    qt2 = np.empty(4)
    th = np.empty(3)
    if lo >= 0:
        quat_to_rot(q[lo], R[lo])
        for k in range(3):
            d_old += ((x[top, k] + h * R[top, k, 2]) - (x[lo, k] - seg[lo, S_H] * R[lo, k, 2])) \
                * R[top, k, 2]
        quat_conj_mul(q[lo], q[top], qt)
        quat_log(qt, th)
        tw_old = th[2]
        ka_old = jp[lo, J_KA]
        kt_old = jp[lo, J_KT]
    wv = scv[0]
    r = scv[1]
    vel = scv[2]
    for k in range(3):
        wv[k] = R[top, k, 0] * w[top, 0] + R[top, k, 1] * w[top, 1] + R[top, k, 2] * w[top, 2]
    h1 = 0.5 * ln
    h2 = h - h1
    xc = scv[3]
    for k in range(3):
        xc[k] = x[top, k]
    # lower piece: centre at (h - h1) below the old centre; new top: h1 above it... along e3
    for k in range(3):
        r[k] = (h - h1) * R[top, k, 2]
    _rigid_point_velocity(v[top], wv, r, vel)
    vnew = scv[4]
    for k in range(3):
        r[k] = -(h - h2) * R[top, k, 2]
    _rigid_point_velocity(v[top], wv, r, vnew)
    for k in range(3):
        x[new, k] = xc[k] - (h - h2) * R[top, k, 2]
        v[new, k] = vnew[k]
        w[new, k] = w[top, k]
        x[top, k] = xc[k] + (h - h1) * R[top, k, 2]
        # the piece was the growing bottom of the top segment: its points moved at
        # the rigid velocity plus the growth rate (ROP or trip speed) along e3
        v[top, k] = vel[k] + growth * R[top, k, 2]
    for k in range(4):
        q[new, k] = q[top, k]
    seg[new, S_RC] = seg[top, S_RC]
    seg[new, S_RB] = seg[top, S_RB]
    m_old = seg[top, S_M]
    cc_old = seg[top, S_CC]
    _seg_row(top, h1, seg, topp)
    for p in range(3):
        hint[3 * new + p] = hint[3 * top + p]
    for k in range(cst.shape[1]):
        cst[new, k] = 0.0
    cst[new, CS_ONT] = -1.0
    # joint below the piece: section of segment n-2 and the piece (top section)
    sc[C_NACT] = n + 1.0
    # the joint top-1 (below the piece) is rebuilt by update_top on an n-active string
    # whose top is the piece; then the piece becomes an ordinary segment
    update_top(h1, n, seg, jp, topp, bp)
    # from now on the segment below the top has the top section
    topp[T_EA2] = topp[T_EA]
    topp[T_EI2] = topp[T_EI]
    topp[T_GJ2] = topp[T_GJ]
    topp[T_KGA2] = topp[T_KGA]
    update_top(h2, n + 1, seg, jp, topp, bp)
    # the per-point contact dash-pot scales with sqrt(mass carried)
    seg[top, S_CC] = cc_old * math.sqrt(seg[top, S_M] / m_old)
    seg[new, S_CC] = cc_old * math.sqrt(seg[new, S_M] / m_old)
    if lo >= 0 and jp[lo, J_KA] > 0.0 and jp[top, J_KA] > 0.0:
        # load continuity (see above); tension T = -k_a d, torque Q = k_t twist
        t_b = -ka_old * d_old
        q_b = kt_old * tw_old
        d1 = -t_b / jp[lo, J_KA] - d_old          # shift of the piece along e3
        a1 = (q_b / jp[lo, J_KT] - tw_old) if jp[lo, J_KT] > 0.0 else 0.0
        t_c = t_b + seg[top, S_W] * R[top, 2, 2]
        d2 = -t_c / jp[top, J_KA] + d1            # shift of the new top
        a2 = (q_b / jp[top, J_KT] if jp[top, J_KT] > 0.0 else 0.0) + a1
        for k in range(3):
            x[top, k] += d1 * R[top, k, 2]
            x[new, k] += d2 * R[top, k, 2]
        quat_exp_mul(q[top], 0.0, 0.0, a1, qt, qt2)
        for k in range(4):
            q[top, k] = qt2[k]
        quat_exp_mul(q[new], 0.0, 0.0, a2, qt, qt2)
        for k in range(4):
            q[new, k] = qt2[k]
    return n + 1


@njit(cache=True)
def merge_top(x, v, q, w, seg, jp, topp, bp, sc, R, scv):
    """Tripping out: merge the (short) top segment with the segment below it.

    The merged body takes the orientation of the lower one, spans from its lower
    end to the old top end along its axis, and the momentum-weighted velocities
    (the relative motion of the two parts is lost: an inelastic merge; the
    caller books the energy change). The merged segment gets the top section's
    per-length properties. Returns the new active count.
    """
    n = int(sc[C_NACT])
    top = n - 1
    lo = n - 2
    quat_to_rot(q[lo], R[lo])
    quat_to_rot(q[top], R[top])
    m1 = seg[lo, S_M]
    m2 = seg[top, S_M]
    i1 = seg[lo, S_IT]
    i2 = seg[top, S_IT]
    lowend = scv[0]
    topend = scv[1]
    for k in range(3):
        lowend[k] = x[lo, k] + seg[lo, S_H] * R[lo, k, 2]
        topend[k] = x[top, k] - seg[top, S_H] * R[top, k, 2]
    L = 0.0
    for k in range(3):
        L += (lowend[k] - topend[k]) * R[lo, k, 2]
    h = 0.5 * L
    for k in range(3):
        v[lo, k] = (m1 * v[lo, k] + m2 * v[top, k]) / (m1 + m2)
        x[lo, k] = lowend[k] - h * R[lo, k, 2]
    w[lo, 0] = (i1 * w[lo, 0] + i2 * w[top, 0]) / (i1 + i2)
    w[lo, 1] = (i1 * w[lo, 1] + i2 * w[top, 1]) / (i1 + i2)
    w[lo, 2] = (seg[lo, S_IA] * w[lo, 2] + seg[top, S_IA] * w[top, 2]) / (seg[lo, S_IA] + seg[top, S_IA])
    for k in range(3):
        x[top, k] = 0.0
        v[top, k] = 0.0
        w[top, k] = 0.0
    for k in range(seg.shape[1]):
        seg[top, k] = 0.0
    for k in range(jp.shape[1]):
        jp[top, k] = 0.0
    sc[C_NACT] = n - 1.0
    _seg_row(lo, h, seg, topp)
    update_top(h, n - 1, seg, jp, topp, bp)
    return n - 1
