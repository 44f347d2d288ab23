"""Bending between supports: continuous beam-column on rigid supports (kernels).

A rigid segment carries no bending inside itself, yet the real pipe sags
between the points where it touches the wall (tool joints, stabilizer blades,
contact points along collars) and, rotating, sees that moment alternate once
per revolution (docs/bending.md). These kernels give the moments of a
chain of spans between supports under a uniform transverse load per span.

Beam solution
-------------
Each span i (length ``L``, bending stiffness ``EI``, effective axial force
``T``, tension > 0) carries a uniform transverse load ``q`` (N/m, a 2-vector
in the pipe cross-section, each component solved alone: the problem is
linear). The supports are rigid; level in :func:`support_moments`, at
different heights in :func:`support_moments_settled` (settlement terms: the
chord rotations of the spans; docs/bending.md, "What the chain carries and what
the span adds", for how the recorder splits the moment between the rigid
chain's joints and this solution). Slope continuity over every interior
support gives the three-moment equation of Clapeyron, generalised to
beam-columns (Timoshenko & Gere, *Theory of Elastic Stability*, 2nd ed. 1961,
section 1.13):

    L_{i-1}/(6 EI_{i-1}) f2_{i-1} M_{i-1}
      + [L_{i-1}/(3 EI_{i-1}) f1_{i-1} + L_i/(3 EI_i) f1_i] M_i
      + L_i/(6 EI_i) f2_i M_{i+1}
    = -q_{i-1} L_{i-1}^3/(24 EI_{i-1}) f3_{i-1} - q_i L_i^3/(24 EI_i) f3_i

with M the bending moment over the supports (sagging positive, i.e. the
fibre on the side the load points to in tension) and the axial-force factors
of the simply supported span, s = T L^2/EI, v = sqrt(|s|):

* tension: f1 = 3 (v/tanh v - 1)/v^2, f2 = 6 (1 - v/sinh v)/v^2,
  f3 = 24 (v/2 - tanh(v/2))/v^3;
* compression: f1 = 3 (1 - v/tan v)/v^2, f2 = 6 (v/sin v - 1)/v^2,
  f3 = 24 (tan(v/2) - v/2)/v^3;
* all three tend to 1 without axial force (power series in s through s^4
  below |s| = 0.02, where the closed forms lose digits to cancellation),
  giving the classical three-moment equation; on equal spans far from the
  ends the support moment is -q L^2/12 and the mid-span moment q L^2/24 (the
  clamped-clamped span).

Chain ends are pinned (M = 0) or clamped (zero slope). Inside a span the
moment is the beam-column solution with those end moments:
M(x) = M_a sinh(k(L-x))/sinh(kL) + M_b sinh(kx)/sinh(kL)
+ (q/k^2)[1 - cosh(k(x - L/2))/cosh(kL/2)], k = sqrt(T/EI) (trigonometric
in compression; x (L-x) q/2 plus the linear end-moment line without axial
force).

Where it stops being valid
--------------------------
* A span that touches the wall between its supports: the mid-span deflection
  (:func:`midspan_deflection`) exceeds the radial clearance. The touching
  point is then a support: the caller adds it and solves again.
* A span in compression at or beyond the Euler load of the pinned span
  (v >= pi): the factors blow up; the kernel returns ``STATUS_SPAN_BUCKLED``.
  (A buckled span lies on the wall: more supports, as above.)
* Small deflections, linear elastic, Euler-Bernoulli (span much longer than
  the diameter); the load is uniform over each span; the supports do not
  move under this load (their heights are given).
* A segment in line contact along its length (the whole body on the wall)
  has no span: give it none (no correction).

Moment vectors in the cross-section
-----------------------------------
For a load q = (q_x, q_y) in some cross-section frame, the bending moment
vector in the same frame is (M_x, M_y) = (M_s[q_y], -M_s[q_x]) with M_s the
sagging-positive scalar moment of that load component. This is the sign
convention of ``loads.parquet`` and :mod:`drillfatigue.fatigue.stress`
(M_x > 0 stretches the +y fibre, M_y > 0 the -x fibre): over a support of a
pipe lying on the low side (load -y) M_x > 0, the top fibre in tension.
Given q in a frame that does not turn with the pipe, :func:`to_pipe_frame`
resolves the moments in the pipe-fixed frame, where they alternate once per
revolution.

Kernels take float64 arrays in SI, write into ``out`` arrays and return a
status code of the package's one enumeration, :mod:`drillfatigue.status`
(``STATUS_OK`` = ``OK`` = 0, ``STATUS_BAD_SPAN`` = ``BAD_SPAN``,
``STATUS_SPAN_BUCKLED`` = ``SPAN_BUCKLED``, ``STATUS_SINGULAR`` = ``SINGULAR``;
the local names are kept for the callers of this module).

References
----------
Timoshenko, S. P. & Gere, J. M., *Theory of Elastic Stability*, 2nd ed.,
McGraw-Hill 1961, sections 1.11-1.13 (beam-columns, continuous beams with
axial loads); Roark's *Formulas for Stress and Strain*, 8th ed., table 8.5
(beam-column end moments); docs/bending.md.
"""

