"""Numba kernels of the fatigue chain: indexed rainflow and multi-plane damage.

Plain functions on float64 arrays in SI (stresses in Pa), importing only numpy,
numba and math. They write into preallocated ``out`` arrays and return a
status code of the package's one enumeration, :mod:`drillfatigue.status`
(:func:`rainflow_indexed` returns the number of cycles, or minus a code); the
Python wrappers in :mod:`drillfatigue.fatigue.rainflow` and
:mod:`drillfatigue.fatigue.critical_plane` turn a failure into an exception
through :func:`drillfatigue.errors.raise_for_status`.

Rainflow here is the 4-point method on exact (unbinned) reversals
(Amzallag et al., Int. J. Fatigue 16 (1994) 287-293; ISO 12110-2), with the
residue closed either as half cycles (ASTM E1049-85 (2017) section 5.4.4
equivalent: each adjacent pair of the residue is a half cycle) or by repeating
the residue once (fatpack's ``find_rainflow_ranges`` convention).

Status codes: ``OK``; ``STACK_OVERFLOW``, a residue stack over its capacity
(the critical-plane wrapper retries with a larger one); ``OUT_OVERFLOW``, more
cycles than the output arrays hold.
"""

from __future__ import annotations

from collections import namedtuple

import numpy as np
from numba import njit, prange

from drillfatigue.status import OK, OUT_OVERFLOW, STACK_OVERFLOW

RESIDUE_HALF = 0
RESIDUE_REPEAT = 1
RESIDUE_NONE = 2  # keep the residue open (streaming; caller carries it)

CRIT_MATAKE = 0
CRIT_FINDLEY = 1
CRIT_FATEMI_SOCIE = 2
CRIT_SHEAR = 3  # Tresca-type: equivalent amplitude = shear range (plane selection)


# ---------------------------------------------------------------------------
# 1-D indexed rainflow
# ---------------------------------------------------------------------------
@njit(cache=True)
def _push_index(y, stk, m, k):
    """Peak-valley filtered push of sample k onto the index stack; returns new m."""
    v = y[k]
    if m >= 1 and y[stk[m - 1]] == v:
        return m  # plateau: the reversal stays at the first sample
    if m >= 2 and (y[stk[m - 1]] - y[stk[m - 2]]) * (v - y[stk[m - 1]]) > 0.0:
        stk[m - 1] = k  # monotone continuation: the top was not a reversal
        return m
    stk[m] = k
    return m + 1



@njit(cache=True)
def rainflow_indexed(y, residue_mode, out_from, out_to, out_count, out_residue):
    """Rainflow cycles of ``y`` with the sample index of each cycle's ends.

    Parameters
    ----------
    y : ndarray, shape (n,), float64
        Signal (any unit).
    residue_mode : int
        RESIDUE_HALF, RESIDUE_REPEAT or RESIDUE_NONE.
    out_from, out_to : ndarray, shape (>= n,), int64
        Sample indices of the start and end of each (half) cycle.
    out_count : ndarray, shape (>= n,), float64
        1.0 for a full cycle, 0.5 for a half cycle.
    out_residue : ndarray, shape (>= n + 1,), int64
        Sample indices of the residue (after the first pass);
        ``out_residue[0]`` holds its length.

    Returns
    -------
    int
        Number of cycles written (>= 0), or ``-OUT_OVERFLOW`` when the output
        arrays are too short.
    """
    n = y.shape[0]
    stk = np.empty(2 * n + 2, dtype=np.int64)
    seq = np.arange(n)  # the samples, then (repeat) the residue once more
    m = 0
    nc = 0
    cap = out_from.shape[0]
    for again in range(2):
        if again:
            if residue_mode != RESIDUE_REPEAT:
                break
            seq = stk[:m].copy()
        for j in range(seq.shape[0]):
            m = _push_index(y, stk, m, seq[j])
            while m >= 4:
                s0 = y[stk[m - 4]]
                s1 = y[stk[m - 3]]
                s2 = y[stk[m - 2]]
                s3 = y[stk[m - 1]]
                d2 = abs(s2 - s1)
                if d2 <= abs(s1 - s0) and d2 <= abs(s3 - s2):
                    if nc >= cap:
                        return -OUT_OVERFLOW
                    out_from[nc] = stk[m - 3]
                    out_to[nc] = stk[m - 2]
                    out_count[nc] = 1.0
                    nc += 1
                    stk[m - 3] = stk[m - 1]
                    m -= 2
                else:
                    break
        if not again:  # the signal ends: the stack is the residue
            out_residue[0] = m
            for i in range(m):
                out_residue[i + 1] = stk[i]
    if residue_mode == RESIDUE_HALF:
        for i in range(m - 1):
            if nc >= cap:
                return -OUT_OVERFLOW
            out_from[nc] = stk[i]
            out_to[nc] = stk[i + 1]
            out_count[nc] = 0.5
            nc += 1
    return nc


