"""Joint between two neighbouring rigid segments (docs/model.md#joints).

The upper end of the lower segment, P_lo = c_lo - h_lo e3_lo, and the lower end
of the upper segment, P_up = c_up + h_up e3_up (e3 = body axis, pointing
downhole), are tied by six spring-dampers expressed in the joint frame: the
mid frame R_m = R_lo exp(theta / 2) halfway between the two segment frames
(theta = log(R_lo^T R_up), the relative rotation vector), so the loads do not
depend on which neighbour is taken as reference and are invariant under a rigid
rotation of the whole string.

Springs: axial k_a = EA/L, two shear k_s = kappa G A / L, two bending
k_b = EI/L and torsion k_t = GJ/L (L the centre distance; for unequal halves the
two half-segment springs are in series), dampers c = 2 zeta sqrt(k m_eff).
Translation: F = K d + C d_dot with d = P_up - P_lo in the joint frame.
Rotation: potential V = theta^T K theta / 2; the exact moment on the lower body
is R_lo J_r^-1(theta) K theta (J_r the right Jacobian of SO(3)), which keeps
the discrete model conservative for finite twists (Barfoot, State Estimation
for Robotics, 2017, eq. 7.77 for J_r^-1). Half of the couple d x F goes to each
body so that angular momentum is conserved.

:func:`joint_forces` applies :func:`joint_force` to every joint of the active
string (reads the state, ``wk.R``/``wk.wW``, ``p.seg``, ``p.jp``; adds to
``s.Fw``/``s.Mw``; writes ``wk.loads``; scratch row ``V_J_VUP``).

Recorded loads (the internal force and moment the upper part exerts on the
lower part, in the joint frame, z downhole along the pipe axis):
[axial_N (tension > 0), shear_x_N, shear_y_N, bending_x_Nm, bending_y_Nm,
torque_Nm (> 0 when the top drives the lower string in the drilling sense)].
"""

from __future__ import annotations

import math

from numba import njit

from drillfatigue.dynamics.core.layout import (
    H_PDISS, H_PE, J_CA, J_CB, J_CS, J_CT, J_KA, J_KB, J_KS, J_KT, S_H, V_J_VUP,
)


@njit(cache=True, inline="always")
def joint_rotation(q_lo, q_up):
    """The joint's rotation and frame from its bodies' quaternions, as a tuple of floats:
    the rotation vector theta = log(conj(q_lo) q_up) on the shortest arc, components in
    the lower frame (3, rad), and the rotation matrix of the mid (joint) frame
    q_lo (1 + qr) / |1 + qr|, row by row (9)."""
    # relative rotation conj(q_lo) q_up (rigid.quat_conj_mul) on the shortest arc
    a0 = q_lo[0]
    a1 = q_lo[1]
    a2 = q_lo[2]
    a3 = q_lo[3]
    b0 = q_up[0]
    b1 = q_up[1]
    b2 = q_up[2]
    b3 = q_up[3]
    qr0 = a0 * b0 + a1 * b1 + a2 * b2 + a3 * b3
    qr1 = a0 * b1 - a1 * b0 - a2 * b3 + a3 * b2
    qr2 = a0 * b2 + a1 * b3 - a2 * b0 - a3 * b1
    qr3 = a0 * b3 - a1 * b2 + a2 * b1 - a3 * b0
    if qr0 < 0.0:
        qr0 = -qr0
        qr1 = -qr1
        qr2 = -qr2
        qr3 = -qr3
    # theta = log(qr) (rigid.quat_log with qr0 >= 0): lower frame == joint frame components
    sq = math.sqrt(qr1 * qr1 + qr2 * qr2 + qr3 * qr3)
    if sq < 1e-12:
        f = 2.0 / qr0 if qr0 > 0.0 else 2.0
    else:
        f = 2.0 * math.atan2(sq, qr0) / sq
    th0 = f * qr1
    th1 = f * qr2
    th2 = f * qr3
    # the half rotation (1 + qr) / |1 + qr| and the mid (joint) frame q_lo * half
    n = math.sqrt((1.0 + qr0) ** 2 + qr1 ** 2 + qr2 ** 2 + qr3 ** 2)
    h0 = (1.0 + qr0) / n
    h1 = qr1 / n
    h2 = qr2 / n
    h3 = qr3 / n
    qw = a0 * h0 - a1 * h1 - a2 * h2 - a3 * h3
    qx = a0 * h1 + a1 * h0 + a2 * h3 - a3 * h2
    qy = a0 * h2 - a1 * h3 + a2 * h0 + a3 * h1
    qz = a0 * h3 + a1 * h2 - a2 * h1 + a3 * h0
    # its rotation matrix Rm (rigid.quat_to_rot)
    m00 = 1.0 - 2.0 * (qy * qy + qz * qz)
    m01 = 2.0 * (qx * qy - qw * qz)
    m02 = 2.0 * (qx * qz + qw * qy)
    m10 = 2.0 * (qx * qy + qw * qz)
    m11 = 1.0 - 2.0 * (qx * qx + qz * qz)
    m12 = 2.0 * (qy * qz - qw * qx)
    m20 = 2.0 * (qx * qz - qw * qy)
    m21 = 2.0 * (qy * qz + qw * qx)
    m22 = 1.0 - 2.0 * (qx * qx + qy * qy)
    return th0, th1, th2, m00, m01, m02, m10, m11, m12, m20, m21, m22


