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
``s.Fw``/``s.Mw``; writes ``wk.loads``; scratch rows ``V_J_*``, ``M_J_RM``).

Recorded loads (the internal force and moment the upper part exerts on the
lower part, in the joint frame, z downhole along the pipe axis):
[axial_N (tension > 0), shear_x_N, shear_y_N, bending_x_Nm, bending_y_Nm,
torque_Nm (> 0 when the top drives the lower string in the drilling sense)].
"""

from __future__ import annotations

import math

from numba import njit

from drillfatigue.dynamics.layout import (
    H_PDISS, H_PE, J_CA, J_CB, J_CS, J_CT, J_KA, J_KB, J_KS, J_KT, M_J_RM, S_H, V_J_ED, V_J_F,
    V_J_MLO, V_J_MUP, V_J_QH, V_J_QM, V_J_QR, V_J_VUP,
)
from drillfatigue.dynamics.rigid import quat_conj_mul, quat_log, quat_mul, quat_to_rot


@njit(cache=True)
def joint_force(x_lo, v_lo, R_lo, q_lo, wl, h_lo, x_up, v_up, R_up, q_up, wu, h_up,
                k_a, k_s, k_b, k_t, c_a, c_s, c_b, c_t,
                qr, qh, qm, Rm, F_lo, M_lo, M_up, loads, ed):
    """Spring-damper loads of one joint.

    Parameters
    ----------
    x_lo, v_lo : ndarray, shape (3,)   lower body centre (m) and velocity (m/s), world
    R_lo : ndarray, shape (3, 3)       lower body rotation matrix
    q_lo : ndarray, shape (4,)         lower body quaternion
    wl : ndarray, shape (3,)           lower body angular velocity, WORLD frame (rad/s)
    h_lo : float                       centre -> upper end distance of the lower body (m)
    x_up, v_up, R_up, q_up, wu, h_up   same for the upper body (h_up: centre -> lower end)
    k_a, k_s, k_b, k_t : float         axial, shear (N/m), bending, torsion (N m/rad) stiffness
    c_a, c_s, c_b, c_t : float         matching damping coefficients
    qr, qh, qm : ndarray, shape (4,)   scratch
    Rm : ndarray, shape (3, 3)         scratch (joint frame)
    F_lo : ndarray, shape (3,)         written: force on the lower body (N, world); -F_lo on the upper
    M_lo, M_up : ndarray, shape (3,)   written: moments about each centre (N m, world)
    loads : ndarray, shape (6,)        written: joint-frame loads (see module doc)
    ed : ndarray, shape (2,)           written: [spring potential energy (J), damper power (W, >= 0)]
    """
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
    # relative rotation and the mid (joint) frame
    quat_conj_mul(q_lo, q_up, qr)
    if qr[0] < 0.0:
        for k in range(4):
            qr[k] = -qr[k]
    quat_log(qr, qh)  # qh[0:3] = theta (lower frame == joint frame components)
    th0, th1, th2 = qh[0], qh[1], qh[2]
    n = math.sqrt((1.0 + qr[0]) ** 2 + qr[1] ** 2 + qr[2] ** 2 + qr[3] ** 2)
    qh[0] = (1.0 + qr[0]) / n
    qh[1] = qr[1] / n
    qh[2] = qr[2] / n
    qh[3] = qr[3] / n
    quat_mul(q_lo, qh, qm)
    quat_to_rot(qm, Rm)
    # translation in the joint frame
    dl0 = Rm[0, 0] * d0 + Rm[1, 0] * d1 + Rm[2, 0] * d2
    dl1 = Rm[0, 1] * d0 + Rm[1, 1] * d1 + Rm[2, 1] * d2
    dl2 = Rm[0, 2] * d0 + Rm[1, 2] * d1 + Rm[2, 2] * d2
    ul0 = Rm[0, 0] * vd0 + Rm[1, 0] * vd1 + Rm[2, 0] * vd2
    ul1 = Rm[0, 1] * vd0 + Rm[1, 1] * vd1 + Rm[2, 1] * vd2
    ul2 = Rm[0, 2] * vd0 + Rm[1, 2] * vd1 + Rm[2, 2] * vd2
    fl0 = k_s * dl0 + c_s * ul0
    fl1 = k_s * dl1 + c_s * ul1
    fl2 = k_a * dl2 + c_a * ul2
    F0 = Rm[0, 0] * fl0 + Rm[0, 1] * fl1 + Rm[0, 2] * fl2
    F1 = Rm[1, 0] * fl0 + Rm[1, 1] * fl1 + Rm[1, 2] * fl2
    F2 = Rm[2, 0] * fl0 + Rm[2, 1] * fl1 + Rm[2, 2] * fl2
    F_lo[0] = F0
    F_lo[1] = F1
    F_lo[2] = F2
    # rotation spring: J_r^-1(theta) K theta, in the lower frame
    kt0 = k_b * th0
    kt1 = k_b * th1
    kt2 = k_t * th2
    a2 = th0 * th0 + th1 * th1 + th2 * th2
    if a2 < 1e-8:
        c2 = 1.0 / 12.0 + a2 / 720.0
    else:
        a = math.sqrt(a2)
        c2 = 1.0 / a2 - (1.0 + math.cos(a)) / (2.0 * a * math.sin(a))
    x0 = th1 * kt2 - th2 * kt1
    x1 = th2 * kt0 - th0 * kt2
    x2 = th0 * kt1 - th1 * kt0
    y0 = th1 * x2 - th2 * x1
    y1 = th2 * x0 - th0 * x2
    y2 = th0 * x1 - th1 * x0
    m0 = kt0 + 0.5 * x0 + c2 * y0
    m1 = kt1 + 0.5 * x1 + c2 * y1
    m2 = kt2 + 0.5 * x2 + c2 * y2
    Mr0 = R_lo[0, 0] * m0 + R_lo[0, 1] * m1 + R_lo[0, 2] * m2
    Mr1 = R_lo[1, 0] * m0 + R_lo[1, 1] * m1 + R_lo[1, 2] * m2
    Mr2 = R_lo[2, 0] * m0 + R_lo[2, 1] * m1 + R_lo[2, 2] * m2
    # rotation damper on the relative angular velocity, joint frame
    o0 = wu[0] - wl[0]
    o1 = wu[1] - wl[1]
    o2 = wu[2] - wl[2]
    ol0 = Rm[0, 0] * o0 + Rm[1, 0] * o1 + Rm[2, 0] * o2
    ol1 = Rm[0, 1] * o0 + Rm[1, 1] * o1 + Rm[2, 1] * o2
    ol2 = Rm[0, 2] * o0 + Rm[1, 2] * o1 + Rm[2, 2] * o2
    Mr0 += c_b * (Rm[0, 0] * ol0 + Rm[0, 1] * ol1) + c_t * Rm[0, 2] * ol2
    Mr1 += c_b * (Rm[1, 0] * ol0 + Rm[1, 1] * ol1) + c_t * Rm[1, 2] * ol2
    Mr2 += c_b * (Rm[2, 0] * ol0 + Rm[2, 1] * ol1) + c_t * Rm[2, 2] * ol2
    # half couple d x F to each body (angular momentum balance)
    h0 = 0.5 * (d1 * F2 - d2 * F1)
    h1 = 0.5 * (d2 * F0 - d0 * F2)
    h2 = 0.5 * (d0 * F1 - d1 * F0)
    M_lo[0] = rl1 * F2 - rl2 * F1 + Mr0 + h0
    M_lo[1] = rl2 * F0 - rl0 * F2 + Mr1 + h1
    M_lo[2] = rl0 * F1 - rl1 * F0 + Mr2 + h2
    M_up[0] = -(ru1 * F2 - ru2 * F1) - Mr0 + h0
    M_up[1] = -(ru2 * F0 - ru0 * F2) - Mr1 + h1
    M_up[2] = -(ru0 * F1 - ru1 * F0) - Mr2 + h2
    loads[0] = -fl2
    loads[1] = fl0
    loads[2] = fl1
    loads[3] = Rm[0, 0] * Mr0 + Rm[1, 0] * Mr1 + Rm[2, 0] * Mr2
    loads[4] = Rm[0, 1] * Mr0 + Rm[1, 1] * Mr1 + Rm[2, 1] * Mr2
    loads[5] = Rm[0, 2] * Mr0 + Rm[1, 2] * Mr1 + Rm[2, 2] * Mr2
    ed[0] = 0.5 * (k_s * (dl0 * dl0 + dl1 * dl1) + k_a * dl2 * dl2
                   + k_b * (th0 * th0 + th1 * th1) + k_t * th2 * th2)
    ed[1] = (c_s * (ul0 * ul0 + ul1 * ul1) + c_a * ul2 * ul2
             + c_b * (ol0 * ol0 + ol1 * ol1) + c_t * ol2 * ol2)


#: :func:`joint_force` compiled into the joint loop of the step (it runs n - 1 times per
#: step there); the other callers (top drive, growth) keep the compiled call, which holds
#: the step's compile time down. Never called from Python, so never compiled alone.
_joint_force_inline = njit(inline="always")(joint_force.py_func)


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
    Fl = vec[V_J_F]
    Ml = vec[V_J_MLO]
    Mu = vec[V_J_MUP]
    ed = vec[V_J_ED]
    vtop = vec[V_J_VUP]
    qr = vec[V_J_QR]
    qh = vec[V_J_QH]
    qm = vec[V_J_QM]
    Rm = wk.mat[M_J_RM]
    for j in range(n - 1):
        vu = v[j + 1]
        if j == n - 2 and growth != 0.0:
            for k in range(3):
                vtop[k] = v[j + 1, k] + growth * R[j + 1, k, 2]
            vu = vtop
        _joint_force_inline(x[j], v[j], R[j], q[j], wW[j], seg[j, S_H],
                            x[j + 1], vu, R[j + 1], q[j + 1], wW[j + 1], seg[j + 1, S_H],
                            jp[j, J_KA], jp[j, J_KS], jp[j, J_KB], jp[j, J_KT],
                            jp[j, J_CA], jp[j, J_CS], jp[j, J_CB], jp[j, J_CT],
                            qr, qh, qm, Rm, Fl, Ml, Mu, loads[j], ed)
        ch[H_PE] += ed[0]
        ch[H_PDISS] += ed[1]
        for k in range(3):
            Fw[j, k] += Fl[k]
            Fw[j + 1, k] -= Fl[k]
            Mw[j, k] += Ml[k]
            Mw[j + 1, k] += Mu[k]