from __future__ import annotations

import math
from collections import namedtuple

import numpy as np
from numba import njit

from drillfatigue.status import BAD_SPAN as STATUS_BAD_SPAN
from drillfatigue.status import OK as STATUS_OK
from drillfatigue.status import SINGULAR as STATUS_SINGULAR
from drillfatigue.status import SPAN_BUCKLED as STATUS_SPAN_BUCKLED

END_PINNED = 0
END_CLAMPED = 1

#: |s| = |T| L^2/EI below which the axial-force factors come from their power
#: series through s^4 (truncation below 1e-13 there; above it the closed forms
#: lose less than 1e-12 to cancellation)
SERIES_S = 0.02
#: |s| below which the moment shape inside a span is the axial-force-free one
#: (its error is O(s) relative, 1e-8; the closed form's cancellation error is
#: 1e-16/s relative, 1e-8 at the switch)
SHAPE_SERIES_S = 1e-8
#: compression v = L sqrt(|T|/EI) at which a pinned span is taken as buckled
BUCKLED_V = 0.999 * math.pi


@njit(cache=True)
def axial_factors(s):
    """(f1, f2, f3) of a simply supported span with s = T L^2/EI (tension > 0).

    f1: near-end rotation under an end moment, f2: far-end rotation under an
    end moment, f3: end rotation under a uniform load, each over its value
    without axial force. NaN for compression at or beyond ``BUCKLED_V``.
    """
    if abs(s) < SERIES_S:
        f1 = 1.0 + s * (-1.0 / 15.0 + s * (2.0 / 315.0 + s * (-1.0 / 1575.0
                                                              + s * 2.0 / 31185.0)))
        f2 = 1.0 + s * (-7.0 / 60.0 + s * (31.0 / 2520.0 + s * (-127.0 / 100800.0
                                                                + s * 73.0 / 570240.0)))
        f3 = 1.0 + s * (-1.0 / 10.0 + s * (17.0 / 1680.0 + s * (-31.0 / 30240.0
                                                                + s * 691.0 / 6652800.0)))
        return (f1, f2, f3)
    v = math.sqrt(abs(s))
    if s > 0.0:
        e = math.exp(-v)
        e2 = e * e
        coth = (1.0 + e2) / (1.0 - e2)
        v_over_sinh = 2.0 * v * e / (1.0 - e2)
        th = (1.0 - e) / (1.0 + e)  # tanh(v/2)
        return (3.0 * (v * coth - 1.0) / (v * v),
                6.0 * (1.0 - v_over_sinh) / (v * v),
                24.0 * (0.5 * v - th) / (v * v * v))
    if v >= BUCKLED_V:
        return (math.nan, math.nan, math.nan)
    return (3.0 * (1.0 - v / math.tan(v)) / (v * v),
            6.0 * (v / math.sin(v) - 1.0) / (v * v),
            24.0 * (math.tan(0.5 * v) - 0.5 * v) / (v * v * v))


@njit(cache=True)
def support_moments(span_m, ei_Nm2, axial_N, q_N_per_m, end_left, end_right, work, out_M):
    """Bending moments over the supports of a continuous beam-column on level supports.

    :func:`support_moments_settled` with every support offset zero (the same
    floating-point operations: the settlement terms are not formed).

    Parameters
    ----------
    span_m : ndarray, shape (n_span,)
        Span lengths between consecutive supports, m (> 0).
    ei_Nm2 : ndarray, shape (n_span,)
        Bending stiffness of each span, N m^2 (> 0).
    axial_N : ndarray, shape (n_span,)
        Effective axial force of each span, N, tension > 0.
    q_N_per_m : ndarray, shape (n_span, 2)
        Uniform transverse load of each span in a cross-section frame, N/m.
    end_left, end_right : int
        ``END_PINNED`` (zero moment) or ``END_CLAMPED`` (zero slope).
    work : ndarray, shape (n_span + 1, 6)
        Scratch.
    out_M : ndarray, shape (n_span + 1, 2)
        Moment vectors (M_x, M_y) over each support in the frame of ``q``
        (module docstring convention), N m.

    Returns
    -------
    int
        ``STATUS_OK``, ``STATUS_BAD_SPAN`` (a span or EI <= 0 or not finite),
        ``STATUS_SPAN_BUCKLED`` or ``STATUS_SINGULAR``.
    """
    return _support_moments(span_m, ei_Nm2, axial_N, q_N_per_m, out_M, False, end_left,
                            end_right, work, out_M)


