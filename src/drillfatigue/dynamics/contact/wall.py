"""Wellbore contact: the fast point-in-cylinder test and the penalty normal force.

The hole is a chain of straight cylinders (centre-line start point ``p0[i]``,
unit axis ``axis[i]``, length ``length[i]``, radius ``radius[i]``), built from
the survey by minimum curvature and resampled finely enough that the chord
error is far below the clearance (:func:`build_cylinder_chain`).

For a contact point X of a segment with contact (outer) radius r, and
cylinder i (docs/model.md#contact; Liyanarachchi & Rideout, Math. Comput. Model.
Dyn. Syst. 30 (2024) 417-443)::

    v = X - P_i,   s = v . a_i,   q = v . v - s**2
    contact  <=>  q > (R_i - r)**2          (no square root needed)
    delta = sqrt(q) - (R_i - r),   n = (v - s a_i) / sqrt(q)

Bends. The hole is the union of the cylinders, capped at each shared end point
by a sphere (the wall of the "wedge" outside a bend). The distance of X from
the hole's centre line is therefore the clamped distance to the polyline,
taken over the located cylinder and its two neighbours:

* inside a bend, where the slabs of cylinders i and i+1 overlap, the cylinder
  with the smaller penetration wins (X is inside the union if it is inside
  either cylinder);
* in the wedge outside a bend (X beyond the end of i and before the start of
  i+1) the distance is measured from the shared end point P_{i+1}.

Both rules give a wall that is continuous (and has a continuous normal) through
the bend. The search is O(1): it starts from the cylinder found at the last
call (``hint``), walks along the chain only while s lies outside [0, l], and
then compares the located cylinder with its two neighbours.

The wall loop (:func:`wall_contact`) runs over the active segments and their
contact points (:func:`contact_point`: the ends, with the tool-joint or
stabilizer radius, and optionally the middle; or the string's own points, plus
each segment's deepest point between them, :func:`deepest_point`), locates each point
(:func:`locate`) and, where it penetrates, computes :func:`wall_force`'s force
(:func:`located_wall_force`: normal
force plus the friction law of :mod:`friction`) at each, estimates Karnopp's
"other" force first, caps the smooth laws' friction so one step cannot reverse
a slip, and records contact statistics and whirl angles (:mod:`events`).
Arrays: reads the state's positions and velocities, ``wk.R``/``wk.wW``,
``p.seg`` (radii ``S_RC``/``S_RB``, dash-pot ``S_CC``), ``p.wall`` (the
cylinders: columns ``W_*``), ``p.cpar`` (``P_*``: penalty, friction law and
parameters, points per segment); updates the hints ``s.hint`` (one per
contact point, ``MAX_CONTACT_POINTS`` per segment) and ``s.cst``; adds to
``s.Fw``, ``s.Mw`` and the energy channels.

Penalty stiffness and the stable step. The wall is a spring k_c (N/m) with
dash-pot c_c (N s/m). With an explicit (symplectic Euler / central
difference) integrator a mass m on a spring k is stable for
dt < 2 / omega = 2 sqrt(m / k) (reduced by damping to
2 (sqrt(1 + zeta**2) - zeta) / omega), see :func:`stable_dt`. The contact
spring should not be the stiffest element of the model: for a 9 m segment of
5 in drill pipe (m ~ 260 kg) the joint shear/axial springs are ~1e8-1e9 N/m,
so the default k_c = 5e7 N/m (the value used by open codes) leaves the step
set by the joints, and the penetration at a 10 kN side force is only 0.2 mm,
far below the ~44 mm radial clearance of 5 in pipe in an 8.5 in hole.
Damping c_c = 2 zeta sqrt(k_c m) with zeta = 0.2 (10-30 % of critical, MODEL
section 5); 5e4 N s/m for the 260 kg segment, as in the open codes.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np
from numba import njit

from drillfatigue.dynamics.contact.events import record_contact, track_whirl
from drillfatigue.dynamics.contact.friction.dispatch import has_stiction
from drillfatigue.dynamics.contact.friction.kernel import friction_force_split
from drillfatigue.dynamics.contact.friction.registry import N_PARAMS as N_FRICTION_PARAMS
from drillfatigue.dynamics.core.layout import (
    B_TWIN, C_MDROCK, H_FCMAX, H_NCON, H_NSEG, H_PDISS, H_PE, MAX_CONTACT_POINTS,
    MAX_TABLE_POINTS, P_CPTAB, P_DEEP, P_FMODEL, P_FP,
    P_KC, P_NPTS, P_ON, S_CC, S_H, S_IA, S_IT, S_M, S_RB, S_RC, WALL_INFO_SIZE, WI_CYL, WI_DELTA,
    WI_DIST, WI_FO, WI_N, WI_NX, WI_SLIP, WI_VS, V_W_ALIN, V_W_ALPHA, V_W_AX, V_W_F, V_W_FO,
    V_W_G, V_W_INFO, V_W_M, V_W_OFF, V_W_WHIRL, V_W_X,
)
from drillfatigue.dynamics.core.status import OK

if TYPE_CHECKING:  # pydantic stays out of the kernel module at run time
    from drillfatigue.config.contact import ContactConfig

#: Layout of the ``out`` array of :func:`find_contact`.
OUT_DELTA = 0
OUT_NX = 1
OUT_NY = 2
OUT_NZ = 3
OUT_S = 4
OUT_DIST = 5
OUT_SIZE = 6

#: Return value of :func:`find_contact` for a point beyond either end of the chain.
OUTSIDE_CHAIN = -1


@njit(cache=True, inline="always")
def _clamped_q(x0, x1, x2, p0, axis, length, i):
    """Squared clamped distance of the point (x0, x1, x2) from the centre-line segment i,
    and s."""
    vx = x0 - p0[i, 0]
    vy = x1 - p0[i, 1]
    vz = x2 - p0[i, 2]
    s = vx * axis[i, 0] + vy * axis[i, 1] + vz * axis[i, 2]
    vv = vx * vx + vy * vy + vz * vz
    if s < 0.0:
        q = vv
    elif s > length[i]:
        # |v - l a|^2 = vv - 2 s l + l^2: distance from the end point P_{i+1}
        q = vv - 2.0 * s * length[i] + length[i] * length[i]
    else:
        q = vv - s * s
    if q < 0.0:  # round-off for a point on the axis
        q = 0.0
    return q, s


@njit(cache=True, inline="always")
def locate(x0, x1, x2, r_contact, p0, axis, length, radius, hint):
    """:func:`find_contact` of the point (x0, x1, x2) as locals: returns (cylinder or
    ``OUTSIDE_CHAIN``, penetration delta (m), the perpendicular w from the hole centre
    line to the point (3, m; the normal is w / |w|), s along the cylinder (m), the
    distance |w| from the centre line (m)). The wall loop keeps these in registers and
    takes the normal only for a point that penetrates."""
    n = length.shape[0]
    i = hint
    if i < 0:
        i = 0
    if i > n - 1:
        i = n - 1
    # --- walk along the chain until s is inside [0, l] or we hit a wedge
    q, s = _clamped_q(x0, x1, x2, p0, axis, length, i)
    direction = 0
    status = i
    for _ in range(n + 1):
        if s < 0.0:
            if i == 0:
                status = OUTSIDE_CHAIN
                break
            if direction == 1:  # came from below: wedge between i-1 and i
                break
            direction = -1
            i -= 1
        elif s > length[i]:
            if i == n - 1:
                status = OUTSIDE_CHAIN
                break
            if direction == -1:  # came from above: wedge between i and i+1
                break
            direction = 1
            i += 1
        else:
            break
        q, s = _clamped_q(x0, x1, x2, p0, axis, length, i)

    best = i
    best_q = q
    best_s = s
    if status == OUTSIDE_CHAIN:
        # prolong the end cylinder: perpendicular distance, unclamped
        vx = x0 - p0[i, 0]
        vy = x1 - p0[i, 1]
        vz = x2 - p0[i, 2]
        best_q = vx * vx + vy * vy + vz * vz - s * s
        if best_q < 0.0:
            best_q = 0.0
    else:
        status = i
        clr = radius[i] - r_contact
        best_margin = best_q - clr * clr  # sign says contact; compared when radii equal
        for j in (i - 1, i + 1):
            if j < 0 or j > n - 1:
                continue
            qj, sj = _clamped_q(x0, x1, x2, p0, axis, length, j)
            clrj = radius[j] - r_contact
            if radius[j] == radius[best]:
                better = qj - clrj * clrj < best_margin
            else:
                better = math.sqrt(qj) - clrj < math.sqrt(best_q) - (radius[best] - r_contact)
            if better:
                best = j
                best_q = qj
                best_s = sj
                best_margin = qj - clrj * clrj
        status = best

    # Reported distance and normal from the explicit perpendicular w = v - s a
    # (no cancellation, unlike sqrt(v.v - s^2) near the axis).
    sc = best_s
    if status != OUTSIDE_CHAIN:
        if sc < 0.0:
            sc = 0.0
        elif sc > length[best]:
            sc = length[best]
    wx = x0 - p0[best, 0] - sc * axis[best, 0]
    wy = x1 - p0[best, 1] - sc * axis[best, 1]
    wz = x2 - p0[best, 2] - sc * axis[best, 2]
    d = math.sqrt(wx * wx + wy * wy + wz * wz)
    return status, d - (radius[best] - r_contact), wx, wy, wz, best_s, d


@njit(cache=True, inline="always")
def find_contact(x, r_contact, p0, axis, length, radius, hint, out):
    """Locate a contact point in the wellbore cylinder chain and measure its penetration.

    Parameters
    ----------
    x : ndarray, shape (3,)
        Contact point position, world frame (x north, y east, z TVD down), m.
    r_contact : float
        Contact (outer) radius of the string at this point, m.
    p0 : ndarray, shape (n, 3)
        Start point of each cylinder's centre line, m.
    axis : ndarray, shape (n, 3)
        Unit axis of each cylinder (pointing to increasing MD).
    length : ndarray, shape (n,)
        Cylinder lengths, m (> 0).
    radius : ndarray, shape (n,)
        Hole radius of each cylinder, m.
    hint : int
        Cylinder found at the previous call for this point (any value is
        accepted; it is clamped to [0, n-1]). The search is O(1) when the
        point moved by less than about one cylinder length.
    out : ndarray, shape (6,)
        Written: ``[delta_m, n_x, n_y, n_z, s_along_m, dist_from_centre_m]``:
        penetration (> 0 in contact, <= 0 otherwise: minus the remaining
        clearance), outward unit normal from the hole centre line towards the
        point (zeros if the point is exactly on the centre line), position
        along the returned cylinder's axis (outside [0, l] in a bend wedge),
        and the distance from the hole centre line.

    Returns
    -------
    int
        Index of the cylinder used (pass it as ``hint`` next time), or
        ``OUTSIDE_CHAIN`` (-1) if the point lies before the start of the first
        cylinder or beyond the end of the last one. In that case ``out`` is
        still filled as if the end cylinder were prolonged, so a caller may
        use it, but the chain should be built to extend beyond the bit.

    Notes
    -----
    The contact decision of each candidate uses squared distances only; one
    square root is taken for the cylinder finally used (to report delta and
    the distance, from the explicit perpendicular vector so that it is exact
    near the axis too), two more only if neighbouring cylinders have
    different radii. References: docs/model.md#contact; Liyanarachchi & Rideout (2024).
    """
    ic, delta, wx, wy, wz, s_along, d = locate(x[0], x[1], x[2], r_contact, p0, axis, length,
                                               radius, hint)
    out[OUT_DELTA] = delta
    out[OUT_S] = s_along
    out[OUT_DIST] = d
    unit_normal(wx, wy, wz, d, out)
    return ic


@njit(cache=True, inline="always")
def unit_normal(wx, wy, wz, d, out):
    """``out[OUT_NX:OUT_NZ + 1]`` = the unit normal w / d (zeros on the centre line, d = 0)."""
    if d > 0.0:
        inv = 1.0 / d
        out[OUT_NX] = wx * inv
        out[OUT_NY] = wy * inv
        out[OUT_NZ] = wz * inv
    else:
        out[OUT_NX] = 0.0
        out[OUT_NY] = 0.0
        out[OUT_NZ] = 0.0


@njit(cache=True, inline="always")
def normal_force(delta, delta_dot, k_c, c_c):
    """Penalty normal force magnitude of the wall on the string; never pulls.

    Parameters
    ----------
    delta : float
        Penetration, m (> 0 in contact).
    delta_dot : float
        Penetration rate, m/s (d delta / dt; > 0 when moving into the wall).
    k_c : float
        Contact stiffness, N/m.
    c_c : float
        Contact damping, N s/m.

    Returns
    -------
    float
        ``max(0, k_c delta + c_c delta_dot)`` if ``delta > 0`` else 0, in N.
        The force acts on the string along ``-n`` (towards the hole centre).
        The clamp at zero stops the dash-pot from pulling the string onto the
        wall while it separates (Hunt-Crossley style unilateral contact).
    """
    if delta <= 0.0:
        return 0.0
    f = k_c * delta + c_c * delta_dot
    if f < 0.0:
        return 0.0
    return f


@njit(cache=True, inline="always")
def wall_force(X, r_contact, body, chain, hint, law, f_other, out):
    """Wall contact plus friction force on one segment at one of its contact points.

    The string touches the wall at its surface point ``Y = X + r n`` (X on the
    segment's centre line, n the outward hole normal), so the slip velocity
    includes the surface speed ``r omega`` of a spinning pipe: friction torque,
    whirl, and rolling without slip (zero slip at Y, i.e. backward whirl) all
    come out of this one mechanism (docs/model.md#friction).

    Parameters
    ----------
    X : ndarray, shape (3,)
        Contact point on the segment's centre line (world frame), m.
    r_contact : float
        Contact radius at this point, m.
    body : tuple
        The segment, ``(xc, vc, omega, t_axis)``: centre of mass position (m) and
        velocity (m/s), angular velocity (rad/s) and unit axis (for the axial drag
        coefficient), all (3,) in the world frame.
    chain : tuple
        The hole's cylinder chain ``(p0, axis, length, radius)``, as in :func:`find_contact`.
    hint : int
        The search hint, as in :func:`find_contact`.
    law : tuple
        ``(k_c, c_c, fmodel, fp, dt)``: penalty stiffness (N/m) and damping (N s/m),
        the friction law id and its parameters
        (:mod:`drillfatigue.dynamics.contact.friction`), the integrator step (s).
    f_other : ndarray, shape (3,)
        Net other force on the segment at this point, N (stiction laws only; its
        component along n is removed here).
    out : tuple
        ``(info, force, moment)``, written. ``info`` (WALL_INFO_SIZE,): the columns
        ``WI_*`` of :mod:`layout`, ``find_contact``'s six values, the normal force N
        (N), the slip speed at Y (m/s), the slip velocity vector at Y (3, m/s), the
        tangential part of ``f_other`` (3, N; scratch) and the cylinder located (the
        next ``hint``; -1 beyond the chain's ends, where the end cylinder is
        prolonged: keep the previous hint then). ``force``, ``moment`` (3,): the wall
        force on the segment (normal plus friction), N, and its moment about ``xc``,
        N m (world frame); zero when not in contact. No allocation.

    Returns
    -------
    int
        A status code (:mod:`drillfatigue.dynamics.core.status`): ``OK`` or
        ``UNKNOWN_FRICTION``.
    """
    p0, axis, length, radius = chain
    ic = find_contact(X, r_contact, p0, axis, length, radius, hint, out[0])
    return located_wall_force(X, r_contact, ic, body, law, f_other, out)


@njit(cache=True, inline="always")
def located_wall_force(X, r_contact, ic, body, law, f_other, out):
    """:func:`wall_force` after the search: ``info[:6]`` (``out[0]``) holds what
    :func:`find_contact` wrote for this point and ``ic`` is the cylinder it returned.

    Fills the rest of ``info`` and ``force``/``moment`` exactly as :func:`wall_force`
    does (it is that function's second half). The wall loop locates every point first and
    calls this only for the points that penetrate (``info[WI_DELTA] > 0``): for the others
    the result is zero force, and the search alone is a third of the work.
    """
    xc, vc, omega, t_axis = body
    k_c, c_c, fmodel, fp, dt = law
    info, force, moment = out
    for k in range(3):
        force[k] = 0.0
        moment[k] = 0.0
    for k in range(6, WALL_INFO_SIZE):
        info[k] = 0.0
    info[WI_CYL] = ic
    # beyond the chain's ends (ic = -1) the end cylinder is prolonged, so the
    # bit drilling ahead of the last node still feels a wall
    if info[OUT_DELTA] <= 0.0:
        return OK
    nx = info[OUT_NX]
    ny = info[OUT_NY]
    nz = info[OUT_NZ]
    # lever arm from the centre of mass to the surface contact point Y = X + r n
    ax_ = X[0] + r_contact * nx - xc[0]
    ay_ = X[1] + r_contact * ny - xc[1]
    az_ = X[2] + r_contact * nz - xc[2]
    vx = vc[0] + omega[1] * az_ - omega[2] * ay_
    vy = vc[1] + omega[2] * ax_ - omega[0] * az_
    vz = vc[2] + omega[0] * ay_ - omega[1] * ax_
    vn = vx * nx + vy * ny + vz * nz  # penetration rate (wall at rest)
    N = normal_force(info[OUT_DELTA], vn, k_c, c_c)
    info[WI_N] = N
    if N <= 0.0:
        return OK
    vs = info[WI_VS:WI_VS + 3]
    vs[0] = vx - vn * nx
    vs[1] = vy - vn * ny
    vs[2] = vz - vn * nz
    info[WI_SLIP] = math.sqrt(vs[0] * vs[0] + vs[1] * vs[1] + vs[2] * vs[2])
    fo = info[WI_FO:WI_FO + 3]
    fon = f_other[0] * nx + f_other[1] * ny + f_other[2] * nz
    fo[0] = f_other[0] - fon * nx
    fo[1] = f_other[1] - fon * ny
    fo[2] = f_other[2] - fon * nz
    st = friction_force_split(fmodel, fp, vs, t_axis, N, fo, dt, force)
    if st != OK:
        return st
    force[0] -= N * nx
    force[1] -= N * ny
    force[2] -= N * nz
    moment[0] = ay_ * force[2] - az_ * force[1]
    moment[1] = az_ * force[0] - ax_ * force[2]
    moment[2] = ax_ * force[1] - ay_ * force[0]
    return OK


@njit(cache=True, inline="always")
def contact_point(seg, i, p):
    """Where contact point ``p`` of segment ``i`` sits: (offset along the axis from the
    centre, m, > 0 downhole; contact radius, m).

    Points 0 and 1 are the segment's lower and upper ends (tool joints or
    stabilizer blades, radius ``seg[i, S_RC]``), point 2 its middle (pipe body,
    ``seg[i, S_RB]``). A new kind of point (several per tool joint, a
    stabilizer mid-segment) is added here and counted in ``MAX_CONTACT_POINTS``.
    """
    h = seg[i, S_H]
    if p == 0:
        return h, seg[i, S_RC]
    if p == 1:
        return -h, seg[i, S_RC]
    return 0.0, seg[i, S_RB]


@njit(cache=True)
def deepest_point(off, g, npt):
    """The deepest point of a straight segment between its tested points in a bend.

    ``off[:npt]`` are the points' offsets along the segment's axis (m) and
    ``g[:npt]`` the offsets of the axis there from the wall (distance from the
    hole's centre line minus the hole radius, m; the point's penetration is
    g + its contact radius). The offset of a straight line from a circular arc
    is quadratic in the distance along it to high accuracy (its square is a
    polynomial in u; the root of it is a parabola to O((u^2 kappa)^2 / c) with the
    line within the clearance c of the arc), so the parabola through the point of
    largest g and its two neighbours along the axis (the two next ones on one
    side when it is an end point) locates the largest g between the points: its
    vertex u*, g*. Returns ``(k, u*, g*)`` with k the point of largest g, or
    k = -1 when there is no vertex to test: fewer than three points, a parabola
    that is not concave (a straight hole: a line's offset from a straight
    cylinder is convex, largest at an end), a vertex outside the intervals next
    to point k, or g* not above g[k]."""
    if npt < 3:
        return -1, 0.0, 0.0
    k = 0
    for j in range(1, npt):
        if g[j] > g[k]:
            k = j
    # neighbours along the axis: the nearest point below and above point k
    lo = -1
    hi = -1
    for j in range(npt):
        if off[j] < off[k] and (lo < 0 or off[j] > off[lo]):
            lo = j
        if off[j] > off[k] and (hi < 0 or off[j] < off[hi]):
            hi = j
    if lo >= 0 and hi >= 0:
        a, b, c = lo, k, hi
        u_lo = off[lo]
        u_hi = off[hi]
    elif hi >= 0:
        nxt = -1
        for j in range(npt):
            if off[j] > off[hi] and (nxt < 0 or off[j] < off[nxt]):
                nxt = j
        if nxt < 0:
            return -1, 0.0, 0.0
        a, b, c = k, hi, nxt
        u_lo = off[k]
        u_hi = off[hi]
    elif lo >= 0:
        nxt = -1
        for j in range(npt):
            if off[j] < off[lo] and (nxt < 0 or off[j] > off[nxt]):
                nxt = j
        if nxt < 0:
            return -1, 0.0, 0.0
        a, b, c = nxt, lo, k
        u_lo = off[lo]
        u_hi = off[k]
    else:
        return -1, 0.0, 0.0
    x0 = off[a]
    x1 = off[b]
    x2 = off[c]
    if x1 - x0 < 1e-9 or x2 - x1 < 1e-9:
        return -1, 0.0, 0.0
    d1 = (g[b] - g[a]) / (x1 - x0)
    d2 = (g[c] - g[b]) / (x2 - x1)
    cc = (d2 - d1) / (x2 - x0)
    if not cc < 0.0:
        return -1, 0.0, 0.0
    u = 0.5 * (x0 + x1) - 0.5 * d1 / cc
    if not (u_lo < u < u_hi):
        return -1, 0.0, 0.0
    gv = g[a] + d1 * (u - x0) + cc * (u - x0) * (u - x1)
    if not gv > g[k]:
        return -1, 0.0, 0.0
    return k, u, gv


# numpy's error model, as wall_contact that it is inlined into
@njit(cache=True, inline="always", error_model="numpy")
def _stiction_prepass(i, m, R, Mb, Mw, Fw, seg, tax, alin, alpha):
    """The stiction pre-pass of :func:`wall_contact`: the linear (``alin``, m/s^2) and
    angular (``alpha``, rad/s^2) acceleration segment ``i`` would have from its non-wall
    loads alone.

    Karnopp pre-pass. Karnopp needs the "other" tangential force at a contact
    point. In this explicit scheme it is estimated first: the acceleration the
    contact point would have from all non-wall forces and moments on the
    segment (gravity, mud, joints, boundaries: this kernel runs after them),
    times the share of the segment's mass carried by the point (m / points).
    Friction is then computed point by point against that estimate.
    """
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


# numpy's error model, as wall_contact that it is inlined into
@njit(cache=True, inline="always", error_model="numpy")
def _point_of(i, pt, npi, own, seg, cp, hint, tbase, offs, gs, dpen):
    """Point ``pt`` of segment ``i`` in :func:`wall_contact`: whether it is tested, its
    offset along the axis (m), its contact radius (m) and its hint's index.

    ``pt == npi`` is the deepest point (:func:`deepest_point`), tested with the body
    radius less the tested points' largest penetration ``dpen``: its force grows from
    zero as the vertex leaves a tested point, and is the whole penalty force where no
    tested point touches. A table point not located yet starts from the segment's
    first hint.

    Contact points from the string. With ``cpar[P_CPTAB]`` set, every segment
    below the top tests its own points ``p.cp[i, :p.cp_n[i]]`` (tool joints,
    blades, centre upsets and the extra points of
    :func:`drillfatigue.string.contacts.contact_points`) instead of its ends;
    the growing top segment keeps the ``cpar[P_NPTS]`` points of
    :func:`contact_point`. Each point adds its force and that force's moment
    about the centre; friction acts at that point's radius. A point not yet
    located (hint -1, e.g. on a piece just split off the top) starts its search
    from the segment's first hint.

    Deepest point (``cpar[P_DEEP]``, ``contact.deepest_point``). A segment with
    three or more points then also tests, after them, the vertex of
    :func:`deepest_point` (the point of its axis furthest out towards the wall
    between its points, in a bend) with the body radius less the tested points'
    largest penetration delta_max >= 0: the force there is the whole penalty
    force where no tested point touches and grows from zero as the vertex
    leaves a tested point that touches. It has the friction, damping and
    Karnopp share of any point and the hint of the outermost point (which it
    does not update).
    """
    if pt == npi:
        kd, off, gd = deepest_point(offs, gs, npi)
        if kd < 0 or gd + seg[i, S_RB] <= dpen:
            return False, 0.0, 0.0, 0
        rc = seg[i, S_RB] - dpen
        if own:
            ih = tbase + MAX_TABLE_POINTS * i + kd
        else:
            ih = MAX_CONTACT_POINTS * i + kd
    elif own:
        off = cp[i, pt, 0]
        rc = cp[i, pt, 1]
        ih = tbase + MAX_TABLE_POINTS * i + pt
        if hint[ih] < 0:
            hint[ih] = hint[MAX_CONTACT_POINTS * i]
    else:
        off, rc = contact_point(seg, i, pt)
        ih = MAX_CONTACT_POINTS * i + pt
    return True, off, rc, ih


# numpy's error model, as wall_contact that it is inlined into
@njit(cache=True, inline="always", error_model="numpy")
def _add_point_load(i, X, rc, delta, state, out, m_cap, karn, kc, dt, ch):
    """A penetrating point's force in :func:`wall_contact`: the slip cap of the smooth
    laws, the penalty energy and dissipated power (``ch``), and the force and its moment
    added to segment ``i``. ``state``: ``(x, v, wW, Fw, Mw)``; ``out``: the point's
    ``(info, force, moment)`` from :func:`located_wall_force`. Returns its normal force (N).

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
    and the step limit of :func:`drillfatigue.dynamics.step.pack.stable_step`.
    """
    x, v, wW, Fw, Mw = state
    info, force, moment = out
    nrm = info[WI_N]
    nx = info[WI_NX]
    ny = info[WI_NX + 1]
    nz = info[WI_NX + 2]
    # velocity of the surface contact point Y = X + r n
    ax_ = X[0] + rc * nx - x[i, 0]
    ay_ = X[1] + rc * ny - x[i, 1]
    az_ = X[2] + rc * nz - x[i, 2]
    vy0 = v[i, 0] + wW[i, 1] * az_ - wW[i, 2] * ay_
    vy1 = v[i, 1] + wW[i, 2] * ax_ - wW[i, 0] * az_
    vy2 = v[i, 2] + wW[i, 0] * ay_ - wW[i, 1] * ax_
    vn = vy0 * nx + vy1 * ny + vy2 * nz
    if not karn and nrm > 0.0:
        # slip cap (see above): |F_t| <= m_eff |v_slip| / dt
        ft0 = force[0] + nrm * nx
        ft1 = force[1] + nrm * ny
        ft2 = force[2] + nrm * nz
        ftm = math.sqrt(ft0 * ft0 + ft1 * ft1 + ft2 * ft2)
        cap = m_cap * info[WI_SLIP] / dt
        if ftm > cap:
            sf = cap / ftm
            force[0] = sf * ft0 - nrm * nx
            force[1] = sf * ft1 - nrm * ny
            force[2] = sf * ft2 - nrm * nz
            moment[0] = ay_ * force[2] - az_ * force[1]
            moment[1] = az_ * force[0] - ax_ * force[2]
            moment[2] = ax_ * force[1] - ay_ * force[0]
    ch[H_PE] += 0.5 * kc * delta * delta
    ch[H_PDISS] += -(force[0] * vy0 + force[1] * vy1 + force[2] * vy2) - kc * delta * vn
    for k in range(3):
        Fw[i, k] += force[k]
        Mw[i, k] += moment[k]
    return nrm


# without numba's reference counting: the rows handed to the inlined point kernels are
# views, each an atomic increment and decrement with it; the loop allocates nothing
# (:func:`drillfatigue.dynamics.core.joints.joint_forces`); divisions with numpy's error model,
# without the zero-divisor test (:func:`drillfatigue.dynamics.step.integrator.half_kicks`)
@njit(cache=True, _nrt=False, error_model="numpy")  # type: ignore[call-overload]  # _nrt: not in numba's stubs
def wall_contact(t, n, s, p, wk):
    """Wall contact and friction on every active segment, with contact and whirl statistics.

    For each segment and each of its ``cpar[P_NPTS]`` contact points
    (:func:`contact_point`) the penalty normal force and the friction of the
    chosen law (:func:`wall_force`; the search first, :func:`locate` with its results
    in locals, the force kernel :func:`located_wall_force` only for a point that
    penetrates) are added to
    ``s.Fw`` / ``s.Mw``; the
    penalty energy and the dissipated power go to ``wk.ch[H_PE]`` /
    ``wk.ch[H_PDISS]``; ``s.cst`` gets the segment's contact statistics and,
    after ``bp[B_TWIN]``, its whirl angles (:mod:`events`); ``wk.ch`` the count
    of segments in contact, the largest normal force and the active count.
    Reads ``s.x, s.v, s.hint`` (updated), ``wk.R, wk.wW``, ``p.seg, p.wall,
    p.cpar, p.bp, p.cp_n, p.cp``. Returns a status code.

    The points: :func:`_point_of` (from the string's table, or the segment's ends and
    middle; the deepest point); the stiction pre-pass: :func:`_stiction_prepass`; the
    slip cap of the smooth laws: :func:`_add_point_load`.
    """
    ch = wk.ch
    cpar = p.cpar
    ncon = 0
    fcmax = 0.0
    if cpar[P_ON] != 0.0:
        dt = p.dt
        x = s.x
        v = s.v
        Fw = s.Fw
        Mw = s.Mw
        Mb = s.Mb
        hint = s.hint
        cst = s.cst
        seg = p.seg
        wall = p.wall
        R = wk.R
        wW = wk.wW
        kc = cpar[P_KC]
        fmodel = int(cpar[P_FMODEL])
        npts = int(cpar[P_NPTS])
        fp = cpar[P_FP:P_FP + N_FRICTION_PARAMS]
        p0 = wall[:, 0:3]
        axc = wall[:, 3:6]
        lnc = wall[:, 6]
        rad = wall[:, 7]
        vec = wk.vec
        info = vec[V_W_INFO]
        X = vec[V_W_X]
        tax = vec[V_W_AX]
        fo = vec[V_W_FO]
        force = vec[V_W_F]
        moment = vec[V_W_M]
        alin = vec[V_W_ALIN]
        alpha = vec[V_W_ALPHA]
        whirl = vec[V_W_WHIRL]
        t_win = p.bp[B_TWIN]
        md_bit = s.sc[C_MDROCK]
        karn = has_stiction(fmodel)
        table = cpar[P_CPTAB] != 0.0
        cp_n = p.cp_n
        cp = p.cp
        tbase = MAX_CONTACT_POINTS * x.shape[0]
        deep = cpar.shape[0] > P_DEEP and cpar[P_DEEP] != 0.0
        offs = vec[V_W_OFF]
        gs = vec[V_W_G]
        for i in range(n):
            m = seg[i, S_M]
            own = table and i < n - 1
            npi = int(cp_n[i]) if own else npts
            # the segment's deepest point between its tested points, after them
            n_test = npi + 1 if deep and npi >= 3 else npi
            dpen = 0.0
            for k in range(3):
                tax[k] = R[i, k, 2]
                fo[k] = 0.0
            if karn:
                _stiction_prepass(i, m, R, Mb, Mw, Fw, seg, tax, alin, alpha)
            nsum = 0.0
            dmax = 0.0
            m_cap = m / (3.0 * npi)
            for pt in range(n_test):
                tested, off, rc, ih = _point_of(i, pt, npi, own, seg, cp, hint, tbase, offs, gs,
                                                dpen)
                if not tested:
                    continue
                for k in range(3):
                    X[k] = x[i, k] + off * tax[k]
                if karn:
                    share = m / npi
                    fo[0] = share * (alin[0] + alpha[1] * off * tax[2] - alpha[2] * off * tax[1])
                    fo[1] = share * (alin[1] + alpha[2] * off * tax[0] - alpha[0] * off * tax[2])
                    fo[2] = share * (alin[2] + alpha[0] * off * tax[1] - alpha[1] * off * tax[0])
                # locate the point; the force kernel only where it penetrates (a point
                # off the wall has zero force, and its search result is all the loop
                # reads: the cylinder, the penetration and the distance)
                ic, delta, wx, wy, wz, s_along, d = locate(X[0], X[1], X[2], rc, p0, axc, lnc,
                                                           rad, hint[ih])
                if delta > 0.0:
                    # find_contact's output, for the force kernel
                    info[WI_DELTA] = delta
                    info[OUT_S] = s_along
                    info[WI_DIST] = d
                    unit_normal(wx, wy, wz, d, info)
                    st = located_wall_force(X, rc, ic, (x[i], v[i], wW[i], tax),
                                            (kc, seg[i, S_CC], fmodel, fp, dt), fo,
                                            (info, force, moment))
                    if st != OK:
                        return st
                if ic >= 0 and pt < npi:
                    hint[ih] = ic
                    if own and pt == 0:
                        # the lower end: the hint whirl tracking and growth read
                        hint[MAX_CONTACT_POINTS * i] = ic
                if pt < npi and n_test > npi:
                    offs[pt] = off
                    gs[pt] = delta - rc
                    if delta > dpen:
                        dpen = delta
                if d > dmax:
                    dmax = d
                if delta > 0.0:
                    nsum += _add_point_load(i, X, rc, delta, (x, v, wW, Fw, Mw), (info, force, moment),
                                            m_cap, karn, kc, dt, ch)
            if record_contact(i, t, md_bit, nsum, dmax, dt, cst):
                ncon += 1
                if nsum > fcmax:
                    fcmax = nsum
            if t >= t_win:
                track_whirl(i, x[i], wW[i], seg[i, S_RC], wall, hint[MAX_CONTACT_POINTS * i], dt,
                            cst, whirl)
    ch[H_NCON] = ncon
    ch[H_FCMAX] = fcmax
    ch[H_NSEG] = n
    return OK


def stable_dt(k_c: float, m_min: float, zeta: float = 0.0) -> float:
    """Critical explicit step for a mass ``m_min`` on the contact spring ``k_c``.

    Parameters
    ----------
    k_c : float
        Contact stiffness, N/m (> 0).
    m_min : float
        Smallest mass carried by one contact point, kg (> 0).
    zeta : float, optional
        Damping ratio of the contact dash-pot (>= 0).

    Returns
    -------
    float
        ``2 (sqrt(1 + zeta**2) - zeta) / omega`` with ``omega = sqrt(k_c/m_min)``,
        in s: the stability limit of the central-difference / symplectic Euler
        scheme for a damped linear oscillator (e.g. Belytschko, Liu & Moran,
        Nonlinear Finite Elements, section 6.3). Use a safety factor (~0.5)
        below it; the integrator takes the minimum over all elements.
    """
    if not (k_c > 0.0 and m_min > 0.0 and zeta >= 0.0):
        raise ValueError(f"stable_dt needs k_c > 0, m_min > 0, zeta >= 0; got {k_c}, {m_min}, {zeta}")
    omega = math.sqrt(k_c / m_min)
    return 2.0 * (math.sqrt(1.0 + zeta * zeta) - zeta) / omega


def damping_from_ratio(k_c: float, m_eff: float, zeta: float) -> float:
    """Contact dash-pot ``c_c = 2 zeta sqrt(k_c m_eff)`` in N s/m."""
    return 2.0 * zeta * math.sqrt(k_c * m_eff)


def contact_damping(cfg: ContactConfig, m_eff: float) -> float:
    """Dash-pot ``c_c`` (N s/m) from a ``ContactConfig``: the fixed value if given,
    else ``2 zeta sqrt(k_c m_eff)`` for the mass ``m_eff`` (kg) carried by the point."""
    if cfg.c_c_N_s_per_m is not None:
        return float(cfg.c_c_N_s_per_m)
    return damping_from_ratio(cfg.k_c_N_per_m, m_eff, cfg.damping_ratio)


def build_cylinder_chain(
    pos_m: np.ndarray, hole_radius_m: float | np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Build the cylinder chain from centre-line points (e.g. a resampled survey).

    Parameters
    ----------
    pos_m : ndarray, shape (n + 1, 3)
        Centre-line points in order of increasing MD, world frame, m.
    hole_radius_m : float or ndarray, shape (n,)
        Hole radius of each cylinder, m.

    Returns
    -------
    p0, axis, length, radius : ndarrays, shapes (n, 3), (n, 3), (n,), (n,)
        Arguments of :func:`find_contact`. Zero-length intervals are dropped.
    """
    pos = np.ascontiguousarray(pos_m, dtype=np.float64)
    if pos.ndim != 2 or pos.shape[1] != 3 or pos.shape[0] < 2:
        raise ValueError(f"pos_m must have shape (n+1, 3) with n >= 1, got {pos.shape}")
    d = np.diff(pos, axis=0)
    length = np.linalg.norm(d, axis=1)
    rad = np.broadcast_to(np.asarray(hole_radius_m, dtype=np.float64), length.shape).copy()
    keep = length > 1e-12
    if not keep.any():
        raise ValueError("cylinder chain has zero total length")
    p0 = np.ascontiguousarray(pos[:-1][keep])
    axis = np.ascontiguousarray(d[keep] / length[keep, None])
    return p0, axis, np.ascontiguousarray(length[keep]), np.ascontiguousarray(rad[keep])