# ---------------------------------------------------------------------------
# S-N evaluation
# ---------------------------------------------------------------------------
@njit(cache=True)
def sn_inverse_life(S, seg_S_low, seg_m, seg_inv_a, S_cut):
    """1/N for a stress range S on a piecewise log-linear S-N curve.

    Parameters
    ----------
    S : float
        Stress range in the curve's unit (MPa for the DNV library).
    seg_S_low : ndarray, shape (n_seg,)
        Lower stress bound of each segment, descending; the last is 0.
    seg_m : ndarray, shape (n_seg,)
        Negative inverse slope m of each segment (N = a S^-m).
    seg_inv_a : ndarray, shape (n_seg,)
        1/a of each segment.
    S_cut : float
        Cut-off (fatigue limit): 1/N = 0 for S < S_cut.

    Returns
    -------
    float
        1/N(S).
    """
    if S <= 0.0 or S < S_cut:
        return 0.0
    i = 0
    while S < seg_S_low[i]:
        i += 1
    m = seg_m[i]
    if m == 3.0:
        p = S * S * S
    elif m == 5.0:
        p = S * S * S * S * S
    elif m == 4.0:
        p = S * S
        p = p * p
    else:
        p = S**m
    return p * seg_inv_a[i]


@njit(cache=True, inline="always")
def _pseudo_angle(x, y):
    """Monotone pseudo-angle of the direction (x, y) in [0, 4)."""
    ax = abs(x)
    if y >= 0.0:
        return 1.0 - x / (ax + y)
    return 3.0 + x / (ax - y)


@njit(cache=True, inline="always")
def _push_group(sv, sx, sy, ms, g, v, x, y):
    """Peak-valley filtered push of (shear v, sigma x, tau y) onto group g's stack;
    ``OK`` or ``STACK_OVERFLOW``."""
    m = ms[g]
    if m >= 1 and sv[g, m - 1] == v:
        return OK  # plateau: the reversal stays at the first sample
    if m >= 2 and (sv[g, m - 1] - sv[g, m - 2]) * (v - sv[g, m - 1]) > 0.0:
        sv[g, m - 1] = v  # monotone continuation: the top was not a reversal
        sx[g, m - 1] = x
        sy[g, m - 1] = y
        return OK
    if m >= sv.shape[1]:
        return STACK_OVERFLOW
    sv[g, m] = v
    sx[g, m] = x
    sy[g, m] = y
    ms[g] = m + 1
    return OK


BATCH_FAST = {"reassoc", "nsz"}  # fastmath flags of the batch loops: sums, maxima reordered


@njit(cache=True, inline="always")
def _ipow(s, e):
    """s**e for an integer 0 <= e < 16 by branch-free squaring (vectorisable)."""
    s2 = s * s
    s4 = s2 * s2
    s8 = s4 * s4
    p = s if e & 1 else 1.0
    p = p * s2 if e & 2 else p
    p = p * s4 if e & 4 else p
    return p * s8 if e & 8 else p


@njit(cache=True, fastmath=BATCH_FAST)
def _miner_batch(S, cnt, n, seg_S_low, seg_m, seg_inv_a, S_cut):
    """sum_i cnt[i] / N(S[i]) over the first n entries (S in the curve's unit).

    Curves of one or two segments with integer slopes (DNV, threaded parts) take
    a branch-free vectorised loop; other curves go through ``sn_inverse_life``.
    """
    n_seg = seg_m.shape[0]
    m1 = seg_m[0]
    m2 = seg_m[n_seg - 1]
    if n_seg <= 2 and m1 == int(m1) and m2 == int(m2) and 0.0 <= m1 < 16.0 and 0.0 <= m2 < 16.0:
        Sd = seg_S_low[0]
        e1 = int(m1)
        e2 = int(m2)
        i1 = seg_inv_a[0]
        i2 = seg_inv_a[n_seg - 1]
        tot = 0.0
        for i in range(n):
            x = S[i]
            v = _ipow(x, e1) * i1 if x >= Sd else _ipow(x, e2) * i2
            tot += cnt[i] * (v if (x > 0.0 and x >= S_cut) else 0.0)
        return tot
    tot = 0.0
    for i in range(n):
        tot += cnt[i] * sn_inverse_life(S[i], seg_S_low, seg_m, seg_inv_a, S_cut)
    return tot


@njit(cache=True, inline="always")
def _max4(S, n):
    """max(0, S[0], ..., S[n-1]) with four running maxima (the single running
    maximum is a serial chain of compares: 2.9x slower here)."""
    m0 = 0.0
    m1 = 0.0
    m2 = 0.0
    m3 = 0.0
    n4 = n - n % 4
    for i in range(0, n4, 4):
        p0 = S[i]
        p1 = S[i + 1]
        p2 = S[i + 2]
        p3 = S[i + 3]
        m0 = p0 if p0 > m0 else m0
        m1 = p1 if p1 > m1 else m1
        m2 = p2 if p2 > m2 else m2
        m3 = p3 if p3 > m3 else m3
    for i in range(n4, n):
        p = S[i]
        m0 = p if p > m0 else m0
    m0 = m1 if m1 > m0 else m0
    m2 = m3 if m3 > m2 else m2
    return m2 if m2 > m0 else m0


