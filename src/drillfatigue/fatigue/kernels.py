"""Numba kernels of the fatigue chain: indexed rainflow and multi-plane damage.

Plain functions on float64 arrays in SI (stresses in Pa), importing only numpy,
numba and math. They write into preallocated ``out`` arrays and return an
integer status (>= 0 success, < 0 error); the Python wrappers in
:mod:`drillfatigue.fatigue.rainflow` and :mod:`drillfatigue.fatigue.critical_plane`
raise.

Rainflow here is the 4-point method on exact (unbinned) reversals
(Amzallag et al., Int. J. Fatigue 16 (1994) 287-293; ISO 12110-2), with the
residue closed either as half cycles (ASTM E1049-85 (2017) section 5.4.4
equivalent: each adjacent pair of the residue is a half cycle) or by repeating
the residue once (fatpack's ``find_rainflow_ranges`` convention).

Status codes: 0 ok, -1 residue stack overflow (wrapper retries with a larger
capacity), -2 output capacity exceeded.
"""

from __future__ import annotations

import numpy as np
from numba import njit, prange

RESIDUE_HALF = 0
RESIDUE_REPEAT = 1
RESIDUE_NONE = 2  # keep the residue open (streaming; caller carries it)

CRIT_MATAKE = 0
CRIT_FINDLEY = 1
CRIT_FATEMI_SOCIE = 2
CRIT_SHEAR = 3  # Tresca-type: equivalent amplitude = shear range (plane selection)