@njit(cache=True)
def support_moments_settled(span_m, ei_Nm2, axial_N, q_N_per_m, d_m, end_left, end_right, work,
                            out_M):
    """Bending moments over the supports of a continuous beam-column whose supports
    stand at different heights.

    The three-moment equation of the module docstring with the settlement terms
    (Timoshenko & Gere 1961, section 1.13; without axial force Timoshenko,
    *Strength of Materials*, part I, 3rd ed. 1955, art. 55): slope continuity
    over support i adds the difference of the chord rotations of its two
    spans,

        ... = -q_{i-1} L_{i-1}^3/(24 EI_{i-1}) f3_{i-1} - q_i L_i^3/(24 EI_i) f3_i
              + psi_{i-1} - psi_i,   psi_k = (d_{k+1} - d_k) / L_k,

    d the support's offset along the load component (towards the side the load
    pushes the span). The chord rotation is a rigid rotation of the span:
    inside the span the beam-column equation EI w'''' - T w'' = q holds for
    the deflection from the chord as it does on level supports, so the chord
    terms carry no axial-force factor; the axial force enters through the
    factors f1, f2 of the end moments they set, and T times the chord's kink
    over a support is a force that support takes. On equal spans without
    axial force, times 6 EI / L, the right-hand side is the familiar
    6 EI (d_{i-1} - 2 d_i + d_{i+1}) / L^2. A clamped end holds zero slope in
    the frame of ``d`` (psi_{-1} = psi_n = 0). Offsets on a straight line
    (supports moved or turned rigidly) give no moment; zero offsets give
    :func:`support_moments` bit for bit. Inside a span the moment follows from
    the support moments as on level supports (:func:`moments_at`).

    Parameters
    ----------
    span_m, ei_Nm2, axial_N, q_N_per_m, end_left, end_right, work, out_M
        As :func:`support_moments`.
    d_m : ndarray, shape (n_span + 1, 2)
        Offset of each support, m, in the frame of ``q`` (component k along the
        load component k).

    Returns
    -------
    int
        As :func:`support_moments`.
    """
    return _support_moments(span_m, ei_Nm2, axial_N, q_N_per_m, d_m, True, end_left, end_right,
                            work, out_M)


@njit(cache=True)
def _support_moments(span_m, ei_Nm2, axial_N, q_N_per_m, d_m, settled, end_left, end_right,
                     work, out_M):
    """Bending moments over the supports of a continuous beam-column (``settled``: with
    the support offsets ``d_m``, :func:`support_moments_settled`); arguments and status
    codes as :func:`support_moments`.

    ``q_N_per_m`` may carry more than two load components (k columns; ``d_m`` and
    ``out_M`` as many, ``work`` 4 + k columns): the first two give the moment vector
    as for two, each further component c its sagging scalar negated in ``out_M[:, c]``
    (the M_y of a load along the first axis). Every component is solved with the same
    floating-point operations as alone."""
    n = span_m.shape[0]
    out_M[:, :] = 0.0
    if n == 0:
        return STATUS_OK
    st = _sagging_moments(span_m, ei_Nm2, axial_N, q_N_per_m, d_m, settled, end_left, end_right,
                          work)
    if st != STATUS_OK:
        return st
    # the load components: M_s of q_y gives M_x, M_s of q_x gives -M_y
    for i in range(n + 1):
        out_M[i, 0] = work[i, 5]
        out_M[i, 1] = -work[i, 4]
        for c in range(2, q_N_per_m.shape[1]):
            out_M[i, c] = -work[i, 4 + c]
    return STATUS_OK