@njit(cache=True, fastmath=BATCH_FAST)
def _equivalent_batch(crit, sc, n0, n1, n2, D, X1, Y1, X2, Y2, n, ca, cb, cc, s_scale, S):
    """Equivalent stress ranges of n buffered cycles of one member plane.

    Cycle i has shear range ``dtau = sc * D[i]`` and normal stress
    ``n0 x + n1 y + n2`` (n2: a constant stress on the plane, e.g. from mud
    pressure, Pa) at its turning instants (X1, Y1) and (X2, Y2), the larger
    of the two being ``snmax``. Writes ``S[i] = 2 sigma_eq s_scale`` (the S-N
    range) and returns the largest criterion parameter p (Pa):

    Matake-type (ca = f/t, cb = a = 2t/f - 1):
        p = (f/t) [dtau/2 + a max(snmax, 0)], sigma_eq = p.
    Findley (ca = k, cb = 2/(k + sqrt(1 + k^2))):
        p = dtau/2 + k snmax, sigma_eq = cb p (uniaxial calibration).
    Fatemi-Socie, stress form (ca = k, cb = 1/sigma_y):
        p = dtau/2 (1 + k max(snmax, 0)/sigma_y), sigma_eq = 2 p.
    Shear (Tresca-type, plane selection): p = dtau/2, sigma_eq = dtau.
    """
    # three loops: the criterion parameter p of each cycle (a map, vectorised),
    # its maximum (a separate reduction: fused, the max would keep the map
    # scalar), then the S-N range from p by the same expression as a fused loop
    if crit == CRIT_MATAKE:
        for i in range(n):
            a = n0 * X1[i] + n1 * Y1[i] + n2
            b = n0 * X2[i] + n1 * Y2[i] + n2
            sm = a if a > b else b
            sm = sm if sm > 0.0 else 0.0
            S[i] = ca * (0.5 * sc * D[i] + cb * sm)
    elif crit == CRIT_FINDLEY:
        for i in range(n):
            sm = max(n0 * X1[i] + n1 * Y1[i] + n2, n0 * X2[i] + n1 * Y2[i] + n2)
            S[i] = 0.5 * sc * D[i] + ca * sm
    elif crit == CRIT_FATEMI_SOCIE:
        for i in range(n):
            sm = max(max(n0 * X1[i] + n1 * Y1[i] + n2, n0 * X2[i] + n1 * Y2[i] + n2), 0.0)
            S[i] = 0.5 * sc * D[i] * (1.0 + ca * sm * cb)
    else:
        for i in range(n):
            S[i] = 0.5 * sc * D[i]
    pmax = _max4(S, n)
    if crit == CRIT_MATAKE:
        for i in range(n):
            S[i] = 2.0 * S[i] * s_scale
    elif crit == CRIT_FINDLEY:
        for i in range(n):
            S[i] = 2.0 * cb * S[i] * s_scale
    else:
        for i in range(n):
            S[i] = 4.0 * S[i] * s_scale
    return pmax


@njit(cache=True)
def _flush_group(g, buf, law, acc):
    """Damage of group g's buffered cycles on each member plane; empties the buffer.

    ``buf`` = (cyc_d, cyc_x1, cyc_y1, cyc_x2, cyc_y2, cyc_c, cyc_n, tmp_S): per group,
    the shear range, (sigma, tau) at the two turning instants and the count of
    each buffered cycle, the fill level, and scratch for the S-N ranges.
    ``law`` = (mem_ptr, mem_cand, mem_scale, cand_n, crit, ca, cb, cc, sel_crit,
    s_scale, seg_S_low, seg_m, seg_inv_a, S_cut) (see ``multiplane_damage``).
    ``acc`` = (acc_dmg, acc_sel, acc_par), per candidate.
    Member j has shear range ``mem_scale * dtau`` and normal stress
    ``cand_n[j, :2] . (sigma, tau) + cand_n[j, 2]`` at each cycle's two
    turning instants.
    """
    cyc_d, cyc_x1, cyc_y1, cyc_x2, cyc_y2, cyc_c, cyc_n, tmp_S = buf
    (mem_ptr, mem_cand, mem_scale, cand_n, crit, ca, cb, cc, sel_crit, s_scale, seg_S_low,
     seg_m, seg_inv_a, S_cut) = law
    acc_dmg, acc_sel, acc_par = acc
    n = cyc_n[g]
    if n == 0:
        return
    D = cyc_d[g]
    X1 = cyc_x1[g]
    Y1 = cyc_y1[g]
    X2 = cyc_x2[g]
    Y2 = cyc_y2[g]
    C = cyc_c[g]
    last_scale = -1.0
    last_sel = 0.0
    for k in range(mem_ptr[g], mem_ptr[g + 1]):
        j = mem_cand[k]
        sc = mem_scale[k]
        n0 = cand_n[j, 0]
        n1 = cand_n[j, 1]
        n2 = cand_n[j, 2]
        pm = _equivalent_batch(crit, sc, n0, n1, n2, D, X1, Y1, X2, Y2, n, ca, cb, cc, s_scale,
                               tmp_S)
        if pm > acc_par[j]:
            acc_par[j] = pm
        acc_dmg[j] += _miner_batch(tmp_S, C, n, seg_S_low, seg_m, seg_inv_a, S_cut)
        if sel_crit != crit:
            if sel_crit == CRIT_SHEAR and sc == last_scale:
                acc_sel[j] += last_sel  # shear selection depends on the range only
            else:
                _equivalent_batch(sel_crit, sc, n0, n1, n2, D, X1, Y1, X2, Y2, n, ca, cb,
                                  cc, s_scale, tmp_S)
                v = _miner_batch(tmp_S, C, n, seg_S_low, seg_m, seg_inv_a, S_cut)
                acc_sel[j] += v
                last_scale = sc
                last_sel = v
    cyc_n[g] = 0


