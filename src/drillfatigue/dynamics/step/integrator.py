"""Time integration: explicit velocity Verlet with a fixed step (docs/model.md#integration).

Choice and justification
------------------------
The paper integrated with variable-step BDF (tol 1e-5, max step 1 ms) and ran
120 segments at about 0.0175x real time. Here the model is integrated with the
explicit, second-order, symplectic velocity-Verlet (kick-drift-kick) scheme:

    w, v  += dt/2 * (I^-1 M_body, F / m)              half kick
    x     += dt * v ;  (q, w) <- free rotor over dt    drift (exact symmetric top,
                                                       quaternion renormalised)
    F, M   = forces(x, q, v, w)                       one force evaluation per step
    w, v  += dt/2 * (...)                             half kick

The rotational part is the symplectic splitting of Dullweber, Leimkuhler &
McLachlan (1997): the gyroscopic term w x I w is integrated exactly in the
free-rotor drift (the explicit form of that term drifts in energy by O(dt):
1 % over 1e5 steps for a spinning string in an inclined hole).

* The coupling is nearest-neighbour and the force evaluation is O(n) with no
  linear solves, so one step costs a few microseconds for 120 segments.
* The scheme is symplectic for the conservative part: with damping off the
  energy error stays bounded (no drift) -- tested over 1e5 steps.
* Stability needs dt < 2 / omega_max. :func:`drillfatigue.dynamics.step.pack.stable_step`
  bounds omega_max from above by Gershgorin's theorem on the mass-normalised
  stiffness of every element (axial, shear with its lever arms, bending,
  torsion, boundary springs), reduces it for the damping ratio
  (sqrt(1 + zeta^2) - zeta) and applies a safety factor (default 0.5). The
  shear springs kappa G A / L are what bounds the step; no mass scaling is used.
* Damping forces use the half-step velocity (first order in the damping, which
  is small); convergence is tested by halving the step (< 1 % change).
* Penalty contact and regularised friction enter the force evaluation only;
  the contact stiffness enters the stable-step bound (a mass m / points on k_c).

Drilling and tripping (docs/model.md#top-boundary): after the drift the string grows or
shrinks at the top (:func:`drillfatigue.dynamics.top.growth.grow_top`). With the
rig boundaries (``bp[B_RIG] == 1``, docs/rig.md) the block, the connection
sequence and the top drive are stepped first
(:func:`drillfatigue.dynamics.top.boundaries.rig_step`): they set the drive angle
and the rate at which the string grows.

Divergence. Every step, after the closing kick, each segment's speed is
checked against bounds no drill string reaches
(:data:`drillfatigue.dynamics.core.status.MAX_SPEED_M_PER_S`, ``MAX_SPIN_RAD_S``):
the first step at which one is exceeded (or a velocity is not finite) stops
the run with ``SPEED``, naming the step and the segment with the largest
speed relative to its bound, which is where the instability started (an
explicit scheme spreads it by about one segment per step). Every 32 steps the
kinetic energy is also checked against ``bp[B_ESCALE]`` (``BLOWUP``) and the
channels for non-finite values (``NONFINITE``).

Numba caching: numba tracks no dependencies across files, so an edit to the
force, contact or friction kernels alone would not invalidate the cached
``advance``; ``drillfatigue/__init__.py`` therefore keys the whole cache folder
by a digest of every kernel module's source (a fresh cache after any edit).

Arrays: the bundles of :mod:`drillfatigue.dynamics.core.bundles` -- the state
(updated), the parameters (the top rows change with growth), the work arrays
and the record buffers (:func:`advance`).

The loop runs a chunk of steps per call in one numba kernel; Python handles
progress, recording buffers and checkpoints between chunks. The time is
step x dt (no accumulated round-off), so a run resumed from a checkpoint is
bit-for-bit identical to an uninterrupted one.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from drillfatigue.dynamics.top.boundaries import drive_omega, rig_step
from drillfatigue.dynamics.step.forces import compute_forces
from drillfatigue.dynamics.top.growth import grow_top
from drillfatigue.dynamics.core.layout import (
    B_ESCALE, B_RIG, C_DISS, C_NACT, C_PHIB, C_PHID, C_STEP, C_WIN, CS_D, CS_N, H_PDISS, H_PIN,
    N_CH, P_LATMASS, P_SPAN, P_SPANDYN, P_SPANZ, S_IA, S_IT, S_M,
)
from drillfatigue.dynamics.core.rigid import free_rotation, kick, kick_lateral
from drillfatigue.dynamics.span.modal import accumulate_span_load, update_span_filters
from drillfatigue.dynamics.span.record import span_sample
from drillfatigue.dynamics.core.status import (
    BLOWUP, MAX_SPEED_M_PER_S, MAX_SPIN_RAD_S, NONFINITE, OK, SPEED,
)


@njit(cache=True)
def kinetic_energy(v, w, seg):
    """Translational + rotational kinetic energy (J) of all segments (inactive rows are zero)."""
    e = 0.0
    for i in range(v.shape[0]):
        e += 0.5 * seg[i, S_M] * (v[i, 0] ** 2 + v[i, 1] ** 2 + v[i, 2] ** 2)
        e += 0.5 * seg[i, S_IT] * (w[i, 0] ** 2 + w[i, 1] ** 2) + 0.5 * seg[i, S_IA] * w[i, 2] ** 2
    return e


@njit(cache=True, inline="always")
def speed_excess(v, w):
    """The larger of (|v| / MAX_SPEED_M_PER_S)^2 and (|w| / MAX_SPIN_RAD_S)^2 for one
    segment; infinite for a non-finite velocity."""
    rv = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]) / (MAX_SPEED_M_PER_S * MAX_SPEED_M_PER_S)
    rw = (w[0] * w[0] + w[1] * w[1] + w[2] * w[2]) / (MAX_SPIN_RAD_S * MAX_SPIN_RAD_S)
    if not (rv <= math.inf and rw <= math.inf):
        return math.inf
    return max(rv, rw)


@njit(cache=True, inline="always")
def record(step, t1, n, s, p, wk, rec):
    """Append the loads / channels / kinematics rows due at ``step`` (time ``t1``) to ``rec``."""
    loads = wk.loads
    ch = wk.ch
    counts = rec.counts
    sel = rec.sel
    if step % rec.every_l == 0:
        r = counts[0]
        buf_l = rec.buf_l
        buf_l[r, 0] = t1
        for a in range(sel.size):
            for k in range(6):
                buf_l[r, 1 + 6 * a + k] = loads[sel[a], k]
        if p.cpar.shape[0] > P_SPAN and p.cpar[P_SPAN] != 0.0:
            # span-bending correction after the loads of all joints (span_record)
            span = np.zeros((sel.size, 2))
            n_cut = span_sample(n, s, p, wk, sel, span)
            if n_cut > 0:
                # a sample with spans handled locally (buckled: no correction in them)
                counts[3] += 1
                counts[4] += n_cut
            elif n_cut < 0:
                # no span solved: the sample's corrections are zero
                counts[5] += 1
            base = 1 + 6 * sel.size
            for a in range(sel.size):
                buf_l[r, base + 2 * a] = span[a, 0]
                buf_l[r, base + 2 * a + 1] = span[a, 1]
        counts[0] = r + 1
    if step % rec.every_c == 0:
        r = counts[1]
        buf_c = rec.buf_c
        buf_c[r, 0] = t1
        for k in range(N_CH):
            buf_c[r, 1 + k] = ch[k]
        buf_c[r, 1 + N_CH] = kinetic_energy(s.v, s.w, p.seg)
        buf_c[r, 2 + N_CH] = s.sc[C_WIN]
        buf_c[r, 3 + N_CH] = s.sc[C_DISS]
        for k in range(buf_c.shape[1] - 4 - N_CH):
            buf_c[r, 4 + N_CH + k] = ch[N_CH + k]
        counts[1] = r + 1
    if step % rec.every_k == 0:
        r = counts[2]
        buf_k = rec.buf_k
        x = s.x
        v = s.v
        cst = s.cst
        buf_k[r, 0] = t1
        for i in range(x.shape[0]):
            if i < n:
                for k in range(3):
                    buf_k[r, 1 + 8 * i + k] = x[i, k]
                    buf_k[r, 4 + 8 * i + k] = v[i, k]
                buf_k[r, 7 + 8 * i] = cst[i, CS_N]
                buf_k[r, 8 + 8 * i] = cst[i, CS_D]
            else:
                for k in range(8):
                    buf_k[r, 1 + 8 * i + k] = math.nan
        counts[2] = r + 1


# The kicks and the drift are calls of their own compiled without numba's reference
# counting (``_nrt=False``): the rows they hand to the per-segment kernels (``v[i]``,
# ``q[i]``, ...) are views, each an atomic increment and decrement with it; they allocate
# nothing. They, the step and the joint loop divide with numpy's error model
# (``error_model="numpy"``): a float division is the bare IEEE division, without the test
# of the divisor that raises ZeroDivisionError (the same quotients; a zero divisor gives
# inf or nan, which the speed and finiteness checks of the step report); about 3 % off
# the joint loop and the integrator.
@njit(cache=True, _nrt=False, error_model="numpy")  # type: ignore[call-overload]  # _nrt: not in numba's stubs
def kick_segment(i, s, p, wk, hdt, latm):
    """Half kick of segment ``i`` by ``hdt`` (s) from its forces ``s.Fw, s.Mb``;
    ``latm``: with the lateral mud mass ``p.mlat``."""
    seg = p.seg
    if latm:
        kick_lateral(s.v[i], s.w[i], s.Fw[i], s.Mb[i], seg[i, S_M], p.mlat[i], seg[i, S_IT],
                     seg[i, S_IA], wk.R[i, :, 2], hdt)
    else:
        kick(s.v[i], s.w[i], s.Fw[i], s.Mb[i], seg[i, S_M], seg[i, S_IT], seg[i, S_IA], hdt)


@njit(cache=True, _nrt=False, error_model="numpy")  # type: ignore[call-overload]  # _nrt: not in numba's stubs
def half_kicks(n, s, p, wk, hdt, latm):
    """:func:`kick_segment` of every active segment."""
    for i in range(n):
        kick_segment(i, s, p, wk, hdt, latm)


@njit(cache=True, _nrt=False, error_model="numpy")  # type: ignore[call-overload]  # _nrt: not in numba's stubs
def half_kicks_checked(n, s, p, wk, hdt, latm):
    """:func:`half_kicks` and the speed check after each segment's kick: returns the largest
    :func:`speed_excess` above 1 and its segment, or (1.0, -1) when none exceeds."""
    v = s.v
    w = s.w
    worst = 1.0
    iworst = -1
    for i in range(n):
        kick_segment(i, s, p, wk, hdt, latm)
        r = speed_excess(v[i], w[i])
        if r > worst:
            worst = r
            iworst = i
    return worst, iworst


@njit(cache=True, _nrt=False, error_model="numpy")  # type: ignore[call-overload]  # _nrt: not in numba's stubs
def drift(n, s, p, wk, dt, latm):
    """Drift of every active segment over ``dt`` (s): positions by the velocities, rotations
    by the exact free rotor (tilt inertia with the lateral mud mass when ``latm``)."""
    x = s.x
    v = s.v
    q = s.q
    w = s.w
    seg = p.seg
    mlat = p.mlat
    for i in range(n):
        for k in range(3):
            x[i, k] += dt * v[i, k]
        it = seg[i, S_IT] * mlat[i] if latm else seg[i, S_IT]
        free_rotation(q[i], w[i], it, seg[i, S_IA], dt)


# One step without the recorder, compiled without numba's reference counting: everything
# in it (kicks, drift, rig, growth, forces) allocates nothing, and the rows its inlined
# kernels take (``q[i]``, ``R[top]``, ...) would otherwise each count references. Only the
# recorder's span sample allocates, so it stays in :func:`advance`.
@njit(cache=True, _nrt=False, error_model="numpy")  # type: ignore[call-overload]  # _nrt: not in numba's stubs
def step(n, s, p, wk, hdt, latm, info):
    """One velocity-Verlet step of the ``n`` active segments (see :func:`advance`), without
    recording; returns (status code, active segments after the step). On failure
    ``info`` = [step, segment (-1: unknown), value]."""
    sc = s.sc
    w = s.w
    ch = wk.ch
    dt = p.dt
    half_kicks(n, s, p, wk, hdt, latm)
    drift(n, s, p, wk, dt, latm)
    sc[C_PHIB] += dt * w[0, 2]
    t0 = sc[C_STEP] * dt
    sc[C_STEP] += 1.0
    t1 = sc[C_STEP] * dt
    if p.bp[B_RIG] == 1.0:
        rst = rig_step(t0, s, p, wk)
        if rst != OK:
            info[0] = sc[C_STEP]
            info[1] = -1.0
            info[2] = 0.0
            return rst, n
    else:
        sc[C_PHID] += 0.5 * dt * (drive_omega(t0, p.tab_t, p.tab_w) + drive_omega(t1, p.tab_t, p.tab_w))
    n = grow_top(n, t1, s, p, wk)
    fst = compute_forces(s, p, wk)
    if fst != OK:
        info[0] = sc[C_STEP]
        info[1] = -1.0
        info[2] = 0.0
        return fst, n
    sc[C_WIN] += dt * ch[H_PIN]
    sc[C_DISS] += dt * ch[H_PDISS]
    worst, iworst = half_kicks_checked(n, s, p, wk, hdt, latm)
    if iworst >= 0:
        info[0] = int(sc[C_STEP])
        info[1] = iworst
        info[2] = worst
        return SPEED, n
    if p.cpar.shape[0] > P_SPANZ and p.cpar[P_SPANDYN] > 0.0:
        # the span filter (span_dynamics): this step's impulse, and the filter's update
        # on the loads record's grid of steps
        accumulate_span_load(n, s, p, dt)
        if sc[C_STEP] % p.cpar[P_SPANDYN] == 0.0:
            update_span_filters(n, s, p, wk, latm, p.cpar[P_SPANZ])
    return OK, n


@njit(cache=True)
def advance(n_steps, s, p, wk, rec):
    """Advance the state ``s`` by ``n_steps`` velocity-Verlet steps, recording on the way.

    Parameters
    ----------
    n_steps : int
    s : bundles.State                 updated (the forces ``Fw, Mw, Mb`` are those of the
                                      current state, kept between calls)
    p : bundles.Params                the model (``seg``, ``jp``, ``topp`` change as the
                                      string grows)
    wk : bundles.Work                 written by the force evaluation
    rec : bundles.Records             loads of the joints ``rec.sel`` every ``rec.every_l``
                                      steps into ``rec.buf_l`` (rows: time_s, then the 6
                                      loads per joint), channels every ``rec.every_c`` into
                                      ``rec.buf_c`` (time_s, ch, kinetic energy, W_in,
                                      dissipated), kinematics every ``rec.every_k`` into
                                      ``rec.buf_k`` (time_s, then x, v, normal force,
                                      distance from the hole centre per segment; NaN:
                                      inactive); ``rec.counts`` rows written to each
                                      (reset by the caller); on failure ``rec.info`` =
                                      [step, segment (-1: unknown), value]

    Returns
    -------
    int
        A status code (:mod:`drillfatigue.dynamics.core.status`): ``OK``; ``SPEED``
        (value: the speed ratio squared), ``NONFINITE`` or ``BLOWUP`` (value: the
        kinetic energy, J); ``UNKNOWN_FRICTION`` / ``UNKNOWN_BIT`` from the forces.
    """
    x = s.x
    v = s.v
    w = s.w
    sc = s.sc
    seg = p.seg
    dt = p.dt
    info = rec.info
    n = int(sc[C_NACT])
    hdt = 0.5 * dt
    ch = wk.ch
    latm = p.cpar.shape[0] > P_LATMASS and p.cpar[P_LATMASS] != 0.0
    for _s in range(n_steps):
        st, n = step(n, s, p, wk, hdt, latm, info)
        if st != OK:
            return st
        step_i = int(sc[C_STEP])
        t1 = sc[C_STEP] * dt
        record(step_i, t1, n, s, p, wk, rec)
        if step_i % 32 == 0 or _s == n_steps - 1:
            ke = kinetic_energy(v, w, seg)
            if not math.isfinite(ke) or not math.isfinite(ch[0] + ch[1] + ch[2]):
                info[0] = step_i
                info[1] = -1.0
                for i in range(n):
                    bad = False
                    for k in range(3):
                        if not (math.isfinite(x[i, k]) and math.isfinite(v[i, k])
                                and math.isfinite(w[i, k])):
                            bad = True
                    if bad:
                        info[1] = i
                        break
                info[2] = ke
                return NONFINITE
            if ke > p.bp[B_ESCALE]:
                info[0] = step_i
                # the segment with the largest kinetic energy
                best = 0.0
                for i in range(n):
                    e = 0.5 * seg[i, S_M] * (v[i, 0] ** 2 + v[i, 1] ** 2 + v[i, 2] ** 2)
                    if e >= best:
                        best = e
                        info[1] = i
                info[2] = ke
                return BLOWUP
    return OK