@njit(cache=True)
def _sagging_moments(span_m, ei_Nm2, axial_N, q_N_per_m, d_m, settled, end_left, end_right,
                     work):
    """Sagging scalar moments over the supports of each load component ``q_N_per_m[:, c]``
    (offsets ``d_m[:, c]`` when ``settled``) into ``work[:, 4 + c]``; status as
    :func:`support_moments`. ``work`` (n_span + 1, 4 + k): columns 0-2 the sub-diagonal,
    diagonal and super-diagonal, 3 the Thomas algorithm's scratch, 4.. the right-hand
    sides, each solved alone (the same operations whatever the other columns)."""
    n = span_m.shape[0]
    ns = n + 1
    k = q_N_per_m.shape[1]
    for i in range(ns):
        for c in range(4 + k):
            work[i, c] = 0.0
    for i in range(n):
        L = span_m[i]
        EI = ei_Nm2[i]
        if not (L > 0.0 and EI > 0.0 and math.isfinite(L) and math.isfinite(EI)):
            return STATUS_BAD_SPAN
        f1, f2, f3 = axial_factors(axial_N[i] * L * L / EI)
        if math.isnan(f1):
            return STATUS_SPAN_BUCKLED
        near = L / (3.0 * EI) * f1
        far = L / (6.0 * EI) * f2
        load = L * L * L / (24.0 * EI) * f3
        # slope continuity at support i (span i is on its right) and i+1 (left)
        work[i, 1] += near
        work[i, 2] += far
        work[i + 1, 0] += far
        work[i + 1, 1] += near
        for c in range(k):
            work[i, 4 + c] -= q_N_per_m[i, c] * load
            work[i + 1, 4 + c] -= q_N_per_m[i, c] * load
        if settled:
            # chord rotation of span i: - at its left support, + at its right one
            for c in range(k):
                psi = (d_m[i + 1, c] - d_m[i, c]) / L
                work[i, 4 + c] -= psi
                work[i + 1, 4 + c] += psi
    if end_left == END_PINNED:
        work[0, 1] = 1.0
        work[0, 2] = 0.0
        for c in range(k):
            work[0, 4 + c] = 0.0
    if end_right == END_PINNED:
        work[ns - 1, 0] = 0.0
        work[ns - 1, 1] = 1.0
        for c in range(k):
            work[ns - 1, 4 + c] = 0.0
    # Thomas algorithm, every right-hand side at once
    b = work[0, 1]
    if b == 0.0:
        return STATUS_SINGULAR
    work[0, 3] = work[0, 2] / b
    for c in range(k):
        work[0, 4 + c] /= b
    for i in range(1, ns):
        den = work[i, 1] - work[i, 0] * work[i - 1, 3]
        if den == 0.0 or not math.isfinite(den):
            return STATUS_SINGULAR
        work[i, 3] = work[i, 2] / den
        for c in range(k):
            work[i, 4 + c] = (work[i, 4 + c] - work[i, 0] * work[i - 1, 4 + c]) / den
    for i in range(ns - 2, -1, -1):
        for c in range(k):
            work[i, 4 + c] -= work[i, 3] * work[i + 1, 4 + c]
    return STATUS_OK


@njit(cache=True)
def _span_shape(s, L, x):
    """Weights (g_a, g_b, h) of M(x) = g_a M_a + g_b M_b + h q in a span with
    s = T L^2/EI (module docstring), x in [0, L]."""
    if abs(s) < SHAPE_SERIES_S:
        return 1.0 - x / L, x / L, 0.5 * x * (L - x)
    v = math.sqrt(abs(s))
    k = v / L
    xi = x - 0.5 * L
    if s > 0.0:
        # exponentials of non-positive arguments only (no overflow for stiff spans)
        den = 1.0 - math.exp(-2.0 * v)
        ga = math.exp(-k * x) * (1.0 - math.exp(-2.0 * k * (L - x))) / den
        gb = math.exp(-k * (L - x)) * (1.0 - math.exp(-2.0 * k * x)) / den
        a = abs(xi)
        ratio = math.exp(k * (a - 0.5 * L)) * (1.0 + math.exp(-2.0 * k * a)) \
            / (1.0 + math.exp(-v))
        return ga, gb, (1.0 - ratio) / (k * k)
    sv = math.sin(v)
    return (math.sin(k * (L - x)) / sv, math.sin(k * x) / sv,
            (math.cos(k * xi) / math.cos(0.5 * v) - 1.0) / (k * k))


@njit(cache=True)
def moments_at(span_m, ei_Nm2, axial_N, q_N_per_m, M_support, read_span, read_x_m, out_M):
    """Bending moment vectors at read points inside the spans.

    Parameters
    ----------
    span_m, ei_Nm2, axial_N, q_N_per_m
        As :func:`support_moments`.
    M_support : ndarray, shape (n_span + 1, 2)
        Its result.
    read_span : ndarray of int64, shape (n_read,)
        Span of each read point.
    read_x_m : ndarray, shape (n_read,)
        Distance of each read point from the span's first support, m,
        0 <= x <= L.
    out_M : ndarray, shape (n_read, 2)
        (M_x, M_y), N m, in the frame of ``q``.

    Returns
    -------
    int
        ``STATUS_OK`` or ``STATUS_BAD_SPAN`` (span index or x out of range).
    """
    n = span_m.shape[0]
    for r in range(read_span.shape[0]):
        i = read_span[r]
        if i < 0 or i >= n:
            return STATUS_BAD_SPAN
        L = span_m[i]
        x = read_x_m[r]
        if not (x >= 0.0 and x <= L):
            return STATUS_BAD_SPAN
        ga, gb, h = _span_shape(axial_N[i] * L * L / ei_Nm2[i], L, x)
        # sagging scalar of the q_y component is M_x; of q_x it is -M_y
        out_M[r, 0] = ga * M_support[i, 0] + gb * M_support[i + 1, 0] + h * q_N_per_m[i, 1]
        out_M[r, 1] = ga * M_support[i, 1] + gb * M_support[i + 1, 1] - h * q_N_per_m[i, 0]
    return STATUS_OK


