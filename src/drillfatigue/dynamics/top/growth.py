"""Growth of the string: drilling and tripping change its length at the top (docs/model.md#top-boundary).

Each step the string length changes by dL = ROP dt (bit on bottom: the ROP
of the bit law or the prescribed one; the rock face MD advances by the same
amount) or trip_speed dt (off bottom). With the rig boundaries
(``bp[B_RIG] == 1``) the two are separate: the string below the rotary grows
by the block's travel, ``sc[C_VGROW] dt`` (0 while the slips are set), and the
rock face advances by what the bit cut, ``ROP dt`` (0 off bottom). The top segment grows (or shrinks)
from its fixed top end (:func:`grow_top`). When it is longer than
``bp[B_LSPLIT]`` a segment of ``bp[B_LNOM]`` is split off its bottom
(:func:`split_top`), so a 480 -> 880 m run keeps its resolution; when a
tripping-out top segment is shorter than ``bp[B_LMIN]`` it merges with the
one below (:func:`merge_top`); with only two segments left tripping out stops
(``sc[C_GUARD] = 1``). Arrays are allocated to the largest size the run can
reach; the kernels use the first ``sc[C_NACT]`` rows (no reallocation).
Energy changed by growth, splits and merges is booked as work put in
(``sc[C_WIN]``, feeding pipe), from :func:`tail_energy` before and after.
The growth is applied once per step (the joint below the top is shortened by
dL at once), so the booking carries an O(dt) error of about k_a dL^2 / 2 per
step: with 3 m pipe segments at 0.5 m/s the summary's
``energy_balance_error_rel`` reaches ~0.2 (it halves with the step); without
growth the balance closes to ~1e-4. With the rig boundaries, and by default
(``solver.growth_work_trapezoid``, ``bp[B_GROWTRAP]``) also with a prescribed
ROP or trip speed, the growth is booked as a prescribed velocity of the top
segment's lower end: the energy difference plus the correction that turns its
force into the trapezoid of the joint's axial force over the step (what the
integrator's kicks see), which closes the balance while drilling. The damper of the joint below the top
sees the growth rate (:func:`growth_rate`), so no spurious static load builds
up there.

Arrays: the state ``s`` (x, v, q, w, sc, hint, cst: rows moved, added or
cleared), the top rows of ``p.seg`` and ``p.jp`` and the section ``p.topp``
(rebuilt by :func:`update_top`), ``wk.R``/``wk.wW``/``wk.loads`` of the top
rows, scratch rows ``V_G_*`` (and the joint rows) of ``wk.vec``.
"""

from __future__ import annotations

import math

from numba import njit

from drillfatigue.dynamics.top.boundaries import top_joint
from drillfatigue.dynamics.core.joints import joint_force
from drillfatigue.dynamics.core.layout import (
    B_AXMODE, B_BITON, B_EXT, B_FREEZE, B_GROWTRAP, B_RIG, C_VGROW, B_LMIN, B_LNOM, B_LSPLIT,
    B_TOPAUTO_A, B_TOPAUTO_T, B_TOPLAT, B_TOPMODE, B_ZB, B_ZJ, C_GUARD, C_MDROCK, C_NACT, C_NMERGE,
    C_NSPLIT, C_ROPNOW, C_WIN, CS_ONT, J_CA, J_CB, J_CS, J_CT, J_KA, J_KB, J_KS, J_KT,
    MAX_CONTACT_POINTS, S_CA, S_CC, S_CL, S_CRA, S_CRL, S_H, S_IA, S_IT, S_M, S_RB, S_RC, S_W,
    T_CAPL, T_CLPL, T_CRAPL, T_CRLPL, T_EA, T_EA2, T_EI, T_EI2, T_GJ, T_GJ2, T_KA_TOP, T_KGA,
    T_KGA2, T_KPAR_B, T_KPAR_S, T_KT_TOP, T_MPL, T_R2, T_WPL, V_G_LOW, V_G_Q, V_G_R, V_G_TH,
    V_G_TOP, V_G_VPIECE, V_G_VTOP, V_G_W, V_G_XC, V_J_ED, V_J_F, V_J_MLO, V_J_MUP, V_J_VUP,
)
from drillfatigue.dynamics.core.rigid import quat_conj_mul, quat_exp_mul, quat_log, quat_to_rot


@njit(cache=True)
def seg_row(i, h, seg, topp):
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
    seg_row(top, h, seg, topp)
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