@njit(cache=True, inline="always")
def _add_cycle(g, d, x1, y1, x2, y2, count, buf, law, acc):
    """Append one (half) cycle of group g to its buffer; a full buffer is flushed."""
    cyc_d, cyc_x1, cyc_y1, cyc_x2, cyc_y2, cyc_c, cyc_n, _ = buf
    k = cyc_n[g]
    cyc_d[g, k] = d
    cyc_x1[g, k] = x1
    cyc_y1[g, k] = y1
    cyc_x2[g, k] = x2
    cyc_y2[g, k] = y2
    cyc_c[g, k] = count
    cyc_n[g] = k + 1
    if k + 1 >= cyc_d.shape[1]:
        _flush_group(g, buf, law, acc)


@njit(cache=True, inline="always")
def _push_count(sv, sx, sy, ms, g, v, x, y, buf, law, acc):
    """Push (shear v, sigma x, tau y) on group g's stack, then 4-point rainflow:
    closed cycles go to the group's buffer. Returns the push status."""
    st = _push_group(sv, sx, sy, ms, g, v, x, y)
    m = ms[g]
    while m >= 4:
        s0 = sv[g, m - 4]
        s1 = sv[g, m - 3]
        s2 = sv[g, m - 2]
        s3 = sv[g, m - 1]
        d2 = abs(s2 - s1)
        if d2 <= abs(s1 - s0) and d2 <= abs(s3 - s2):
            _add_cycle(g, d2, sx[g, m - 3], sy[g, m - 3], sx[g, m - 2], sy[g, m - 2], 1.0,
                       buf, law, acc)
            sv[g, m - 3] = s3
            sx[g, m - 3] = sx[g, m - 1]
            sy[g, m - 3] = sy[g, m - 1]
            m -= 2
        else:
            break
    ms[g] = m
    return st


# samples per block of the per-sample stages: the fastest measured of
# 1024-8192 (docs/performance.md)
BLOCK = 2048
STACK_PAD = 9
CYCLE_BATCH = 256  # closed cycles buffered per group before their damage is evaluated
MASK_GROUPS = 62  # up to this many shear groups, reversals are sorted by a group bit mask
#: The damage law of ``multiplane_damage``: members of each shear group (group g
#: is ``mem_cand[mem_ptr[g]:mem_ptr[g + 1]]``, member ranges ``mem_scale`` times
#: the group's, > 0), the candidates' normal-stress coefficients on (sigma, tau)
#: and constant normal stress, Pa, ``cand_n`` (n_cand, 3), the
#: criterion for damage ``crit`` and for plane selection ``sel_crit`` with its
#: constants (ca, cb, cc) (see ``_equivalent_batch``), the factor ``s_scale``
#: from Pa to the S-N unit times the thickness correction, and the
#: S-N curve (seg_S_low, seg_m, seg_inv_a, S_cut) (see ``sn_inverse_life``).
DamageLaw = namedtuple("DamageLaw", ["mem_ptr", "mem_cand", "mem_scale", "cand_n", "crit",
                                     "ca", "cb", "cc", "sel_crit", "s_scale", "seg_S_low",
                                     "seg_m", "seg_inv_a", "S_cut"])