@njit(cache=True)
def midspan_deflection(span_m, ei_Nm2, axial_N, q_N_per_m, M_support, out_m):
    """Mid-span deflection magnitude of each span, m (for the wall check).

    Without axial force: |5 q L^4/(384 EI) + (M_a + M_b) L^2/(16 EI)| per load
    component (sagging moments positive), combined as a vector. Tension only
    lowers it, so the axial-free value is kept as a bound; in compression it is
    amplified by 1/(1 - |T|/P_E), P_E = pi^2 EI/L^2 (the standard beam-column
    amplification, within a few percent below 0.8 P_E).

    Parameters
    ----------
    out_m : ndarray, shape (n_span,)

    Returns
    -------
    int
        ``STATUS_OK`` or ``STATUS_SPAN_BUCKLED``.
    """
    for i in range(span_m.shape[0]):
        L = span_m[i]
        EI = ei_Nm2[i]
        c_q = 5.0 * L ** 4 / (384.0 * EI)
        c_m = L * L / (16.0 * EI)
        # sagging scalars: q_y with M_x, q_x with -M_y
        dy = c_q * q_N_per_m[i, 1] + c_m * (M_support[i, 0] + M_support[i + 1, 0])
        dx = c_q * q_N_per_m[i, 0] - c_m * (M_support[i, 1] + M_support[i + 1, 1])
        amp = 1.0
        if axial_N[i] < 0.0:
            ratio = -axial_N[i] * L * L / (math.pi * math.pi * EI)
            if ratio >= BUCKLED_V * BUCKLED_V / (math.pi * math.pi):
                return STATUS_SPAN_BUCKLED
            amp = 1.0 / (1.0 - ratio)
        out_m[i] = amp * math.sqrt(dx * dx + dy * dy)
    return STATUS_OK


@njit(cache=True)
def midspan_offset(span_m, ei_Nm2, axial_N, q_N_per_m, M_support, out_m):
    """Mid-span deflection of each span from its chord, as a vector in the frame of
    ``q``, m (where the pipe's axis is at mid span: the chord's middle plus this).

    The components of :func:`midspan_deflection` with their signs: per load
    component 5 q L^4/(384 EI) + (M_a + M_b) L^2/(16 EI) (sagging moments
    positive), towards the side the load component points to, amplified by
    1/(1 - |T|/P_E) in compression and taken without axial force in tension
    (an upper bound there).

    Parameters
    ----------
    span_m, ei_Nm2, axial_N, q_N_per_m, M_support
        As :func:`midspan_deflection`; ``q_N_per_m`` and ``M_support`` may carry
        further load components as :func:`_support_moments` does (each column c >= 2
        a load along the first axis with its moment M_y).
    out_m : ndarray, shape (n_span, k)
        k the load components of ``q_N_per_m``.

    Returns
    -------
    int
        ``STATUS_OK`` or ``STATUS_SPAN_BUCKLED``.
    """
    for i in range(span_m.shape[0]):
        L = span_m[i]
        EI = ei_Nm2[i]
        c_q = 5.0 * L ** 4 / (384.0 * EI)
        c_m = L * L / (16.0 * EI)
        dy = c_q * q_N_per_m[i, 1] + c_m * (M_support[i, 0] + M_support[i + 1, 0])
        dx = c_q * q_N_per_m[i, 0] - c_m * (M_support[i, 1] + M_support[i + 1, 1])
        amp = 1.0
        if axial_N[i] < 0.0:
            ratio = -axial_N[i] * L * L / (math.pi * math.pi * EI)
            if ratio >= BUCKLED_V * BUCKLED_V / (math.pi * math.pi):
                return STATUS_SPAN_BUCKLED
            amp = 1.0 / (1.0 - ratio)
        out_m[i, 0] = amp * dx
        out_m[i, 1] = amp * dy
        for c in range(2, q_N_per_m.shape[1]):
            dc = c_q * q_N_per_m[i, c] - c_m * (M_support[i, c] + M_support[i + 1, c])
            out_m[i, c] = amp * dc
    return STATUS_OK


@njit(cache=True)
def to_pipe_frame(M_xy, angle_rad, out_M):
    """Resolve moment vectors from a non-turning frame into the pipe-fixed frame.

    The pipe-fixed axes are the non-turning axes turned by ``angle_rad`` about
    the pipe axis (right-handed), so components transform by the rotation
    through -angle: a moment fixed in the hole alternates once per revolution
    in the pipe.

    Parameters
    ----------
    M_xy : ndarray, shape (n, 2)
    angle_rad : ndarray, shape (n,)
    out_M : ndarray, shape (n, 2)
    """
    for i in range(M_xy.shape[0]):
        c = math.cos(angle_rad[i])
        s = math.sin(angle_rad[i])
        mx = M_xy[i, 0]
        my = M_xy[i, 1]
        out_M[i, 0] = c * mx + s * my
        out_M[i, 1] = -s * mx + c * my
    return STATUS_OK