@njit(cache=True, inline="always")
def growth_rate(bp, sc):
    """Rate (m/s) at which the top segment's lower end moves along its axis by growth:
    the ROP on bottom, the trip speed off bottom, 0 while frozen or stopped."""
    if bp[B_FREEZE] == 1.0:
        return 0.0
    if bp[B_RIG] == 1.0:
        return sc[C_VGROW]
    if bp[B_BITON] == 1.0:
        return sc[C_ROPNOW]
    g = bp[B_EXT]
    if sc[C_GUARD] == 1.0 and g < 0.0:
        return 0.0
    return g


@njit(cache=True, inline="always")
def tail_energy(lo, t, s, p, wk):
    """Energy (J) of segments lo..n-1 (kinetic + gravity), the joints lo-1..n-2 and the top boundary.

    Used to book the work of feeding pipe when the top segment grows, is split
    (drilling) or merged (tripping out): the difference before/after. Refreshes
    ``wk.R`` and ``wk.wW`` of segments lo-1..n-1 and their rows of ``wk.loads``.
    """
    x = s.x
    v = s.v
    q = s.q
    w = s.w
    seg = p.seg
    jp = p.jp
    R = wk.R
    wW = wk.wW
    loads = wk.loads
    vec = wk.vec
    n = int(s.sc[C_NACT])
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
        joint_force((x[j], v[j], R[j], q[j], wW[j], seg[j, S_H]),
                    (x[j + 1], v[j + 1], R[j + 1], q[j + 1], wW[j + 1], seg[j + 1, S_H]), jp[j],
                    (vec[V_J_F], vec[V_J_MLO], vec[V_J_MUP], loads[j], vec[V_J_ED]))
        e += vec[V_J_ED, 0]
    top_joint(t, top, s, p, wk, loads[top])
    e += vec[V_J_ED, 0]
    return e


@njit(cache=True)
def joint_below_top_axial(top, growth, s, p, wk):
    """Axial load (N, tension > 0) of the joint below the top segment ``top`` now, its
    damper seeing the growth rate ``growth`` (m/s) as in the force evaluation
    (:func:`joints.joint_forces`); ``wk.R``, ``wk.wW`` of both segments must be current.
    Writes ``wk.loads[top - 1]``."""
    x = s.x
    v = s.v
    q = s.q
    seg = p.seg
    jp = p.jp
    R = wk.R
    wW = wk.wW
    vec = wk.vec
    j = top - 1
    vu = vec[V_J_VUP]
    for k in range(3):
        vu[k] = v[top, k] + growth * R[top, k, 2]
    joint_force((x[j], v[j], R[j], q[j], wW[j], seg[j, S_H]),
                (x[top], vu, R[top], q[top], wW[top], seg[top, S_H]), jp[j],
                (vec[V_J_F], vec[V_J_MLO], vec[V_J_MUP], wk.loads[j], vec[V_J_ED]))
    return wk.loads[j, 0]


@njit(cache=True)
def _rigid_point_velocity(v, wW, r, out):
    out[0] = v[0] + wW[1] * r[2] - wW[2] * r[1]
    out[1] = v[1] + wW[2] * r[0] - wW[0] * r[2]
    out[2] = v[2] + wW[0] * r[1] - wW[1] * r[0]


@njit(cache=True)
def split_top(s, p, wk, growth):
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
    x = s.x
    v = s.v
    q = s.q
    w = s.w
    sc = s.sc
    hint = s.hint
    cst = s.cst
    seg = p.seg
    jp = p.jp
    topp = p.topp
    bp = p.bp
    R = wk.R
    vec = wk.vec
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
    qt = vec[V_G_Q]
    th = vec[V_G_TH]
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
    wv = vec[V_G_W]
    r = vec[V_G_R]
    vel = vec[V_G_VPIECE]
    for k in range(3):
        wv[k] = R[top, k, 0] * w[top, 0] + R[top, k, 1] * w[top, 1] + R[top, k, 2] * w[top, 2]
    h1 = 0.5 * ln
    h2 = h - h1
    xc = vec[V_G_XC]
    for k in range(3):
        xc[k] = x[top, k]
    # lower piece: centre (h - h1) below the old centre along e3; new top: (h - h2) above it
    for k in range(3):
        r[k] = (h - h1) * R[top, k, 2]
    _rigid_point_velocity(v[top], wv, r, vel)
    vnew = vec[V_G_VTOP]
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
    seg_row(top, h1, seg, topp)
    for pt in range(MAX_CONTACT_POINTS):
        hint[MAX_CONTACT_POINTS * new + pt] = hint[MAX_CONTACT_POINTS * top + pt]
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
        quat_exp_mul(q[top], 0.0, 0.0, a1, q[top])
        quat_exp_mul(q[new], 0.0, 0.0, a2, q[new])
    return n + 1


