"""Force assembly: every force and moment on every segment at one instant.

One kernel, :func:`compute_forces`, sums (MODEL.md §1-4):

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

from numba import njit

from drillfatigue.dynamics.joints import joint_force
from drillfatigue.dynamics.layout import (
    B_AXMODE, B_BITON, B_CBIT, B_HL, B_KBIT, B_LOBE, B_MD0, B_NLOBE, B_ROP, B_TOB,
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
from drillfatigue.dynamics.rigid import quat_mul, quat_to_rot

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
def update_top(h, seg, jp, topp, bp):
    """Rebuild the parameters of the extensible top segment for half length h (m).

    Mass, inertia, weight and mud damping scale with the length; the stiffness of
    the joint below it and (when automatic) of the top boundary follow 1/length.
    Writes seg[n-1, :], jp[n-2, :] and jp[n-1, :].
    """
    n = seg.shape[0]
    top = n - 1
    L = 2.0 * h
    m = topp[T_MPL] * L
    seg[top, S_M] = m
    seg[top, S_H] = h
    seg[top, S_IA] = 0.5 * m * topp[T_R2]
    seg[top, S_IT] = m * (3.0 * topp[T_R2] + L * L) / 12.0
    seg[top, S_W] = topp[T_WPL] * L
    seg[top, S_CL] = topp[T_CLPL] * L
    seg[top, S_CA] = topp[T_CAPL] * L
    seg[top, S_CRL] = topp[T_CRLPL] * L
    seg[top, S_CRA] = topp[T_CRAPL] * L
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
    jp[top, J_KA] = ka
    jp[top, J_KS] = ks
    jp[top, J_KB] = kb
    jp[top, J_KT] = kt
    jp[top, J_CA] = 2.0 * zb * math.sqrt(ka * m)
    jp[top, J_CS] = 2.0 * zb * math.sqrt(ks * m)
    jp[top, J_CB] = 2.0 * zb * math.sqrt(kb * seg[top, S_IT])
    jp[top, J_CT] = 2.0 * zb * math.sqrt(kt * seg[top, S_IA])


@njit(cache=True)
def top_joint(t, x, v, q, wW, R, seg, jp, anchor, tab_t, tab_w, sc, scq, scm, scv, loads_row, ed):
    """Loads of the top boundary: the top segment's upper end tied to the top drive.

    The drive is a virtual body at ``anchor[0:3]`` with orientation
    ``anchor[3:7] * rot_z(phi_drive)`` turning at the table speed about the
    downhole axis ``anchor[7:10]``. Writes scv[0] (force on the top segment),
    scv[1] (its moment), scv[2] (moment on the drive), scv[3] (drive angular
    velocity), ``loads_row`` and ``ed``. Returns the drive speed (rad/s).
    """
    top = x.shape[0] - 1
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
    joint_force(x[top], v[top], R[top], q[top], wW[top], seg[top, S_H],
                anchor[0:3], va, Ra, qa, wa, 0.0,
                jp[top, J_KA], jp[top, J_KS], jp[top, J_KB], jp[top, J_KT],
                jp[top, J_CA], jp[top, J_CS], jp[top, J_CB], jp[top, J_CT],
                scq[0], scq[1], scq[2], scm[0], scv[0], scv[1], scv[2], loads_row, ed)
    return omega_d


@njit(cache=True)
def top_energy(t, x, v, q, w, seg, jp, anchor, tab_t, tab_w, sc, R, wW, scq, scm, scv,
               loads, ed):
    """Energy (J) held by the top segment: its kinetic and gravity energy and the
    springs of the joint below it and of the top boundary.

    Used to account for the work of feeding pipe when the top segment grows
    (the difference before/after :func:`update_top`). Refreshes R and wW of the
    two top segments.
    """
    n = x.shape[0]
    top = n - 1
    lo = max(n - 2, 0)
    for i in range(lo, n):
        quat_to_rot(q[i], R[i])
        for k in range(3):
            wW[i, k] = R[i, k, 0] * w[i, 0] + R[i, k, 1] * w[i, 1] + R[i, k, 2] * w[i, 2]
    e = 0.5 * seg[top, S_M] * (v[top, 0] ** 2 + v[top, 1] ** 2 + v[top, 2] ** 2)
    e += 0.5 * seg[top, S_IT] * (w[top, 0] ** 2 + w[top, 1] ** 2) + 0.5 * seg[top, S_IA] * w[top, 2] ** 2
    e -= seg[top, S_W] * x[top, 2]
    if n >= 2:
        j = n - 2
        joint_force(x[j], v[j], R[j], q[j], wW[j], seg[j, S_H],
                    x[top], v[top], R[top], q[top], wW[top], seg[top, S_H],
                    jp[j, J_KA], jp[j, J_KS], jp[j, J_KB], jp[j, J_KT],
                    jp[j, J_CA], jp[j, J_CS], jp[j, J_CB], jp[j, J_CT],
                    scq[0], scq[1], scq[2], scm[0], scv[0], scv[1], scv[2], loads[j], ed)
        e += ed[0]
    top_joint(t, x, v, q, wW, R, seg, jp, anchor, tab_t, tab_w, sc, scq, scm, scv, loads[top], ed)
    e += ed[0]
    return e


@njit(cache=True)
def compute_forces(dt, x, v, q, w, seg, jp, bp, anchor, tab_t, tab_w,
                   node_md, node_pos, node_tan, wall, cpar, hint, sc, R, wW, Fw, Mw, Mb, loads, ch,
                   scq, scm, scv, ed):
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
    cpar : ndarray, shape (>= 1,) contact / friction parameters; cpar[P_ON] == 0: no wall contact
    hint : ndarray of int64, shape (n,)  per-segment cylinder hints (state, checkpointed)
    sc : ndarray, shape (N_SC,)   scalar state (sc[C_HINT] updated)
    R : ndarray, shape (n, 3, 3)  written: rotation matrices
    wW : ndarray, shape (n, 3)    written: angular velocities, world frame
    Fw, Mw : ndarray, shape (n, 3)  written: world force (N), world moment about the centre (N m)
    Mb : ndarray, shape (n, 3)    written: total body-frame moment (N m)
    loads : ndarray, shape (n, 6) written: joint loads, rows 0..n-2 joints, row n-1 top boundary
    ch : ndarray, shape (N_CH,)   written: channels and energy terms
    scq, scm, scv, ed             scratch, shapes (5, 4), (2, 3, 3), (8, 3), (2,)

    Returns
    -------
    int
        0, or 1 when wall contact is requested but not available.
    """
    n = x.shape[0]
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
    for j in range(n - 1):
        joint_force(x[j], v[j], R[j], q[j], wW[j], seg[j, S_H],
                    x[j + 1], v[j + 1], R[j + 1], q[j + 1], wW[j + 1], seg[j + 1, S_H],
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
    # --- wall contact and friction: ADD HERE (next issue) --------------------------------
    # Inputs already passed in: wall (cylinders: p0 = wall[:, 0:3], axis = wall[:, 3:6],
    # length = wall[:, 6], radius = wall[:, 7]), cpar (contact/friction parameters,
    # cpar[P_ON] == 0 -> off), hint[i] (cylinder hint of segment i, kept in the state),
    # seg[i, S_RC] (contact radius), dt. Outline:
    # if cpar[P_ON] != 0.0: for each segment i and each of its contact points X:
    #   ic = contact.find_contact(X, seg[i, S_RC], p0, axis, length, radius, hint[i], out6)
    #   if ic >= 0: normal force N = max(0, k_c delta + c_c delta_dot) along -n;
    #       slip velocity v_slip = v_i + wW_i x (X - x_i) minus its normal part;
    #       friction.friction_force(model, fparams, v_slip, N, f_other, dt, out3);
    #   hint[i] = ic; add the force to Fw[i] and (X - x_i) x force to Mw[i]; add the
    #   contact damping and friction power to pdiss and the contact spring energy to pe.
    #   Nothing else in the integrator changes.
    if cpar[P_ON] != 0.0:
        return 1  # wall contact requested but not implemented in this build
    # -----------------------------------------------------------------------------------
    # --- top boundary: top drive and rig -------------------------------------------------
    top = n - 1
    omega_d = top_joint(t, x, v, q, wW, R, seg, jp, anchor, tab_t, tab_w, sc, scq, scm, scv,
                        loads[top], ed)
    wa = scv[3]
    pe += ed[0]
    pdiss += ed[1]
    # the drive works on the string: minus the reaction moment on the drive times its speed
    pin -= Mu[0] * wa[0] + Mu[1] * wa[1] + Mu[2] * wa[2]
    for k in range(3):
        Fw[top, k] += Fl[k]
        Mw[top, k] += Ml[k]
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
    ch[H_TSURF] = loads[top, 5]
    ch[H_TOPRPM] = omega_d * RPM_PER_RAD_S
    # --- bit boundary ----------------------------------------------------------------------
    md_bit = bp[B_MD0] + bp[B_ROP] * t
    ch[H_BITMD] = md_bit
    ch[H_BITRPM] = w[0, 2] * RPM_PER_RAD_S
    if bp[B_BITON] == 1.0:
        ch[H_ROP] = bp[B_ROP]
        pos = scv[5]
        tan = scv[6]
        sc[C_HINT] = path_point(md_bit, node_md, node_pos, node_tan, int(sc[C_HINT]), pos, tan)
        nl = bp[B_NLOBE]
        s0 = bp[B_LOBE]
        phib = sc[C_PHIB]
        lob = s0 * math.sin(nl * phib)
        vl = bp[B_ROP] + s0 * nl * math.cos(nl * phib) * w[0, 2]
        h0 = seg[0, S_H]
        kb = bp[B_KBIT]
        cb = bp[B_CBIT]
        wob_f = 0.0
        fb0 = 0.0
        fb1 = 0.0
        fb2 = 0.0
        dd = 0.0
        for k in range(3):
            r = h0 * R[0, k, 2]
            xa = x[0, k] + r
            tgt = pos[k] + lob * tan[k]
            va_k = v[0, k] + (wW[0, (k + 1) % 3] * h0 * R[0, (k + 2) % 3, 2]
                              - wW[0, (k + 2) % 3] * h0 * R[0, (k + 1) % 3, 2])
            vt = vl * tan[k]
            f = -kb * (xa - tgt) - cb * (va_k - vt)
            dd += (xa - tgt) ** 2
            pdiss += cb * (va_k - vt) ** 2
            pin += f * vt
            wob_f -= f * tan[k]
            if k == 0:
                fb0 = f
            elif k == 1:
                fb1 = f
            else:
                fb2 = f
        pe += 0.5 * kb * dd
        r0 = h0 * R[0, 0, 2]
        r1 = h0 * R[0, 1, 2]
        r2 = h0 * R[0, 2, 2]
        Fw[0, 0] += fb0
        Fw[0, 1] += fb1
        Fw[0, 2] += fb2
        Mw[0, 0] += r1 * fb2 - r2 * fb1
        Mw[0, 1] += r2 * fb0 - r0 * fb2
        Mw[0, 2] += r0 * fb1 - r1 * fb0
        ch[H_WOB] = wob_f
        # torque on bit, opposing the bit rotation (bit-rock law plugs in here)
        tob = bp[B_TOB] * math.tanh(w[0, 2] / bp[B_WREF])
        Mb[0, 2] -= tob
        pdiss += tob * w[0, 2]
        ch[H_TOB] = tob
    else:
        ch[H_ROP] = 0.0
        ch[H_WOB] = 0.0
        ch[H_TOB] = 0.0
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