@njit(cache=True)
def transverse_load(weight_per_m_N, axis, gravity_dir, inertia_per_m_N, drag_per_m_N, e1, e2,
                    out_q):
    """Distributed transverse load of each span in its cross-section frame.

    q = buoyed weight per length times the component of the gravity direction
    normal to the axis, plus the lateral inertia and mud drag loads per length
    (already normal to the axis), resolved on the cross-section axes e1, e2.

    Parameters
    ----------
    weight_per_m_N : ndarray, shape (n,)
        Buoyed weight per length, N/m.
    axis : ndarray, shape (n, 3)
        Unit axis of each span (world frame).
    gravity_dir : ndarray, shape (3,)
        Unit vector of gravity (world frame).
    inertia_per_m_N, drag_per_m_N : ndarray, shape (n, 3)
        Lateral inertia (-m_eff a per length) and drag loads per length, N/m,
        world frame (their axial parts are removed here).
    e1, e2 : ndarray, shape (n, 3)
        Cross-section axes (unit, normal to ``axis``) in which q is wanted.
    out_q : ndarray, shape (n, 2)
    """
    for i in range(axis.shape[0]):
        f0 = weight_per_m_N[i] * gravity_dir[0] + inertia_per_m_N[i, 0] + drag_per_m_N[i, 0]
        f1 = weight_per_m_N[i] * gravity_dir[1] + inertia_per_m_N[i, 1] + drag_per_m_N[i, 1]
        f2 = weight_per_m_N[i] * gravity_dir[2] + inertia_per_m_N[i, 2] + drag_per_m_N[i, 2]
        a = f0 * axis[i, 0] + f1 * axis[i, 1] + f2 * axis[i, 2]
        f0 -= a * axis[i, 0]
        f1 -= a * axis[i, 1]
        f2 -= a * axis[i, 2]
        out_q[i, 0] = f0 * e1[i, 0] + f1 * e1[i, 1] + f2 * e1[i, 2]
        out_q[i, 1] = f0 * e2[i, 0] + f1 * e2[i, 1] + f2 * e2[i, 2]
    return STATUS_OK



@njit(cache=True)
def _span_code(L, EI, T):
    """``STATUS_OK`` for a span the beam-column solution holds on, else why not
    (``STATUS_BAD_SPAN``: L or EI <= 0 or not finite, or T not finite;
    ``STATUS_SPAN_BUCKLED``: compression at or beyond ``BUCKLED_V``)."""
    if not (L > 0.0 and EI > 0.0 and math.isfinite(L) and math.isfinite(EI)
            and math.isfinite(T)):
        return STATUS_BAD_SPAN
    if T < 0.0 and math.sqrt(-T * L * L / EI) >= BUCKLED_V:
        return STATUS_SPAN_BUCKLED
    return STATUS_OK


#: a chain of segments (:func:`chain_span_moments`): segment ends from the bit ``top_s``
#: (n_seg + 1,), m (0 first, increasing); bending stiffness ``ei`` (n_seg,), N m^2;
#: effective axial force ``T`` (n_seg,), N, tension > 0; transverse load per length ``q``
#: (n_seg, k), N/m, in a common cross-section frame (k = 2; more: :func:`_support_moments`)
SegmentChain = namedtuple("SegmentChain", ("top_s", "ei", "T", "q"))
#: the spans between supports (outputs of :func:`chain_span_moments`, one row per span):
#: length ``L``, m; bending stiffness ``ei``, N m^2; axial force ``T``, N; load ``q``
#: (n_span, k), N/m (rows beyond the spans in use are left alone)
Spans = namedtuple("Spans", ("L", "ei", "T", "q"))