STATUS_OK = 0
STATUS_STACK_OVERFLOW = -1
STATUS_OUT_OVERFLOW = -2


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
        Number of cycles written (>= 0) or a negative status.
    """
    n = y.shape[0]
    stk = np.empty(2 * n + 2, dtype=np.int64)
    m = 0
    nc = 0
    cap = out_from.shape[0]
    for k in range(n):
        m = _push_index(y, stk, m, k)
        while m >= 4:
            s0 = y[stk[m - 4]]
            s1 = y[stk[m - 3]]
            s2 = y[stk[m - 2]]
            s3 = y[stk[m - 1]]
            d2 = abs(s2 - s1)
            if d2 <= abs(s1 - s0) and d2 <= abs(s3 - s2):
                if nc >= cap:
                    return STATUS_OUT_OVERFLOW
                out_from[nc] = stk[m - 3]
                out_to[nc] = stk[m - 2]
                out_count[nc] = 1.0
                nc += 1
                stk[m - 3] = stk[m - 1]
                m -= 2
            else:
                break
    out_residue[0] = m
    for i in range(m):
        out_residue[i + 1] = stk[i]
    if residue_mode == RESIDUE_HALF:
        for i in range(m - 1):
            if nc >= cap:
                return STATUS_OUT_OVERFLOW
            out_from[nc] = stk[i]
            out_to[nc] = stk[i + 1]
            out_count[nc] = 0.5
            nc += 1
    elif residue_mode == RESIDUE_REPEAT:
        res = stk[:m].copy()
        for i in range(res.shape[0]):
            m = _push_index(y, stk, m, res[i])
            while m >= 4:
                s0 = y[stk[m - 4]]
                s1 = y[stk[m - 3]]
                s2 = y[stk[m - 2]]
                s3 = y[stk[m - 1]]
                d2 = abs(s2 - s1)
                if d2 <= abs(s1 - s0) and d2 <= abs(s3 - s2):
                    if nc >= cap:
                        return STATUS_OUT_OVERFLOW
                    out_from[nc] = stk[m - 3]
                    out_to[nc] = stk[m - 2]
                    out_count[nc] = 1.0
                    nc += 1
                    stk[m - 3] = stk[m - 1]
                    m -= 2
                else:
                    break
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


@njit(cache=True)
def _equivalent(crit, dtau, sn1, sn2, ca, cb, cc):
    """Criterion parameter (Pa) and equivalent tension amplitude (Pa) of one cycle.

    Matake-type (ca = f/t, cb = a = 2t/f - 1):
        p = (f/t) [dtau/2 + a max(sn1, sn2, 0)], sigma_eq = p.
    Findley (ca = k, cb = 2/(k + sqrt(1 + k^2))):
        p = dtau/2 + k max(sn1, sn2), sigma_eq = cb p (uniaxial calibration).
    Fatemi-Socie, stress form (ca = k, cb = 1/sigma_y):
        p = dtau/2 (1 + k max(sn1, sn2, 0)/sigma_y), sigma_eq = 2 p.
    Shear (Tresca-type): p = dtau/2, sigma_eq = dtau.
    """
    snmax = sn1 if sn1 > sn2 else sn2
    if crit == CRIT_MATAKE:
        p = ca * (0.5 * dtau + cb * (snmax if snmax > 0.0 else 0.0))
        return p, p
    elif crit == CRIT_FINDLEY:
        p = 0.5 * dtau + ca * snmax
        return p, cb * p
    elif crit == CRIT_FATEMI_SOCIE:
        p = 0.5 * dtau * (1.0 + ca * (snmax if snmax > 0.0 else 0.0) * cb)
        return p, 2.0 * p
    else:
        return 0.5 * dtau, dtau


@njit(cache=True, inline="always")
def _pseudo_angle(x, y):
    """Monotone pseudo-angle of the direction (x, y) in [0, 4)."""
    ax = abs(x)
    if y >= 0.0:
        return 1.0 - x / (ax + y)
    return 3.0 + x / (ax - y)


@njit(cache=True)
def _sector(pa, bnd):
    """Number of boundaries with pseudo-angle < pa (binary search), mod len."""
    lo = 0
    hi = bnd.shape[0]
    while lo < hi:
        mid = (lo + hi) >> 1
        if bnd[mid] < pa:
            lo = mid + 1
        else:
            hi = mid
    if lo == bnd.shape[0]:
        return 0
    return lo


CYCLE_BUFFER = 8192


@njit(cache=True)
def _flush(p, buf_j, buf_d, buf_n1, buf_n2, buf_c, nbuf, crit, ca, cb, cc, s_scale, seg_S_low,
           seg_m, seg_inv_a, S_cut, sel_crit, out_dmg, out_sel, out_par):
    """Damage of the buffered cycles of point p (equivalent stress, S-N, Miner)."""
    for i in range(nbuf[0]):
        j = buf_j[i]
        dtau = buf_d[i]
        count = buf_c[i]
        par, seq = _equivalent(crit, dtau, buf_n1[i], buf_n2[i], ca, cb, cc)
        if seq > 0.0:
            out_dmg[p, j] += count * sn_inverse_life(2.0 * seq * s_scale, seg_S_low, seg_m,
                                                     seg_inv_a, S_cut)
        if par > out_par[p, j]:
            out_par[p, j] = par
        if sel_crit != crit:
            _, sq2 = _equivalent(sel_crit, dtau, buf_n1[i], buf_n2[i], ca, cb, cc)
            if sq2 > 0.0:
                out_sel[p, j] += count * sn_inverse_life(2.0 * sq2 * s_scale, seg_S_low, seg_m,
                                                         seg_inv_a, S_cut)
    nbuf[0] = 0


@njit(cache=True, inline="always")
def _push_value(sv, sn, ms, j, v, nv):
    """Peak-valley filtered push of (shear v, normal nv) onto candidate j's stack."""
    m = ms[j]
    if m >= 1 and sv[j, m - 1] == v:
        return 0
    if m >= 2 and (sv[j, m - 1] - sv[j, m - 2]) * (v - sv[j, m - 1]) > 0.0:
        sv[j, m - 1] = v
        sn[j, m - 1] = nv
        return 0
    if m >= sv.shape[1]:
        return STATUS_STACK_OVERFLOW
    sv[j, m] = v
    sn[j, m] = nv
    ms[j] = m + 1
    return 0


@njit(cache=True, inline="always")
def _four_point(sv, sn, ms, j, buf_j, buf_d, buf_n1, buf_n2, buf_c, nbuf):
    """4-point rainflow on candidate j's stack; closed cycles go to the buffer."""
    m = ms[j]
    while m >= 4:
        s0 = sv[j, m - 4]
        s1 = sv[j, m - 3]
        s2 = sv[j, m - 2]
        s3 = sv[j, m - 1]
        d2 = abs(s2 - s1)
        if d2 <= abs(s1 - s0) and d2 <= abs(s3 - s2):
            k = nbuf[0]
            buf_j[k] = j
            buf_d[k] = d2
            buf_n1[k] = sn[j, m - 3]
            buf_n2[k] = sn[j, m - 2]
            buf_c[k] = 1.0
            nbuf[0] = k + 1
            sv[j, m - 3] = s3
            sn[j, m - 3] = sn[j, m - 1]
            m -= 2
        else:
            break
    ms[j] = m


