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
free-rotor drift, which removed an O(dt) energy drift of the explicit form
(measured 1 % over 1e5 steps for a spinning string in an inclined hole).

* The coupling is nearest-neighbour and the force evaluation is O(n) with no
  linear solves, so one step costs a few microseconds for 120 segments.
* The scheme is symplectic for the conservative part: with damping off the
  energy error stays bounded (no drift) -- tested over 1e5 steps.
* Stability needs dt < 2 / omega_max. :func:`drillfatigue.dynamics.model.stable_step`
  bounds omega_max from above by Gershgorin's theorem on the mass-normalised
  stiffness of every element (axial, shear with its lever arms, bending,
  torsion, boundary springs), reduces it for the damping ratio
  (sqrt(1 + zeta^2) - zeta) and applies a safety factor (default 0.5). The
  shear springs kappa G A / L are what bounds the step; no mass scaling is used.
* Damping forces use the half-step velocity (first order in the damping, which
  is small); convergence is tested by halving the step (< 1 % change).
* Penalty contact and regularised friction enter the force evaluation only;
  the contact stiffness enters the stable-step bound (a mass m / points on k_c).

Drilling and tripping (docs/model.md#top-boundary). Each step the string length changes by
dL = ROP dt (bit on bottom: the ROP of the bit law or the prescribed one; the
rock face MD advances by the same amount) or trip_speed dt (off bottom). The
top segment grows (or shrinks) from its fixed top end. When it is longer than
``bp[B_LSPLIT]`` a segment of ``bp[B_LNOM]`` is split off its bottom
(:func:`forces.split_top`), so a 480 -> 880 m run keeps its resolution; when a
tripping-out top segment is shorter than ``bp[B_LMIN]`` it merges with the one
below (:func:`forces.merge_top`); with only two segments left tripping out stops
(``sc[C_GUARD] = 1``). Arrays are allocated to the largest size the run can
reach; the kernels use the first ``sc[C_NACT]`` rows (no reallocation). Energy
changed by growth, splits and merges is booked as work put in (feeding pipe).
The growth is applied once per step (the joint below the top is shortened by
dL = ROP dt at once), so the booking carries an O(dt) error of about
k_a dL^2 / 2 per step: with 3 m pipe segments at 0.5 m/s the summary's
``energy_balance_error_rel`` reaches ~0.2 (it halves with the step); without
growth the balance closes to ~1e-4. The damper of the joint below the top sees
the growth rate (:func:`forces.compute_forces`), so no spurious static load
builds up there.

Numba caching: numba tracks no dependencies across files, so an edit to the
force, contact or friction kernels alone would not invalidate the cached
``advance``; ``drillfatigue/__init__.py`` therefore keys the whole cache folder
by a digest of every kernel module's source (a fresh cache after any edit).

The loop runs a chunk of steps per call in one numba kernel; Python handles
progress, recording buffers and checkpoints between chunks. The time is
step x dt (no accumulated round-off), so a run resumed from a checkpoint is
bit-for-bit identical to an uninterrupted one.
"""

from __future__ import annotations

import math

from numba import njit

from drillfatigue.dynamics.forces import (
    compute_forces, drive_omega, merge_top, split_top, tail_energy, update_top,
)
from drillfatigue.dynamics.layout import (
    B_BITON, B_EXT, B_FREEZE, B_LMIN, B_LSPLIT, C_DISS, C_GUARD, C_MDROCK, C_NACT, C_NMERGE, C_NSPLIT,
    C_PHIB, C_PHID, C_ROPNOW, C_STEP, C_WIN, CS_D, CS_N, H_PDISS, H_PIN, N_CH, S_H, S_IA, S_IT,
    S_M, ST_BLOWUP, ST_FORCES, ST_NONFINITE, ST_OK, B_ESCALE,
)
from drillfatigue.dynamics.rigid import free_rotation, kick


@njit(cache=True)
def kinetic_energy(v, w, seg):
    """Translational + rotational kinetic energy (J) of all segments (inactive rows are zero)."""
    e = 0.0
    for i in range(v.shape[0]):
        e += 0.5 * seg[i, S_M] * (v[i, 0] ** 2 + v[i, 1] ** 2 + v[i, 2] ** 2)
        e += 0.5 * seg[i, S_IT] * (w[i, 0] ** 2 + w[i, 1] ** 2) + 0.5 * seg[i, S_IA] * w[i, 2] ** 2
    return e


@njit(cache=True)
def advance(n_steps, dt, x, v, q, w, Fw, Mw, Mb, sc, seg, jp, bp, topp, anchor, tab_t, tab_w,
            node_md, node_pos, node_tan, wall, cpar, hint, cst, R, wW, loads, ch,
            sel, every_l, buf_l, every_c, buf_c, every_k, buf_k, counts, info,
            scq, scm, scv, ed, cw):
    """Advance the state by ``n_steps`` velocity-Verlet steps, recording on the way.

    Parameters
    ----------
    n_steps : int
    dt : float                         step (s)
    x, v, q, w                         state (see :func:`forces.compute_forces`), updated
    Fw, Mw, Mb                         forces at the current state (kept between calls)
    sc : ndarray, shape (N_SC,)        scalar state, updated
    seg, jp, bp, topp, anchor, tab_t, tab_w, node_md, node_pos, node_tan, wall, cpar
                                       parameters (see :mod:`layout`)
    hint : ndarray of int64, shape (3 n,)  contact cylinder hints per contact point (state)
    cst : ndarray, shape (n, N_CST)  contact / whirl statistics (state)
    R, wW, loads, ch                   work arrays written by the force evaluation
    sel : ndarray of int64, shape (J,) joint rows recorded
    every_l, every_c, every_k : int    record loads / channels / kinematics every this many steps
    buf_l : ndarray, shape (>= rows, 1 + 6 J)    written rows: time_s, then the 6 loads per joint
    buf_c : ndarray, shape (>= rows, 1 + N_CH + 3)  time_s, ch, kinetic energy, W_in, dissipated
    buf_k : ndarray, shape (>= rows, 1 + 8 n)    time_s, then x, v, normal force, distance from
                                                 the hole centre per segment (NaN: inactive)
    counts : ndarray of int64, shape (3,)  rows written to each buffer (reset by the caller)
    info : ndarray, shape (3,)         written on failure: [step, segment, kinetic energy]
    scq, scm, scv, ed, cw              scratch

    Returns
    -------
    int
        ST_OK, ST_NONFINITE (a non-finite state), ST_BLOWUP (kinetic energy above
        ``bp[B_ESCALE]``) or ST_FORCES (the force kernel failed, its code in info[2]);
        on failure ``info`` says where.
    """
    nmax = x.shape[0]
    n = int(sc[C_NACT])
    hdt = 0.5 * dt
    ext = bp[B_EXT]
    biton = bp[B_BITON] == 1.0
    nsel = sel.size
    for _s in range(n_steps):
        for i in range(n):
            kick(v[i], w[i], Fw[i], Mb[i], seg[i, S_M], seg[i, S_IT], seg[i, S_IA], hdt)
        for i in range(n):
            for k in range(3):
                x[i, k] += dt * v[i, k]
            free_rotation(q[i], w[i], seg[i, S_IT], seg[i, S_IA], dt, scq[0], scq[1])
        sc[C_PHIB] += dt * w[0, 2]
        t0 = sc[C_STEP] * dt
        sc[C_STEP] += 1.0
        t1 = sc[C_STEP] * dt
        sc[C_PHID] += 0.5 * dt * (drive_omega(t0, tab_t, tab_w) + drive_omega(t1, tab_t, tab_w))
        if bp[B_FREEZE] == 1.0:
            dL = 0.0
        elif biton:
            dL = sc[C_ROPNOW] * dt
            sc[C_MDROCK] += dL
        else:
            dL = ext * dt
            if sc[C_GUARD] == 1.0 and dL < 0.0:
                dL = 0.0
        if dL != 0.0:
            top = n - 1
            # the top segment grows downward from its fixed top end; the energy
            # this changes is booked as work put in (feeding pipe)
            e_before = tail_energy(top, t1, x, v, q, w, seg, jp, anchor, tab_t, tab_w, sc, R, wW,
                                   scq, scm, scv, loads, ed)
            h_new = seg[top, S_H] + 0.5 * dL
            if 2.0 * h_new < bp[B_LMIN] and n <= 2:
                # tripping out: keep a minimum string
                sc[C_GUARD] = 1.0
                h_new = seg[top, S_H]
            dh = h_new - seg[top, S_H]
            for k in range(3):
                x[top, k] += dh * R[top, k, 2]
            update_top(h_new, n, seg, jp, topp, bp)
            if 2.0 * h_new > bp[B_LSPLIT] and n < nmax:
                n = split_top(x, v, q, w, seg, jp, topp, bp, hint, cst, sc, R, scv, dL / dt)
                sc[C_NSPLIT] += 1.0
            elif 2.0 * h_new < bp[B_LMIN] and n > 2:
                e_before = tail_energy(n - 2, t1, x, v, q, w, seg, jp, anchor, tab_t, tab_w, sc, R,
                                       wW, scq, scm, scv, loads, ed) - tail_energy(
                    top, t1, x, v, q, w, seg, jp, anchor, tab_t, tab_w, sc, R, wW, scq, scm, scv,
                    loads, ed) + e_before
                n = merge_top(x, v, q, w, seg, jp, topp, bp, sc, R, scv)
                sc[C_NMERGE] += 1.0
                top = n - 1
            sc[C_WIN] += tail_energy(top, t1, x, v, q, w, seg, jp, anchor, tab_t, tab_w, sc, R, wW,
                                     scq, scm, scv, loads, ed) - e_before
        fst = compute_forces(dt, x, v, q, w, seg, jp, bp, anchor, tab_t, tab_w,
                             node_md, node_pos, node_tan, wall, cpar, hint, cst, sc, R, wW, Fw, Mw,
                             Mb, loads, ch, scq, scm, scv, ed, cw)
        if fst != 0:
            info[0] = sc[C_STEP]
            info[1] = -1.0
            info[2] = fst
            return ST_FORCES
        sc[C_WIN] += dt * ch[H_PIN]
        sc[C_DISS] += dt * ch[H_PDISS]
        for i in range(n):
            kick(v[i], w[i], Fw[i], Mb[i], seg[i, S_M], seg[i, S_IT], seg[i, S_IA], hdt)
        step = int(sc[C_STEP])
        if step % every_l == 0:
            r = counts[0]
            buf_l[r, 0] = t1
            for a in range(nsel):
                for k in range(6):
                    buf_l[r, 1 + 6 * a + k] = loads[sel[a], k]
            counts[0] = r + 1
        if step % every_c == 0:
            r = counts[1]
            buf_c[r, 0] = t1
            for k in range(N_CH):
                buf_c[r, 1 + k] = ch[k]
            buf_c[r, 1 + N_CH] = kinetic_energy(v, w, seg)
            buf_c[r, 2 + N_CH] = sc[C_WIN]
            buf_c[r, 3 + N_CH] = sc[C_DISS]
            counts[1] = r + 1
        if step % every_k == 0:
            r = counts[2]
            buf_k[r, 0] = t1
            for i in range(nmax):
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
        if step % 32 == 0 or _s == n_steps - 1:
            ke = kinetic_energy(v, w, seg)
            if not math.isfinite(ke) or not math.isfinite(ch[0] + ch[1] + ch[2]):
                info[0] = step
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
                return ST_NONFINITE
            if ke > bp[B_ESCALE]:
                info[0] = step
                # the segment with the largest kinetic energy
                best = 0.0
                for i in range(n):
                    e = 0.5 * seg[i, S_M] * (v[i, 0] ** 2 + v[i, 1] ** 2 + v[i, 2] ** 2)
                    if e >= best:
                        best = e
                        info[1] = i
                info[2] = ke
                return ST_BLOWUP
    return ST_OK