@njit(cache=True)
def chain_span_moments(sup_s, chain, end_left, end_right, read_s, spans, work, sup_M, read_M,
                       span_cut):
    """Span-bending moments at read points of a segment chain with given supports.

    The glue for the dynamics: supports (contact points in contact, tool
    joints, stabilizer blades) and read points (recorded joints) are given by
    their distance from the bit; each span between consecutive supports takes
    the segments' properties over its length (EI as the length-weighted
    harmonic mean, since end rotations integrate 1/EI; axial force and load
    as length-weighted means), then :func:`support_moments` and
    :func:`moments_at`. Read points outside [sup_s[0], sup_s[-1]] get zero
    (the chain ends are supports).

    A span the beam-column solution does not hold on (in compression at or
    beyond its Euler load, or with bad properties) is handled locally: the
    chain is cut there and every run of good spans between cuts is solved as
    its own continuous beam, pinned at the cut (its own end condition at a
    chain end). The cut span gets no correction: beyond the Euler load the
    straight span between its supports does not exist (it bows onto the wall
    and gains supports the rigid chain does not see), and the linear solution
    over it says nothing about the rotational restraint it gives its
    neighbours, so they are given none (a pin: zero moment over the cut
    span's supports). The spans away from the cut are thus exactly the
    solution of the chain without that span. A run of good spans whose
    system is singular is zeroed alone. ``span_cut`` says which spans were
    cut and why.

    Parameters
    ----------
    sup_s : ndarray, shape (n_sup,)
        Support positions from the bit, m, strictly increasing (n_sup >= 2).
    chain : SegmentChain
        The segments: ends, EI, axial force and load per length (``q`` (n_seg, 2)).
    end_left, end_right : int
        End conditions at the first and last support.
    read_s : ndarray, shape (n_read,)
        Read positions from the bit, m.
    spans : Spans
        Outputs, n_sup - 1 rows: the spans' lengths, EI, axial forces and loads.
    work : ndarray, shape (n_sup, 6)
        Scratch.
    sup_M : ndarray, shape (n_sup, 2)
    read_M : ndarray, shape (n_read, 2)
        Outputs: moments over the supports and at the read points, N m.
    span_cut : ndarray of int64, shape (n_sup - 1,)
        Output: ``STATUS_OK`` for a solved span, else the reason it got no
        correction (``STATUS_SPAN_BUCKLED``, ``STATUS_BAD_SPAN``, or
        ``STATUS_SINGULAR`` for the spans of an unsolvable run).

    Returns
    -------
    int
        ``STATUS_OK`` (spans cut locally included: see ``span_cut``), or
        ``STATUS_BAD_SPAN`` for unsorted supports or a span outside the
        segments (then every output is zero).
    """
    read_ok = np.zeros(read_s.shape[0], dtype=np.int64)
    return _chain_span(sup_s, sup_M, False, chain, end_left, end_right, read_s, spans, work,
                       sup_M, read_M, span_cut, read_ok)


@njit(cache=True)
def chain_span_moments_settled(sup_s, sup_d, chain, end_left, end_right, read_s, spans, work,
                               sup_M, read_M, span_cut, read_ok):
    """:func:`chain_span_moments` on supports that stand at different heights.

    Every run of good spans is solved by :func:`support_moments_settled` with
    the offsets of its supports (a run cut off by a buckled span keeps its
    supports' offsets; a pinned end ignores its own offset's rotation, as any
    pinned support does). Zero offsets give :func:`chain_span_moments` bit for
    bit.

    Parameters
    ----------
    sup_d : ndarray, shape (n_sup, 2)
        Offset of each support in the frame of ``chain.q``, m.
    read_ok : ndarray of int64, shape (n_read,)
        Output: 1 where a read point lies in a solved span (its moment is the
        beam's), 0 where it lies outside the supports or in a cut span.
    others
        As :func:`chain_span_moments`.
    """
    return _chain_span(sup_s, sup_d, True, chain, end_left, end_right, read_s, spans, work,
                       sup_M, read_M, span_cut, read_ok)


@njit(cache=True)
def _chain_span(sup_s, sup_d, settled, chain, end_left, end_right, read_s, spans, work, sup_M,
                read_M, span_cut, read_ok):
    """:func:`chain_span_moments` (``settled``: with the support offsets ``sup_d``)."""
    n_sup = sup_s.shape[0]
    read_M[:, :] = 0.0
    sup_M[:, :] = 0.0
    span_cut[:] = STATUS_OK
    read_ok[:] = 0
    if n_sup < 2:
        return STATUS_OK
    if span_properties(sup_s, chain, spans, span_cut) != STATUS_OK:
        span_cut[:] = STATUS_BAD_SPAN
        return STATUS_BAD_SPAN
    runs_support_moments(sup_d, settled, spans, end_left, end_right, work, sup_M, span_cut)
    read_moments(sup_s, spans, sup_M, span_cut, read_s, read_M, read_ok)
    return STATUS_OK