BLOCK = 4096


@njit(cache=True, parallel=True)
def multiplane_damage(loads_T, coef_sig, coef_tau, cand_c, cand_n, bnd_pa, bnd_cand, lut_lo,
                      lut_hi, crit, ca, cb, cc, sel_crit, s_scale, seg_S_low, seg_m, seg_inv_a,
                      S_cut, residue_mode, stack_cap, out_dmg, out_sel, out_par):
    """Miner damage on every candidate plane of every surface point.

    For each surface point p the plane stress (sigma, tau) is formed from the
    loads; the resolved shear on candidate j is ``cand_c[j] @ (sigma, tau)`` and
    the normal stress ``cand_n[j] @ (sigma, tau)``. Instead of a reversal search
    per plane, each increment's direction in the (sigma, tau) plane is located
    (pseudo-angle; while it stays inside the current sector nothing is done,
    otherwise a look-up table ``lut_lo/lut_hi`` over pseudo-angle bins with an
    exact search only in bins holding a boundary) among the sorted directions
    ``bnd_pa`` where some candidate's shear increment changes sign; a sample is
    a reversal of exactly the candidates whose boundary lies on the short arc
    between the previous and the new increment direction. The per-sample stage
    runs over blocks of ``BLOCK`` samples with contiguous per-channel loads;
    only direction changes reach the sequential stage. Each candidate keeps its
    own 4-point rainflow stack; each closed cycle gets the criterion's
    equivalent stress from its shear range and the normal stress at its two
    turning instants, and Miner damage 1/N from the S-N curve. The result
    equals a per-plane reversal search and rainflow (exact values, no binning).

    Parameters
    ----------
    loads_T : ndarray, shape (6, n_time), C-contiguous
        Internal loads, N and N m, one row per channel.
    coef_sig, coef_tau : ndarray, shape (n_points, 6)
        Load-to-stress maps (Pa per N or N m), from ``surface_coefficients``.
    cand_c, cand_n : ndarray, shape (n_cand, 2)
        Shear and normal stress coefficients of each candidate on (sigma, tau).
    bnd_pa : ndarray, shape (n_bnd,)
        Sorted pseudo-angles of the sign-change directions (n_bnd >= 1).
    bnd_cand : ndarray, shape (n_bnd,), int64
        Candidate owning each boundary.
    lut_lo, lut_hi : ndarray, shape (n_bins,), int64
        Number of boundaries below the start / end of each pseudo-angle bin.
    crit, sel_crit : int
        Criterion for damage and for plane selection (CRIT_*).
    ca, cb, cc : float
        Criterion constants (see ``_equivalent``).
    s_scale : float
        Factor from Pa to the S-N curve unit, times the thickness correction.
    seg_S_low, seg_m, seg_inv_a, S_cut
        S-N curve (see ``sn_inverse_life``).
    residue_mode : int
        RESIDUE_HALF or RESIDUE_REPEAT.
    stack_cap : int
        Capacity of each candidate's residue stack.
    out_dmg, out_sel, out_par : ndarray, shape (n_points, n_cand)
        Damage, plane-selection damage and max criterion parameter (Pa); zeroed
        here.

    Returns
    -------
    int
        0 or STATUS_STACK_OVERFLOW.
    """
    n_t = loads_T.shape[1]
    n_p = coef_sig.shape[0]
    n_c = cand_c.shape[0]
    n_b = bnd_pa.shape[0]
    n_bins = lut_lo.shape[0]
    bin_scale = n_bins / 4.0
    status = np.zeros(n_p, dtype=np.int64)
    for p in prange(n_p):
        sv = np.empty((n_c, stack_cap))
        sn = np.empty((n_c, stack_cap))
        ms = np.zeros(n_c, dtype=np.int64)
        sgb = np.empty(BLOCK + 1)
        tab = np.empty(BLOCK + 1)
        pab = np.empty(BLOCK)
        bcap = CYCLE_BUFFER + stack_cap
        buf_j = np.empty(bcap, dtype=np.int64)
        buf_d = np.empty(bcap)
        buf_n1 = np.empty(bcap)
        buf_n2 = np.empty(bcap)
        buf_c = np.empty(bcap)
        nbuf = np.zeros(1, dtype=np.int64)
        for j in range(n_c):
            out_dmg[p, j] = 0.0
            out_sel[p, j] = 0.0
            out_par[p, j] = 0.0
        a0 = coef_sig[p, 0]
        a1 = coef_sig[p, 1]
        a2 = coef_sig[p, 2]
        a3 = coef_sig[p, 3]
        a4 = coef_sig[p, 4]
        a5 = coef_sig[p, 5]
        b0 = coef_tau[p, 0]
        b1 = coef_tau[p, 1]
        b2 = coef_tau[p, 2]
        b3 = coef_tau[p, 3]
        b4 = coef_tau[p, 4]
        b5 = coef_tau[p, 5]
        L0 = loads_T[0]
        L1 = loads_T[1]
        L2 = loads_T[2]
        L3 = loads_T[3]
        L4 = loads_T[4]
        L5 = loads_T[5]
        sgb[0] = a0 * L0[0] + a1 * L1[0] + a2 * L2[0] + a3 * L3[0] + a4 * L4[0] + a5 * L5[0]
        tab[0] = b0 * L0[0] + b1 * L1[0] + b2 * L2[0] + b3 * L3[0] + b4 * L4[0] + b5 * L5[0]
        st = 0
        for j in range(n_c):
            st |= _push_value(sv, sn, ms, j, cand_c[j, 0] * sgb[0] + cand_c[j, 1] * tab[0],
                              cand_n[j, 0] * sgb[0] + cand_n[j, 1] * tab[0])
        cur = -1
        wrap = False
        lo_pa = 1.0
        hi_pa = 0.0  # empty interval: the first direction always goes to the search
        b_first = bnd_pa[0]
        b_last = bnd_pa[n_b - 1]
        for k0 in range(1, n_t, BLOCK):
            nb = min(BLOCK, n_t - k0)
            # stage 1a: plane stress of the block (channel-outer loops, vectorisable;
            # only the channels with a non-zero coefficient are visited)
            for i in range(nb):
                sgb[i + 1] = 0.0
                tab[i + 1] = 0.0
            for c in range(6):
                ac = coef_sig[p, c]
                if ac != 0.0:
                    Lc = loads_T[c]
                    for i in range(nb):
                        sgb[i + 1] += ac * Lc[k0 + i]
                bc = coef_tau[p, c]
                if bc != 0.0:
                    Lc = loads_T[c]
                    for i in range(nb):
                        tab[i + 1] += bc * Lc[k0 + i]
            # stage 1b: pseudo-angle of each increment direction (-1: no change)
            for i in range(nb):
                dx = sgb[i + 1] - sgb[i]
                dy = tab[i + 1] - tab[i]
                den = abs(dx) + abs(dy)
                if den == 0.0:
                    pab[i] = -1.0
                elif dy >= 0.0:
                    pab[i] = 1.0 - dx / den
                else:
                    pab[i] = 3.0 + dx / den
            # stage 2: direction changes -> reversals of the crossed candidates
            for i in range(nb):
                pa = pab[i]
                if pa < 0.0:
                    continue
                if wrap:
                    if pa <= b_first or pa > b_last:
                        continue
                elif pa > lo_pa and pa <= hi_pa:
                    continue
                b = int(pa * bin_scale)
                if b >= n_bins:
                    b = n_bins - 1
                s = lut_lo[b]
                hi = lut_hi[b]
                while s < hi and bnd_pa[s] < pa:
                    s += 1
                if s >= n_b:
                    s = 0
                if cur >= 0 and s != cur:
                    f = s - cur
                    if f < 0:
                        f += n_b
                    if 2 * f <= n_b:
                        i0 = cur
                        cnt = f
                    else:
                        i0 = s
                        cnt = n_b - f
                    x = sgb[i]
                    y = tab[i]
                    for q in range(cnt):
                        ib = i0 + q
                        if ib >= n_b:
                            ib -= n_b
                        j = bnd_cand[ib]
                        st |= _push_value(sv, sn, ms, j, cand_c[j, 0] * x + cand_c[j, 1] * y,
                                          cand_n[j, 0] * x + cand_n[j, 1] * y)
                        _four_point(sv, sn, ms, j, buf_j, buf_d, buf_n1, buf_n2, buf_c, nbuf)
                        if nbuf[0] >= CYCLE_BUFFER:
                            _flush(p, buf_j, buf_d, buf_n1, buf_n2, buf_c, nbuf, crit, ca, cb, cc,
                                   s_scale, seg_S_low, seg_m, seg_inv_a, S_cut, sel_crit,
                                   out_dmg, out_sel, out_par)
                cur = s
                wrap = s == 0
                if not wrap:
                    lo_pa = bnd_pa[s - 1]
                    hi_pa = bnd_pa[s]
            sgb[0] = sgb[nb]
            tab[0] = tab[nb]
        # last sample closes every candidate's sequence
        x = sgb[0]
        y = tab[0]
        for j in range(n_c):
            st |= _push_value(sv, sn, ms, j, cand_c[j, 0] * x + cand_c[j, 1] * y,
                              cand_n[j, 0] * x + cand_n[j, 1] * y)
            _four_point(sv, sn, ms, j, buf_j, buf_d, buf_n1, buf_n2, buf_c, nbuf)
            m = ms[j]
            if residue_mode == RESIDUE_HALF:
                for i in range(m - 1):
                    k = nbuf[0]
                    buf_j[k] = j
                    buf_d[k] = abs(sv[j, i + 1] - sv[j, i])
                    buf_n1[k] = sn[j, i]
                    buf_n2[k] = sn[j, i + 1]
                    buf_c[k] = 0.5
                    nbuf[0] = k + 1
                    if nbuf[0] >= CYCLE_BUFFER:
                        _flush(p, buf_j, buf_d, buf_n1, buf_n2, buf_c, nbuf, crit, ca, cb, cc,
                               s_scale, seg_S_low, seg_m, seg_inv_a, S_cut, sel_crit, out_dmg,
                               out_sel, out_par)
            elif residue_mode == RESIDUE_REPEAT:
                rv = sv[j, :m].copy()
                rn = sn[j, :m].copy()
                for i in range(m):
                    st |= _push_value(sv, sn, ms, j, rv[i], rn[i])
                    _four_point(sv, sn, ms, j, buf_j, buf_d, buf_n1, buf_n2, buf_c, nbuf)
                    if nbuf[0] >= CYCLE_BUFFER:
                        _flush(p, buf_j, buf_d, buf_n1, buf_n2, buf_c, nbuf, crit, ca, cb, cc,
                               s_scale, seg_S_low, seg_m, seg_inv_a, S_cut, sel_crit, out_dmg,
                               out_sel, out_par)
            if nbuf[0] >= CYCLE_BUFFER:
                _flush(p, buf_j, buf_d, buf_n1, buf_n2, buf_c, nbuf, crit, ca, cb, cc, s_scale,
                       seg_S_low, seg_m, seg_inv_a, S_cut, sel_crit, out_dmg, out_sel, out_par)
        _flush(p, buf_j, buf_d, buf_n1, buf_n2, buf_c, nbuf, crit, ca, cb, cc, s_scale, seg_S_low,
               seg_m, seg_inv_a, S_cut, sel_crit, out_dmg, out_sel, out_par)
        if sel_crit == crit:
            for j in range(n_c):
                out_sel[p, j] = out_dmg[p, j]
        status[p] = st
    for p in range(n_p):
        if status[p] != 0:
            return STATUS_STACK_OVERFLOW
    return STATUS_OK


@njit(cache=True)
def pseudo_angles(x, y, out):
    """Vectorised ``_pseudo_angle`` (for building boundaries in the wrapper)."""
    for i in range(x.shape[0]):
        out[i] = _pseudo_angle(x[i], y[i])
    return 0