@njit(cache=True, inline="always")
def joint_terms(lo, up, jrow):
    """Spring-damper loads of one joint, as a tuple of floats.

    Parameters
    ----------
    lo : tuple
        The lower body, ``(x, v, R, q, w, h)``: centre (m) and velocity (m/s), world,
        shape (3,); rotation matrix (3, 3); quaternion (4,); angular velocity in the
        WORLD frame (rad/s, (3,)); centre -> upper end distance h (m).
    up : tuple
        The upper body, the same (h: centre -> lower end).
    jrow : ndarray, shape (N_JP,)
        The joint's row of ``jp``: axial, shear (N/m), bending, torsion (N m/rad)
        stiffness and the matching damping coefficients (``J_*``).

    Returns
    -------
    tuple of 17 floats
        The force on the lower body (3, N, world; -F on the upper), the moments about
        each centre on the lower and on the upper body (3 + 3, N m, world), the
        joint-frame loads (6, see the module doc), the spring potential energy (J) and
        the damper power (W, >= 0).

    Every intermediate is a local, not a scratch array: a store to an array the
    compiler cannot tell apart from the inputs makes it load them again.
    """
    x_lo, v_lo, R_lo, q_lo, wl, h_lo = lo
    x_up, v_up, R_up, q_up, wu, h_up = up
    k_a = jrow[J_KA]
    k_s = jrow[J_KS]
    k_b = jrow[J_KB]
    k_t = jrow[J_KT]
    c_a = jrow[J_CA]
    c_s = jrow[J_CS]
    c_b = jrow[J_CB]
    c_t = jrow[J_CT]
    # attachment points and lever arms
    rl0 = -h_lo * R_lo[0, 2]
    rl1 = -h_lo * R_lo[1, 2]
    rl2 = -h_lo * R_lo[2, 2]
    ru0 = h_up * R_up[0, 2]
    ru1 = h_up * R_up[1, 2]
    ru2 = h_up * R_up[2, 2]
    d0 = (x_up[0] + ru0) - (x_lo[0] + rl0)
    d1 = (x_up[1] + ru1) - (x_lo[1] + rl1)
    d2 = (x_up[2] + ru2) - (x_lo[2] + rl2)
    # relative velocity of the attachment points
    vd0 = (v_up[0] + wu[1] * ru2 - wu[2] * ru1) - (v_lo[0] + wl[1] * rl2 - wl[2] * rl1)
    vd1 = (v_up[1] + wu[2] * ru0 - wu[0] * ru2) - (v_lo[1] + wl[2] * rl0 - wl[0] * rl2)
    vd2 = (v_up[2] + wu[0] * ru1 - wu[1] * ru0) - (v_lo[2] + wl[0] * rl1 - wl[1] * rl0)
    th0, th1, th2, m00, m01, m02, m10, m11, m12, m20, m21, m22 = joint_rotation(q_lo, q_up)
    # translation in the joint frame
    dl0 = m00 * d0 + m10 * d1 + m20 * d2
    dl1 = m01 * d0 + m11 * d1 + m21 * d2
    dl2 = m02 * d0 + m12 * d1 + m22 * d2
    ul0 = m00 * vd0 + m10 * vd1 + m20 * vd2
    ul1 = m01 * vd0 + m11 * vd1 + m21 * vd2
    ul2 = m02 * vd0 + m12 * vd1 + m22 * vd2
    fl0 = k_s * dl0 + c_s * ul0
    fl1 = k_s * dl1 + c_s * ul1
    fl2 = k_a * dl2 + c_a * ul2
    F0 = m00 * fl0 + m01 * fl1 + m02 * fl2
    F1 = m10 * fl0 + m11 * fl1 + m12 * fl2
    F2 = m20 * fl0 + m21 * fl1 + m22 * fl2
    # rotation spring: J_r^-1(theta) K theta, in the lower frame
    kt0 = k_b * th0
    kt1 = k_b * th1
    kt2 = k_t * th2
    aa = th0 * th0 + th1 * th1 + th2 * th2
    if aa < 1e-8:
        c2 = 1.0 / 12.0 + aa / 720.0
    else:
        a = math.sqrt(aa)
        c2 = 1.0 / aa - (1.0 + math.cos(a)) / (2.0 * a * math.sin(a))
    x0 = th1 * kt2 - th2 * kt1
    x1 = th2 * kt0 - th0 * kt2
    x2 = th0 * kt1 - th1 * kt0
    y0 = th1 * x2 - th2 * x1
    y1 = th2 * x0 - th0 * x2
    y2 = th0 * x1 - th1 * x0
    mm0 = kt0 + 0.5 * x0 + c2 * y0
    mm1 = kt1 + 0.5 * x1 + c2 * y1
    mm2 = kt2 + 0.5 * x2 + c2 * y2
    Mr0 = R_lo[0, 0] * mm0 + R_lo[0, 1] * mm1 + R_lo[0, 2] * mm2
    Mr1 = R_lo[1, 0] * mm0 + R_lo[1, 1] * mm1 + R_lo[1, 2] * mm2
    Mr2 = R_lo[2, 0] * mm0 + R_lo[2, 1] * mm1 + R_lo[2, 2] * mm2
    # rotation damper on the relative angular velocity, joint frame
    o0 = wu[0] - wl[0]
    o1 = wu[1] - wl[1]
    o2 = wu[2] - wl[2]
    ol0 = m00 * o0 + m10 * o1 + m20 * o2
    ol1 = m01 * o0 + m11 * o1 + m21 * o2
    ol2 = m02 * o0 + m12 * o1 + m22 * o2
    Mr0 += c_b * (m00 * ol0 + m01 * ol1) + c_t * m02 * ol2
    Mr1 += c_b * (m10 * ol0 + m11 * ol1) + c_t * m12 * ol2
    Mr2 += c_b * (m20 * ol0 + m21 * ol1) + c_t * m22 * ol2
    # half couple d x F to each body (angular momentum balance)
    hc0 = 0.5 * (d1 * F2 - d2 * F1)
    hc1 = 0.5 * (d2 * F0 - d0 * F2)
    hc2 = 0.5 * (d0 * F1 - d1 * F0)
    return (F0, F1, F2,
            rl1 * F2 - rl2 * F1 + Mr0 + hc0,
            rl2 * F0 - rl0 * F2 + Mr1 + hc1,
            rl0 * F1 - rl1 * F0 + Mr2 + hc2,
            -(ru1 * F2 - ru2 * F1) - Mr0 + hc0,
            -(ru2 * F0 - ru0 * F2) - Mr1 + hc1,
            -(ru0 * F1 - ru1 * F0) - Mr2 + hc2,
            -fl2, fl0, fl1,
            m00 * Mr0 + m10 * Mr1 + m20 * Mr2,
            m01 * Mr0 + m11 * Mr1 + m21 * Mr2,
            m02 * Mr0 + m12 * Mr1 + m22 * Mr2,
            0.5 * (k_s * (dl0 * dl0 + dl1 * dl1) + k_a * dl2 * dl2
                   + k_b * (th0 * th0 + th1 * th1) + k_t * th2 * th2),
            (c_s * (ul0 * ul0 + ul1 * ul1) + c_a * ul2 * ul2
             + c_b * (ol0 * ol0 + ol1 * ol1) + c_t * ol2 * ol2))