#: The shear groups' reversal geometry of ``multiplane_damage``: representative
#: shear coefficients ``grp_c`` (n_grp, 2) on (sigma, tau); the sorted
#: pseudo-angles ``bnd_pa`` (2 n_grp,) where some group's shear increment
#: changes sign, the first half B in [0, 2), the second B + 2 (the antipodes);
#: the group ``bnd_grp`` (2 n_grp,), int64, owning each.
ShearSectors = namedtuple("ShearSectors", ["grp_c", "bnd_pa", "bnd_grp"])


@njit(cache=True)
def _plane_stress(loads_T, k0, nb, a, b, tube, sgb, tab):
    """Plane stress (sigma, tau) of samples k0 .. k0 + nb - 1 into ``sgb[1:]``,
    ``tab[1:]``: one fused pass over the channels, vectorisable; tube surface
    points (``tube``: the other coefficients are zero) use three each.
    ``a``, ``b``: the point's load-to-stress rows, shape (6,)."""
    # the loops index views with the bare loop counter: an offset index such
    # as k0 + i or i + 1 is not provably >= 0, numba keeps its negative-index
    # wraparound and LLVM does not vectorise
    a0, a1, a2, a3, a4, a5 = a[0], a[1], a[2], a[3], a[4], a[5]
    b0, b1, b2, b3, b4, b5 = b[0], b[1], b[2], b[3], b[4], b[5]
    x0 = loads_T[0][k0:k0 + nb]
    x1 = loads_T[1][k0:k0 + nb]
    x2 = loads_T[2][k0:k0 + nb]
    x3 = loads_T[3][k0:k0 + nb]
    x4 = loads_T[4][k0:k0 + nb]
    x5 = loads_T[5][k0:k0 + nb]
    s_new = sgb[1:nb + 1]
    t_new = tab[1:nb + 1]
    if tube:
        for i in range(nb):
            s_new[i] = a0 * x0[i] + a3 * x3[i] + a4 * x4[i]
            t_new[i] = b1 * x1[i] + b2 * x2[i] + b5 * x5[i]
    else:
        for i in range(nb):
            s_new[i] = a0 * x0[i] + a1 * x1[i] + a2 * x2[i] + a3 * x3[i] \
                + a4 * x4[i] + a5 * x5[i]
            t_new[i] = b0 * x0[i] + b1 * x1[i] + b2 * x2[i] + b3 * x3[i] \
                + b4 * x4[i] + b5 * x5[i]
    return 0


@njit(cache=True, error_model="numpy")
def _sectors(bnd_pa, nb, sgb, tab, pab, paf, secb):
    """Pseudo-angle ``pab`` of each of the block's nb increment directions (-1:
    no change), branch-free so that it vectorises, folded to [0, 2) in ``paf``
    (the boundaries come in antipodal pairs, pa and pa + 2); its sector
    ``secb`` = the number of boundaries below it (boundary-outer loop over the
    first half, vectorisable, four boundaries per pass: a quarter of the loads
    and stores)."""
    n_half = bnd_pa.shape[0] // 2
    s_new = sgb[1:nb + 1]
    t_new = tab[1:nb + 1]
    s_old = sgb[0:nb]
    t_old = tab[0:nb]
    for i in range(nb):
        dx = s_new[i] - s_old[i]
        dy = t_new[i] - t_old[i]
        den = abs(dx) + abs(dy)
        r = dx / den
        q = 1.0 - r if dy >= 0.0 else 3.0 + r
        q = q if den != 0.0 else -1.0
        pab[i] = q
        up = q >= 2.0
        paf[i] = q - 2.0 if up else q
        secb[i] = n_half if up else 0
    ib = 0
    while ib + 4 <= n_half:
        bp0 = bnd_pa[ib]
        bp1 = bnd_pa[ib + 1]
        bp2 = bnd_pa[ib + 2]
        bp3 = bnd_pa[ib + 3]
        for i in range(nb):
            f = paf[i]
            secb[i] += ((1 if f > bp0 else 0) + (1 if f > bp1 else 0)
                        + (1 if f > bp2 else 0) + (1 if f > bp3 else 0))
        ib += 4
    while ib < n_half:
        bp = bnd_pa[ib]
        for i in range(nb):
            secb[i] += 1 if paf[i] > bp else 0
        ib += 1
    return 0


@njit(cache=True)
def _sector_masks(bnd_grp, use_mask):
    """Sector masks, shape (n_b + 1,), int64: bit g of ``smask[s]`` is the parity of
    group g's boundaries below sector s; a change of sector crosses (along the
    short arc) exactly the groups whose bits differ, each once (the long arc
    crosses the other boundary of each: the same parity). Zeros unless
    ``use_mask`` (at most ``MASK_GROUPS`` groups)."""
    n_b = bnd_grp.shape[0]
    smask = np.zeros(n_b + 1, dtype=np.int64)
    if use_mask:
        for s in range(1, n_b + 1):
            smask[s] = smask[s - 1] ^ (1 << bnd_grp[s - 1])
    return smask