@njit(cache=True)
def span_properties(sup_s, chain, spans, span_cut):
    """The spans between the supports ``sup_s`` (n_sup,) over the segments ``chain``
    (:func:`chain_span_moments`): their length, EI (length-weighted harmonic mean),
    axial force and load per component (length-weighted means) into the first
    n_sup - 1 rows of ``spans``, and whether the beam-column solution holds on each
    (``span_cut``: ``STATUS_OK`` or why not). Returns ``STATUS_OK``, or
    ``STATUS_BAD_SPAN`` for unsorted supports or a span outside the segments (the
    outputs then partly written)."""
    n_sup = sup_s.shape[0]
    seg_top_s = chain.top_s
    seg_ei = chain.ei
    seg_T = chain.T
    seg_q = chain.q
    n_seg = seg_ei.shape[0]
    nq = seg_q.shape[1]
    span_L = spans.L
    span_ei = spans.ei
    span_T = spans.T
    span_q = spans.q
    j = 0
    for k in range(n_sup - 1):
        a = sup_s[k]
        b = sup_s[k + 1]
        if not (b > a) or a < seg_top_s[0] - 1e-9 or b > seg_top_s[n_seg] + 1e-9:
            return STATUS_BAD_SPAN
        while j < n_seg - 1 and seg_top_s[j + 1] <= a:
            j += 1
        flex = 0.0
        t = 0.0
        for c in range(nq):
            span_q[k, c] = 0.0
        i = j
        while i < n_seg and seg_top_s[i] < b:
            lo = max(a, seg_top_s[i])
            hi = min(b, seg_top_s[i + 1])
            w = hi - lo
            if w > 0.0:
                flex += w / seg_ei[i]
                t += w * seg_T[i]
                for c in range(nq):
                    span_q[k, c] += w * seg_q[i, c]
            i += 1
        L = b - a
        span_L[k] = L
        span_ei[k] = L / flex if flex > 0.0 else seg_ei[j]
        span_T[k] = t / L
        for c in range(nq):
            span_q[k, c] /= L
        span_cut[k] = _span_code(L, span_ei[k], span_T[k])
    return STATUS_OK


@njit(cache=True)
def runs_support_moments(sup_d, settled, spans, end_left, end_right, work, sup_M, span_cut):
    """Support moments ``sup_M`` of every run of good spans (``span_cut`` ``STATUS_OK``;
    the ``span_cut`` rows of the spans in use) as its own continuous beam, pinned at a
    cut (:func:`chain_span_moments`); a run whose system is singular is zeroed and its
    spans marked ``STATUS_SINGULAR``. ``sup_M``, ``sup_d`` (n_span + 1, k) and ``work``
    (n_span + 1, 4 + k) as :func:`_support_moments`."""
    n_span = span_cut.shape[0]
    span_L = spans.L
    span_ei = spans.ei
    span_T = spans.T
    span_q = spans.q
    a = 0
    while a < n_span:
        if span_cut[a] != STATUS_OK:
            a += 1
            continue
        b = a
        while b < n_span and span_cut[b] == STATUS_OK:
            b += 1
        el = end_left if a == 0 else END_PINNED
        er = end_right if b == n_span else END_PINNED
        if settled:
            st = support_moments_settled(span_L[a:b], span_ei[a:b], span_T[a:b], span_q[a:b],
                                         sup_d[a:b + 1], el, er, work[a:b + 1], sup_M[a:b + 1])
        else:
            st = support_moments(span_L[a:b], span_ei[a:b], span_T[a:b], span_q[a:b], el, er,
                                 work[a:b + 1], sup_M[a:b + 1])
        if st != STATUS_OK:
            sup_M[a:b + 1, :] = 0.0
            for k in range(a, b):
                span_cut[k] = STATUS_SINGULAR
        a = b


@njit(cache=True)
def read_moments(sup_s, spans, sup_M, span_cut, read_s, read_M, read_ok):
    """Moments at the read points ``read_s`` of the spans solved (``span_cut``
    ``STATUS_OK``) between the supports ``sup_s`` (n_sup,), from the support moments
    ``sup_M``: ``read_M`` (n_read, k), columns as ``sup_M``, and ``read_ok`` 1 there
    (outputs not written elsewhere)."""
    n_sup = sup_s.shape[0]
    span_L = spans.L
    span_ei = spans.ei
    span_T = spans.T
    span_q = spans.q
    for r in range(read_s.shape[0]):
        x = read_s[r]
        if x < sup_s[0] or x > sup_s[n_sup - 1]:
            continue
        lo = 0
        hi = n_sup - 1
        while hi - lo > 1:  # span of x by bisection
            mid = (lo + hi) // 2
            if sup_s[mid] <= x:
                lo = mid
            else:
                hi = mid
        if span_cut[lo] != STATUS_OK:
            continue
        read_ok[r] = 1
        L = span_L[lo]
        ga, gb, h = _span_shape(span_T[lo] * L * L / span_ei[lo], L, min(x - sup_s[lo], L))
        read_M[r, 0] = ga * sup_M[lo, 0] + gb * sup_M[lo + 1, 0] + h * span_q[lo, 1]
        read_M[r, 1] = ga * sup_M[lo, 1] + gb * sup_M[lo + 1, 1] - h * span_q[lo, 0]
        for c in range(2, sup_M.shape[1]):
            read_M[r, c] = ga * sup_M[lo, c] + gb * sup_M[lo + 1, c] - h * span_q[lo, c]