@njit(cache=True)
def joint_force(lo, up, jrow, out):
    """Spring-damper loads of one joint (:func:`joint_terms`) written into arrays.

    Parameters: ``lo``, ``up``, ``jrow`` as for :func:`joint_terms`, and ``out``, the
    arrays written, ``(F_lo, M_lo, M_up, loads, ed)``: the force on the lower body
    (3, N, world; -F_lo on the upper), the moments about each centre (3 + 3, N m,
    world), the joint-frame loads (6, see the module doc) and
    ``[spring potential energy (J), damper power (W, >= 0)]``.
    """
    F_lo, M_lo, M_up, loads, ed = out
    r = joint_terms(lo, up, jrow)
    for k in range(3):
        F_lo[k] = r[k]
        M_lo[k] = r[3 + k]
        M_up[k] = r[6 + k]
    for k in range(6):
        loads[k] = r[9 + k]
    ed[0] = r[15]
    ed[1] = r[16]


# Compiled without numba's reference counting (``_nrt=False``), as a call of its own: each
# row passed to the joint kernel (``x[j]``, ``R[j]``, ``loads[j]``, ...) is a view, and with
# reference counting every view costs an atomic increment and decrement; the loop
# allocates nothing, so it needs none. Same arithmetic in the same order (bit-identical),
# about 3x faster. numpy's error model: divisions without the zero-divisor test
# (integrator.half_kicks).
@njit(cache=True, _nrt=False, error_model="numpy")  # type: ignore[call-overload]  # _nrt: not in numba's stubs
def joint_forces(n, growth, s, p, wk):
    """Loads of the n - 1 joints between the active segments, added to the segments.

    ``growth`` (m/s): the rate at which the top segment's lower end moves along
    its axis by drilling or tripping (on top of its rigid motion), which the
    damper of the joint below it sees. Reads ``s.x, s.v, s.q``, ``wk.R, wk.wW``,
    ``p.seg, p.jp``; adds to ``s.Fw, s.Mw``; writes ``wk.loads[0:n-1]`` and adds
    the spring energy and damper power to ``wk.ch[H_PE]``, ``wk.ch[H_PDISS]``.
    """
    x = s.x
    v = s.v
    q = s.q
    Fw = s.Fw
    Mw = s.Mw
    R = wk.R
    wW = wk.wW
    seg = p.seg
    jp = p.jp
    loads = wk.loads
    ch = wk.ch
    vec = wk.vec
    vtop = vec[V_J_VUP]
    for j in range(n - 1):
        vu = v[j + 1]
        if j == n - 2 and growth != 0.0:
            for k in range(3):
                vtop[k] = v[j + 1, k] + growth * R[j + 1, k, 2]
            vu = vtop
        r = joint_terms((x[j], v[j], R[j], q[j], wW[j], seg[j, S_H]),
                        (x[j + 1], vu, R[j + 1], q[j + 1], wW[j + 1], seg[j + 1, S_H]), jp[j])
        lj = loads[j]
        for k in range(6):
            lj[k] = r[9 + k]
        ch[H_PE] += r[15]
        ch[H_PDISS] += r[16]
        for k in range(3):
            Fw[j, k] += r[k]
            Fw[j + 1, k] -= r[k]
            Mw[j, k] += r[3 + k]
            Mw[j + 1, k] += r[6 + k]