@njit(cache=True)
def _changes_masked(smask, nb, secb, pab, chg_i, chg_m, cmask, cur):
    """Mask mode: branch-free compaction of the block's samples where the sector
    mask changes into ``chg_i``, the groups each change reverses as the bits of
    ``chg_m`` (``smask[n_b] = smask[0]``: no folding; masks of two sectors
    differ iff the sectors do). ``cmask``, ``cur``: mask and state (-1: no
    increment yet, else 0) before the block. Returns (changes, cmask, cur)."""
    nch = 0
    for i in range(nb):
        sm = smask[secb[i]]
        sm = cmask if pab[i] < 0.0 else sm  # no increment: it stays
        xm = sm ^ cmask
        chg_i[nch] = i
        chg_m[nch] = xm
        nch += (xm != 0) & (cur >= 0)  # bitwise: no branch
        cur = 0 if pab[i] >= 0.0 else cur
        cmask = sm
    return nch, cmask, cur


@njit(cache=True)
def _changes_walked(n_b, nb, secb, pab, chg_i, cur):
    """Walk mode: the block's samples where the sector changes, into ``chg_i``;
    ``secb`` becomes each sample's sector (no increment: it stays). ``cur``:
    the sector before the block (-1: none yet). Returns (changes, cur)."""
    nch = 0
    for i in range(nb):
        s = secb[i]
        s = 0 if s >= n_b else s
        s = cur if pab[i] < 0.0 else s  # no increment: the sector stays
        secb[i] = s
        chg_i[nch] = i
        nch += 1 if (s != cur and cur >= 0) else 0
        cur = s
    return nch, cur


@njit(cache=True)
def _reversals_masked(nch, chg_i, chg_m, rev_i, rev_n):
    """Mask mode: each group's list of reversal samples (``rev_i[g, :rev_n[g]]``),
    in time order (a change crosses each group at most once, so a list holds
    <= nb samples): one branch-free compaction of the change list per group,
    three groups per pass over the list (a third of its loads)."""
    n_g = rev_n.shape[0]
    chq = chg_i[:nch]
    cmq = chg_m[:nch]
    g = 0
    while g + 3 <= n_g:
        r0 = rev_i[g]
        r1 = rev_i[g + 1]
        r2 = rev_i[g + 2]
        n0 = 0
        n1 = 0
        n2 = 0
        for q in range(nch):
            c = chq[q]
            xq = cmq[q] >> g
            r0[n0] = c
            r1[n1] = c
            r2[n2] = c
            n0 += xq & 1
            n1 += (xq >> 1) & 1
            n2 += (xq >> 2) & 1
        rev_n[g] = n0
        rev_n[g + 1] = n1
        rev_n[g + 2] = n2
        g += 3
    while g < n_g:
        r0 = rev_i[g]
        n0 = 0
        for q in range(nch):
            r0[n0] = chq[q]
            n0 += (cmq[q] >> g) & 1
        rev_n[g] = n0
        g += 1
    return 0


@njit(cache=True)
def _reversals_walked(bnd_grp, nch, cur0, secb, chg_i, rev_i, rev_n):
    """Walk mode: each group's list of reversal samples, in time order, by
    walking the boundaries on the short arc of each sector change (``cur0``:
    the sector before the block)."""
    n_b = bnd_grp.shape[0]
    for g in range(rev_n.shape[0]):
        rev_n[g] = 0
    for q in range(nch):
        i = chg_i[q]
        s = secb[i]
        prev = secb[i - 1] if i > 0 else cur0
        f = s - prev
        if f < 0:
            f += n_b
        if 2 * f <= n_b:
            i0 = prev
            cnt = f
        else:
            i0 = s
            cnt = n_b - f
        for r in range(cnt):
            ib = i0 + r
            if ib >= n_b:
                ib -= n_b
            g = bnd_grp[ib]
            rev_i[g, rev_n[g]] = i
            rev_n[g] += 1
    return 0


@njit(cache=True)
def _close_groups(grp_c, x, y, residue_mode, sv, sx, sy, ms, buf, law, acc):
    """The last sample (sigma x, tau y) closes every group's sequence; each
    residue is closed (half cycles, or repeated once) and every buffer is
    evaluated. Returns the OR of the push codes."""
    st = OK
    for g in range(grp_c.shape[0]):
        st |= _push_count(sv, sx, sy, ms, g, grp_c[g, 0] * x + grp_c[g, 1] * y, x, y, buf, law,
                          acc)
        m = ms[g]
        if residue_mode == RESIDUE_HALF:
            for i in range(m - 1):
                _add_cycle(g, abs(sv[g, i + 1] - sv[g, i]), sx[g, i], sy[g, i],
                           sx[g, i + 1], sy[g, i + 1], 0.5, buf, law, acc)
        elif residue_mode == RESIDUE_REPEAT:
            rv = sv[g, :m].copy()
            rx = sx[g, :m].copy()
            ry = sy[g, :m].copy()
            for i in range(m):
                st |= _push_count(sv, sx, sy, ms, g, rv[i], rx[i], ry[i], buf, law, acc)
        _flush_group(g, buf, law, acc)
    return st