@njit(cache=True)
def merge_top(s, p, wk):
    """Tripping out: merge the (short) top segment with the segment below it.

    The merged body takes the orientation of the lower one, spans from its lower
    end to the old top end along its axis, and the momentum-weighted velocities
    (the relative motion of the two parts is lost: an inelastic merge; the
    caller books the energy change). The merged segment gets the top section's
    per-length properties. Returns the new active count.
    """
    x = s.x
    v = s.v
    q = s.q
    w = s.w
    sc = s.sc
    seg = p.seg
    jp = p.jp
    R = wk.R
    n = int(sc[C_NACT])
    top = n - 1
    lo = n - 2
    quat_to_rot(q[lo], R[lo])
    quat_to_rot(q[top], R[top])
    m1 = seg[lo, S_M]
    m2 = seg[top, S_M]
    i1 = seg[lo, S_IT]
    i2 = seg[top, S_IT]
    lowend = wk.vec[V_G_LOW]
    topend = wk.vec[V_G_TOP]
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
    seg_row(lo, h, seg, p.topp)
    update_top(h, n - 1, seg, jp, p.topp, p.bp)
    return n - 1


@njit(cache=True, inline="always")
def grow_top(n, t1, s, p, wk):
    """One step of growth of the string (see the module docstring); returns the active count.

    ``n``: active segments, ``t1``: the time at the end of the step (s). The
    rock face advances by the bit's ROP on bottom (``sc[C_MDROCK]``); the top
    segment lengthens or shortens from its fixed top end; a split or a merge
    follows when it passes its limits; the energy this changes is booked as
    work put in (``sc[C_WIN]``).
    """
    sc = s.sc
    bp = p.bp
    seg = p.seg
    x = s.x
    R = wk.R
    dt = p.dt
    nmax = x.shape[0]
    if bp[B_FREEZE] == 1.0:
        dL = 0.0
    elif bp[B_RIG] == 1.0:
        # the rig: the rock face advances by what the bit cut (0 off bottom), the string
        # below the rotary by what the block moved
        if bp[B_BITON] == 1.0:
            sc[C_MDROCK] += sc[C_ROPNOW] * dt
        dL = sc[C_VGROW] * dt
        if sc[C_GUARD] == 1.0 and dL < 0.0:
            dL = 0.0
    elif bp[B_BITON] == 1.0:
        dL = sc[C_ROPNOW] * dt
        sc[C_MDROCK] += dL
    else:
        dL = bp[B_EXT] * dt
        if sc[C_GUARD] == 1.0 and dL < 0.0:
            dL = 0.0
    if dL == 0.0:
        return n
    top = n - 1
    trap = (bp[B_RIG] == 1.0 or bp[B_GROWTRAP] == 1.0) and top >= 1
    t_prev = wk.loads[top - 1, 0] if trap else 0.0
    e_before = tail_energy(top, t1, s, p, wk)
    if trap:
        # growth as a prescribed velocity: the feed works against the axial force of the
        # joint below the top with the trapezoid of that force over the step (its value at
        # the last force evaluation and at the end of the drift), as the integrator's
        # kicks do; the energy difference of the length change alone books the force at
        # the end of the drift only and leaves k_a dL * (string motion) / 2 per step
        sc[C_WIN] += 0.5 * dL * (joint_below_top_axial(top, dL / dt, s, p, wk) - t_prev)
    h_new = seg[top, S_H] + 0.5 * dL
    if 2.0 * h_new < bp[B_LMIN] and n <= 2:
        # tripping out: keep a minimum string
        sc[C_GUARD] = 1.0
        h_new = seg[top, S_H]
    dh = h_new - seg[top, S_H]
    for k in range(3):
        x[top, k] += dh * R[top, k, 2]
    update_top(h_new, n, seg, p.jp, p.topp, bp)
    if 2.0 * h_new > bp[B_LSPLIT] and n < nmax:
        n = split_top(s, p, wk, dL / dt)
        sc[C_NSPLIT] += 1.0
    elif 2.0 * h_new < bp[B_LMIN] and n > 2:
        e_before = tail_energy(n - 2, t1, s, p, wk) - tail_energy(top, t1, s, p, wk) + e_before
        n = merge_top(s, p, wk)
        sc[C_NMERGE] += 1.0
        top = n - 1
    sc[C_WIN] += tail_energy(top, t1, s, p, wk) - e_before
    return n
