"""Dynamic response of a span to its distributed load (docs/bending.md#dynamic-span-response).

The span correction (:mod:`drillfatigue.dynamics.span.record`) gives the
moment of a span's distributed transverse load between its supports. That
load is the buoyed weight and mud drag minus the segment's lateral inertia,
and the inertia carries every concentrated force the segment feels: a wall
impact of a few milliseconds shows as a load spike of the same duration. Put
quasi-statically into the span (moment ~ F L / 8), such a spike says the pipe
bends between its supports as if the impact had lasted for ever, and the
200 Hz record either catches it whole or misses it (the window's damage then
depends on where the samples fall).

A real span answers a load through its flexural modes, and a row of equal
spans on rigid supports has a band of them: from the pinned-pinned frequency
(neighbouring spans bowing in opposite senses, which puts no moment over the
supports) to the clamped-clamped one (spans bowing alike, zero slope over
every support: the mode of a load that every span carries alike, weight or a
whirl's inertia, and the one that holds the moment over the supports, where
the joints are read). The filter follows that in-phase mode, whose shape is
within 0.4 % of the static deflection's and 3 % of its mid-span moment, as one
degree of freedom (the modal, or "dynamic load factor", approach of
structural dynamics: Biggs, *Introduction to Structural Dynamics*, 1964,
ch. 2; Clough & Penzien, *Dynamics of Structures*, 2nd ed. 1993, ch. 4-6):

    y'' + 2 zeta omega y' + omega^2 y = omega^2 u(t)

with u the quasi-static load (per segment, world frame: each component solved
alone, the equation is linear) and y the load that the span's deflection
holds now, which the three-moment solution then turns into moments. Static
gain 1: a load that changes slowly compared with the span's period (weight,
the drag of a steady whirl, the once-per-revolution alternation in the pipe
frame, which is a steady load in the world frame) gives the moment of the
quasi-static correction; an impulse J lasting tau << 1/omega gives a peak of
about J omega (against J / tau quasi-statically), i.e. the factor omega tau,
and then rings down at the span's frequency.

* omega: the first in-phase frequency of the span clamped at both ends with
  its axial force T, by Rayleigh's quotient with that mode's shape:
  omega^2 = (4.730 / L)^4 EI / mu + 12.30 T / (mu L^2) (exact without T;
  in tension it tends to the string's pi^2 T / (mu L^2), 25 % below, a
  slight over-estimate; in compression it falls towards the span's
  buckling, and is kept above 0.3 of its value without T: a span that far
  in compression lies on the wall). L: the distance between neighbouring
  raised contact points (tool joints, upsets, blades) when they reach both
  ends of the segment (one pipe joint, 9.14 m, however many joints a
  segment holds), else the segment's length (flush collars, a stabilizer
  segment); the growing top segment takes the span of the one below it.
  mu: the lateral mass per length (steel, and with ``lateral_mud_mass`` the
  mud inside and the added mass). T: the mean effective tension of the
  segment's two joints, as the span solution takes it. 5 in drill pipe in
  1.2 SG mud, one joint: 5.5 Hz without axial force (328 rpm), 5.9 Hz at
  100 kN of tension; 4 m segments of 6 3/4 in collars: 39 Hz.
* zeta: the segment's own linear mud drag (``seg[:, S_CL]``, the one the
  integrator applies to its lateral motion) as a modal damping ratio,
  c / (2 m_lat omega), not below ``zeta_min`` (contact and structural damping
  that the rigid chain does not carry): 0 < zeta < 1.
* u: the mean load over the record interval (its impulse divided by the
  interval: the integrator adds (-c v - F) dt every step), held constant over
  the interval -- the exact zero-order-hold solution of the equation, so an
  impulse anywhere in the interval counts once, whatever the sample times.
  The response is resolved to the interval (5 ms at 200 Hz, omega T ~ 0.2
  for drill-pipe spans); a span stiff enough to answer within the interval
  sees its load averaged over it.

Validity: linear, small deflections, one mode: a load on one span alone
excites the whole band, whose lower modes put less moment over the supports,
so the filter (at the band's top) errs towards the quasi-static answer there;
a span shorter or longer than its raised-point spacing (a mid-body wall
contact, a row of segments in line contact) keeps that spacing's frequency.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from drillfatigue.dynamics.core.layout import (
    CS_SQA, CS_SQD, CS_SQF, CS_SQON, CS_SQT, P_CPTAB, P_LATMASS, S_CL, S_H, S_M, S_RB,
)

#: the damping ratio kept below 1 (the closed form below is the under-damped one)
ZETA_MAX = 0.95


#: first in-phase mode of a span clamped at both ends (a row of equal spans loaded
#: alike: zero slope over every support), beam theory: (beta L)^4 with beta L = 4.7300
CC_EIGEN4 = 500.5639
#: its tension term, L^2 int(phi'^2) / int(phi^2) of that mode shape (Rayleigh's
#: quotient; pi^2 = 9.87 for the pinned-pinned mode, the string's limit)
CC_TENSION = 12.3026
#: the least omega as a share of the span's omega without axial force: in compression
#: near the span's buckling load (40.7 EI / L^2 by the same quotient) the span lies on
#: the wall, which the quasi-static solution handles by splitting it
OMEGA_MIN_SHARE = 0.3


@njit(cache=True)
def span_mode(length_m, ei_Nm2, mass_kg, drag_N_s_per_m, zeta_min, axial_N):
    """First in-phase bending frequency (rad/s) and damping ratio of a span of
    ``length_m`` clamped at both ends, with ``mass_kg`` (lateral), linear lateral drag
    ``drag_N_s_per_m`` on the whole span and effective axial force ``axial_N``
    (tension > 0), by Rayleigh's quotient with the mode's shape (module docstring)."""
    mu = mass_kg / length_m
    w0sq = CC_EIGEN4 * ei_Nm2 / (mu * length_m ** 4)
    wsq = w0sq + CC_TENSION * axial_N / (mu * length_m ** 2)
    lo = OMEGA_MIN_SHARE * OMEGA_MIN_SHARE * w0sq
    if not wsq >= lo:
        wsq = lo
    omega = math.sqrt(wsq)
    zeta = drag_N_s_per_m / (2.0 * mass_kg * omega)
    if zeta < zeta_min:
        zeta = zeta_min
    if zeta > ZETA_MAX:
        zeta = ZETA_MAX
    return omega, zeta


@njit(cache=True)
def sdof_hold_step(y, yd, u, omega, zeta, T):
    """Exact step over ``T`` of y'' + 2 zeta omega y' + omega^2 y = omega^2 u with u held
    constant (zero-order hold); returns (y, y') at the end. 0 <= zeta < 1."""
    wd = omega * math.sqrt(1.0 - zeta * zeta)
    e0 = y - u
    a = math.exp(-zeta * omega * T)
    c = math.cos(wd * T)
    sn = math.sin(wd * T)
    b = (yd + zeta * omega * e0) / wd
    e1 = a * (e0 * c + b * sn)
    yd1 = a * (yd * c - (omega * omega * e0 + zeta * omega * yd) / wd * sn)
    return u + e1, yd1


@njit(cache=True, _nrt=False, error_model="numpy")  # type: ignore[call-overload]  # _nrt: not in numba's stubs
def accumulate_span_load(n, s, p, dt):
    """Add the impulse over one step of each active segment's dynamic transverse load
    -c_lat v - F (world frame, N s; its axial part is removed where it is used) and the
    step to the segment's running sums in ``s.cst``."""
    seg = p.seg
    v = s.v
    Fw = s.Fw
    cst = s.cst
    for i in range(n):
        cl = seg[i, S_CL]
        for k in range(3):
            cst[i, CS_SQA + k] += dt * (-cl * v[i, k] - Fw[i, k])
        cst[i, CS_SQT] += dt


@njit(cache=True)
def span_length_m(i, n, p):
    """The span whose mode segment ``i``'s filter follows, m: the longest distance
    between neighbouring raised contact points (tool joints, blades, upsets: radius
    above the body's) in the segment's own table (``cpar[P_CPTAB]``) when they reach
    both ends of the segment, else the segment's length. The growing top segment (its
    own table is not used) takes the span of the segment below it."""
    seg = p.seg
    j = n - 2 if (i == n - 1 and n >= 2) else i
    if not (p.cpar[P_CPTAB] != 0.0 and j < n - 1):
        return 2.0 * seg[i, S_H]
    k = int(p.cp_n[j])
    rb = seg[j, S_RB]
    best = 0.0
    top = -math.inf
    bot = math.inf
    for a in range(k):
        if p.cp[j, a, 1] <= rb:
            continue
        top = max(top, p.cp[j, a, 0])
        bot = min(bot, p.cp[j, a, 0])
        # the nearest raised point below this one
        near = math.inf
        for b in range(k):
            if b == a or p.cp[j, b, 1] <= rb:
                continue
            d = p.cp[j, a, 0] - p.cp[j, b, 0]
            if 0.0 < d < near:
                near = d
        if near < math.inf and near > best:
            best = near
    # raised points that do not reach both ends of the segment (a stabilizer's blades
    # in the middle of a flush segment) do not make its spans
    h = seg[j, S_H]
    if best <= 0.0 or top < h - 0.05 * h or bot > -h + 0.05 * h:
        return 2.0 * h
    return best


@njit(cache=True)
def segment_axial_N(i, n, loads):
    """Effective axial force of active segment ``i`` (N, tension > 0): the mean of its
    two joints' (the first and the last segment take their one joint's; row ``n - 1``
    of ``loads`` is the top boundary). The span solution and the span filter both
    take it."""
    lo = loads[i - 1, 0] if i > 0 else loads[0, 0]
    up = loads[i, 0] if i < n - 1 else loads[n - 2, 0]
    return 0.5 * (lo + up)


@njit(cache=True)
def segment_mode(i, n, p, latm, zeta_min, axial_N):
    """(span m, omega rad/s, zeta) of active segment ``i``'s span filter under the axial
    force ``axial_N``: the span of :func:`span_length_m`, with the segment's lateral
    mass and drag per length (``latm``: the lateral mud mass ``p.mlat``)."""
    seg = p.seg
    L = 2.0 * seg[i, S_H]
    ls = span_length_m(i, n, p)
    m = seg[i, S_M] * p.mlat[i] if latm else seg[i, S_M]
    omega, zeta = span_mode(ls, p.ei[i], m * ls / L, seg[i, S_CL] * ls / L, zeta_min, axial_N)
    return ls, omega, zeta


@njit(cache=True, _nrt=False, error_model="numpy")  # type: ignore[call-overload]  # _nrt: not in numba's stubs
def update_span_filters(n, s, p, wk, latm, zeta_min):
    """Advance every active segment's span filter over the interval summed since its last
    update (the mean load over it held, :func:`sdof_hold_step`); the running sums
    restart. A segment whose filter has not run yet (a new run, a segment the string
    just grew) starts at rest on the interval's mean load."""
    cst = s.cst
    for i in range(n):
        T = cst[i, CS_SQT]
        if T <= 0.0:
            continue
        _, omega, zeta = segment_mode(i, n, p, latm, zeta_min, segment_axial_N(i, n, wk.loads))
        started = cst[i, CS_SQON] != 0.0
        for k in range(3):
            u = cst[i, CS_SQA + k] / T
            if started:
                y, yd = sdof_hold_step(cst[i, CS_SQF + k], cst[i, CS_SQD + k], u, omega, zeta, T)
            else:
                y = u
                yd = 0.0
            cst[i, CS_SQF + k] = y
            cst[i, CS_SQD + k] = yd
            cst[i, CS_SQA + k] = 0.0
        cst[i, CS_SQON] = 1.0
        cst[i, CS_SQT] = 0.0


def span_modes(p: object, n: int, zeta_min: float,
               axial_N: np.ndarray | None = None) -> np.ndarray:
    """(span m, omega rad/s, zeta) of the ``n`` active segments of the parameter bundle
    ``p`` (:class:`drillfatigue.dynamics.core.bundles.Params`) under the segments' axial
    forces ``axial_N`` (N, tension > 0; None: zero): what the span filter uses."""
    cpar = p.cpar  # type: ignore[attr-defined]
    latm = bool(cpar.shape[0] > P_LATMASS and cpar[P_LATMASS] != 0.0)
    out = np.zeros((n, 3))
    for i in range(n):
        ax = 0.0 if axial_N is None else float(axial_N[i])
        out[i] = segment_mode(i, n, p, latm, zeta_min, ax)
    return out