@njit(cache=True, parallel=True, error_model="numpy")
def multiplane_damage(loads_T, coef_sig, coef_tau, sectors, law, residue_mode, stack_cap,
                      out_dmg, out_sel, out_par):
    """Miner damage on every candidate plane of every surface point.

    For each surface point p the plane stress (sigma, tau) is formed from the
    loads. Candidates whose resolved-shear coefficients are parallel (e.g. a
    plane and its conjugate at 90 deg, whose shear is exactly opposite) form a
    shear group: one representative shear ``grp_c[g] @ (sigma, tau)`` is
    rainflow counted once (rainflow of -y or of c y, c > 0, gives the same
    cycles at the same instants), and every member j gets the cycle with range
    ``mem_scale * dtau`` and its own normal stress
    ``cand_n[j, :2] @ (sigma, tau) + cand_n[j, 2]`` at the two turning instants
    (the constant term carries stresses fixed over the window, e.g. the Lame
    hoop and radial stresses of mud pressure; a constant shear on a plane does
    not change its cycles, so it needs no term).

    Instead of a reversal search per group, each increment's direction in the
    (sigma, tau) plane gets its sector among the sorted directions ``bnd_pa``
    where some group's shear increment changes sign; a sample is a reversal of
    exactly the groups whose boundary lies on the short arc between the
    previous and the new sector. Blocks of ``BLOCK`` samples go through
    vectorised stages (``_plane_stress``, ``_sectors``, ``_changes_*``,
    ``_reversals_*``: by a bit mask per sector up to ``MASK_GROUPS`` groups,
    else by walking the arc) to one list of reversal samples per group, which
    then goes through that group's 4-point rainflow stack (shear, sigma, tau
    at each reversal) in one tight loop: the same cycles in the same order as
    a sample-by-sample walk. Closed cycles are buffered per group and evaluated
    in vectorised batches (``_flush_group``). The result equals a per-plane
    reversal search and rainflow (exact values, no binning; batch sums are
    reassociated).

    Parameters
    ----------
    loads_T : ndarray, shape (6, n_time), C-contiguous
        Internal loads, N and N m, one row per channel.
    coef_sig, coef_tau : ndarray, shape (n_points, 6)
        Load-to-stress maps (Pa per N or N m), from ``surface_coefficients``.
    sectors : ShearSectors
        Shear groups and their sign-change boundaries (see :data:`ShearSectors`).
    law : DamageLaw
        Group members, normal stresses, criteria and S-N curve (see
        :data:`DamageLaw`).
    residue_mode : int
        RESIDUE_HALF or RESIDUE_REPEAT.
    stack_cap : int
        Capacity of each group's residue stack.
    out_dmg, out_sel, out_par : ndarray, shape (n_points, n_cand)
        Damage, plane-selection damage and max criterion parameter (Pa);
        candidates in no group (zero shear) get 0.

    Returns
    -------
    int
        ``OK`` or ``STACK_OVERFLOW``.
    """
    grp_c, bnd_pa, bnd_grp = sectors
    (mem_ptr, mem_cand, mem_scale, cand_n, crit, ca, cb, cc, sel_crit, s_scale, seg_S_low,
     seg_m, seg_inv_a, S_cut) = law
    n_t = loads_T.shape[1]
    n_p = coef_sig.shape[0]
    n_g = grp_c.shape[0]
    n_c = cand_n.shape[0]
    n_b = bnd_pa.shape[0]
    status = np.zeros(n_p, dtype=np.int64)
    use_mask = n_g <= MASK_GROUPS
    smask = _sector_masks(bnd_grp, use_mask)
    for p in prange(n_p):
        # rows padded by an odd number of doubles: the tops of the groups' stacks
        # do not all fall into one cache set (a power-of-two row stride would)
        sv = np.empty((n_g, stack_cap + STACK_PAD))
        sx = np.empty((n_g, stack_cap + STACK_PAD))
        sy = np.empty((n_g, stack_cap + STACK_PAD))
        ms = np.zeros(n_g, dtype=np.int64)
        sgb = np.empty(BLOCK + 1)
        tab = np.empty(BLOCK + 1)
        pab = np.empty(BLOCK)
        chg_i = np.empty(BLOCK, dtype=np.int64)
        chg_m = np.empty(BLOCK, dtype=np.int64)
        rev_i = np.empty((n_g, BLOCK), dtype=np.int64)
        rev_n = np.zeros(n_g, dtype=np.int64)
        secb = np.empty(BLOCK, dtype=np.int64)
        paf = np.empty(BLOCK)
        cyc_d = np.empty((n_g, CYCLE_BATCH + STACK_PAD))
        cyc_x1 = np.empty((n_g, CYCLE_BATCH + STACK_PAD))
        cyc_y1 = np.empty((n_g, CYCLE_BATCH + STACK_PAD))
        cyc_x2 = np.empty((n_g, CYCLE_BATCH + STACK_PAD))
        cyc_y2 = np.empty((n_g, CYCLE_BATCH + STACK_PAD))
        cyc_c = np.empty((n_g, CYCLE_BATCH + STACK_PAD))
        cyc_n = np.zeros(n_g, dtype=np.int64)
        tmp_S = np.empty(CYCLE_BATCH + STACK_PAD)
        acc_dmg = np.zeros(n_c)
        acc_sel = np.zeros(n_c)
        acc_par = np.zeros(n_c)
        buf = (cyc_d, cyc_x1, cyc_y1, cyc_x2, cyc_y2, cyc_c, cyc_n, tmp_S)
        lawt = (mem_ptr, mem_cand, mem_scale, cand_n, crit, ca, cb, cc, sel_crit, s_scale,
                seg_S_low, seg_m, seg_inv_a, S_cut)
        acc = (acc_dmg, acc_sel, acc_par)
        a = coef_sig[p]
        b = coef_tau[p]
        tube = a[1] == 0.0 and a[2] == 0.0 and a[5] == 0.0 and b[0] == 0.0 and b[3] == 0.0 \
            and b[4] == 0.0
        _plane_stress(loads_T, 0, 1, a, b, False, sgb, tab)  # sample 0, all six terms
        sgb[0] = sgb[1]
        tab[0] = tab[1]
        st = OK  # OR of the pushes' codes: STACK_OVERFLOW is the only failure they return
        for g in range(n_g):
            st |= _push_group(sv, sx, sy, ms, g, grp_c[g, 0] * sgb[0] + grp_c[g, 1] * tab[0],
                              sgb[0], tab[0])
        cur = -1  # sector of the last increment direction (-1: none yet; 0 in mask mode)
        cmask = 0  # its sector mask (mask mode)
        for k0 in range(1, n_t, BLOCK):
            nb = min(BLOCK, n_t - k0)
            # per-sample stages, vectorised over the block: plane stress,
            # pseudo-angle and sector of each increment direction, the samples
            # where the sector changes, each group's list of reversal samples
            _plane_stress(loads_T, k0, nb, a, b, tube, sgb, tab)
            _sectors(bnd_pa, nb, sgb, tab, pab, paf, secb)
            if use_mask:
                nch, cmask, cur = _changes_masked(smask, nb, secb, pab, chg_i, chg_m, cmask,
                                                  cur)
                _reversals_masked(nch, chg_i, chg_m, rev_i, rev_n)
            else:
                cur0 = cur  # the sector before the block (for its first change)
                nch, cur = _changes_walked(n_b, nb, secb, pab, chg_i, cur)
                _reversals_walked(bnd_grp, nch, cur0, secb, chg_i, rev_i, rev_n)
            # one group at a time, its reversals through its rainflow stack
            for g in range(n_g):
                c0 = grp_c[g, 0]
                c1 = grp_c[g, 1]
                for q in range(rev_n[g]):
                    i = rev_i[g, q]
                    x = sgb[i]
                    y = tab[i]
                    st |= _push_count(sv, sx, sy, ms, g, c0 * x + c1 * y, x, y, buf, lawt, acc)
            sgb[0] = sgb[nb]
            tab[0] = tab[nb]
        # the last sample closes every group's sequence
        st |= _close_groups(grp_c, sgb[0], tab[0], residue_mode, sv, sx, sy, ms, buf, lawt, acc)
        for j in range(n_c):
            out_dmg[p, j] = acc_dmg[j]
            out_sel[p, j] = acc_dmg[j] if sel_crit == crit else acc_sel[j]
            out_par[p, j] = acc_par[j]
        status[p] = st
    for p in range(n_p):
        if status[p] != OK:
            return STACK_OVERFLOW
    return OK


@njit(cache=True, parallel=True)
def channels_of(loads, out):
    """Transpose loads (n_time, 6) into contiguous channels ``out`` (6, n_time).

    Blocks of ``BLOCK`` samples run in parallel; each block is read once and written
    to the six channel rows (about 2x faster than numpy's strided copy here).
    """
    n = loads.shape[0]
    n_ch = loads.shape[1]
    n_blk = (n + BLOCK - 1) // BLOCK
    for b in prange(n_blk):
        i0 = b * BLOCK
        i1 = min(n, i0 + BLOCK)
        for c in range(n_ch):
            o = out[c]
            for i in range(i0, i1):
                o[i] = loads[i, c]
    return 0


@njit(cache=True)
def pseudo_angles(x, y, out):
    """Vectorised ``_pseudo_angle`` (for building boundaries in the wrapper)."""
    for i in range(x.shape[0]):
        out[i] = _pseudo_angle(x[i], y[i])
    return 0

