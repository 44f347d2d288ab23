"""Invariants of the span kernels with supports at different heights, and of the rigid
chain's static moments (hypothesis).

* Zero offsets reproduce the level solution bit for bit (the settlement terms add
  exact zeros), for the beam and for the chain form.
* Offsets on a straight line (the supports moved and turned rigidly) give no moment
  with pinned ends (a clamped end holds the slope, so there only a translation).
* The solution is linear in the offsets: M(q, a d1 + b d2) = M(q, 0) + a M(0, d1)
  + b M(0, d2).
* The chain's static moments: holds on a straight line and no load give none; holds at
  every node give the kinks' k (theta_up - theta_lo) whatever the load and axial force;
  linear in the load; a chain cut into ever shorter segments on the same supports tends
  to the continuous beam (the error falls as the segments shorten).
"""

from __future__ import annotations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from drillfatigue.dynamics.span import bending as K
from drillfatigue.dynamics.span.beam import continuous_beam_moments
from drillfatigue.dynamics.span.chain import chain_static_moments

spans = st.lists(st.floats(1.0, 15.0), min_size=1, max_size=8)
ENDS = st.sampled_from([K.END_PINNED, K.END_CLAMPED])
EI = 8.5e6


def _case(L: list[float], seed: int, P: float):
    n = len(L)
    rng = np.random.default_rng(seed)
    q = rng.uniform(-1500.0, 1500.0, (n, 2))
    d = rng.uniform(-0.03, 0.03, (n + 1, 2))
    P = max(P, -0.5 * np.pi ** 2 * EI / max(L) ** 2)  # every span below its Euler load
    return np.array(L), np.full(n, EI), np.full(n, P), q, d


def _settled(L, ei, T, q, d, e0, e1):
    out = np.zeros((L.size + 1, 2))
    assert K.support_moments_settled(L, ei, T, q, d, e0, e1, np.zeros((L.size + 1, 6)),
                                     out) == K.STATUS_OK
    return out


@settings(max_examples=60, deadline=None)
@given(spans, st.integers(0, 2**31), ENDS, ENDS, st.floats(-2e4, 5e5))
def test_zero_offsets_give_the_level_solution_bit_for_bit(L, seed, e0, e1, P) -> None:
    L, ei, T, q, _ = _case(L, seed, P)
    level = np.zeros((L.size + 1, 2))
    K.support_moments(L, ei, T, q, e0, e1, np.zeros((L.size + 1, 6)), level)
    assert np.array_equal(_settled(L, ei, T, q, np.zeros((L.size + 1, 2)), e0, e1), level)
    # the chain form: supports over a string of segments
    bounds = np.concatenate([[0.0], np.cumsum(L)])
    m = L.size
    chain = K.SegmentChain(bounds, ei, T, q)
    args = (chain, e0, e1, bounds[1:-1].copy())
    outs = []
    for settled in (False, True):
        sup_M = np.zeros((m + 1, 2))
        read_M = np.zeros((m - 1, 2))
        scratch = (K.Spans(np.zeros(m), np.zeros(m), np.zeros(m), np.zeros((m, 2))),
                   np.zeros((m + 1, 6)))
        cut = np.zeros(m, dtype=np.int64)
        if settled:
            K.chain_span_moments_settled(bounds, np.zeros((m + 1, 2)), *args, *scratch,
                                         sup_M, read_M, cut, np.zeros(m - 1, dtype=np.int64))
        else:
            K.chain_span_moments(bounds, *args, *scratch, sup_M, read_M, cut)
        outs.append((sup_M, read_M))
    assert np.array_equal(outs[0][0], outs[1][0]) and np.array_equal(outs[0][1], outs[1][1])


@settings(max_examples=60, deadline=None)
@given(spans, st.integers(0, 2**31), st.floats(-0.05, 0.05), st.floats(-0.02, 0.02),
       st.floats(-2e4, 5e5))
def test_offsets_on_a_straight_line_give_no_moment(L, seed, a, b, P) -> None:
    L, ei, T, _, _ = _case(L, seed, P)
    s = np.concatenate([[0.0], np.cumsum(L)])
    d = np.stack([a + b * s, -a + 0.5 * b * s], axis=1)
    got = _settled(L, ei, T, np.zeros((L.size, 2)), d, K.END_PINNED, K.END_PINNED)
    # the settlement scale: 3 EI |b| / L_min
    np.testing.assert_allclose(got, 0.0, atol=1e-9 * 3 * EI * (abs(b) + 1e-3) / L.min())
    # clamped ends hold the slope: a translation alone gives nothing
    d = np.full((L.size + 1, 2), a)
    got = _settled(L, ei, T, np.zeros((L.size, 2)), d, K.END_CLAMPED, K.END_CLAMPED)
    np.testing.assert_allclose(got, 0.0, atol=1e-9 * 3 * EI * 1e-3 / L.min())


@settings(max_examples=60, deadline=None)
@given(spans, st.integers(0, 2**31), st.integers(0, 2**31), ENDS, ENDS, st.floats(-3, 3),
       st.floats(-3, 3), st.floats(-2e4, 5e5))
def test_linear_in_the_offsets(L, s1, s2, e0, e1, a, b, P) -> None:
    L, ei, T, q, d1 = _case(L, s1, P)
    d2 = _case(list(L), s2, P)[4]
    z = np.zeros_like(q)
    got = _settled(L, ei, T, q, a * d1 + b * d2, e0, e1)
    want = (_settled(L, ei, T, q, 0 * d1, e0, e1) + a * _settled(L, ei, T, z, d1, e0, e1)
            + b * _settled(L, ei, T, z, d2, e0, e1))
    scale = 1.0 + np.abs(want).max() + 3 * EI * 0.03 * (abs(a) + abs(b)) / L.min() ** 2
    np.testing.assert_allclose(got, want, atol=1e-9 * scale)


chains = st.lists(st.floats(0.5, 10.0), min_size=2, max_size=12)


@settings(max_examples=60, deadline=None)
@given(chains, st.integers(0, 2**31), st.floats(-0.05, 0.05), st.floats(-0.02, 0.02),
       st.floats(0.0, 3e5))
def test_chain_static_held_on_a_line_carries_nothing(L, seed, a, b, T) -> None:
    top = np.concatenate([[0.0], np.cumsum(L)])
    n = len(L)
    rng = np.random.default_rng(seed)
    hs = np.sort(rng.uniform(0.0, top[-1], 4))
    hs[0], hs[-1] = 0.0, top[-1]
    y = np.stack([a + b * hs, 2 * a - b * hs], axis=1)
    out = np.zeros((n - 1, 2))
    k = rng.uniform(1e5, 5e6, n - 1)
    assert chain_static_moments(top, k, np.full(n, T), np.zeros((n, 2)), hs, y,
                                out) == K.STATUS_OK
    np.testing.assert_allclose(out, 0.0, atol=1e-6 * k.max() * (abs(b) + 1e-3) / min(L))


@settings(max_examples=60, deadline=None)
@given(chains, st.integers(0, 2**31), st.floats(-1e5, 3e5))
def test_chain_static_held_at_every_node_is_its_kinks(L, seed, T) -> None:
    top = np.concatenate([[0.0], np.cumsum(L)])
    n = len(L)
    rng = np.random.default_rng(seed)
    y = rng.uniform(-0.02, 0.02, (n + 1, 1))
    k = rng.uniform(1e5, 5e6, n - 1)
    q = rng.uniform(-2e3, 2e3, (n, 1))
    out = np.zeros((n - 1, 1))
    assert chain_static_moments(top, k, np.full(n, T), q, top.copy(), y, out) == K.STATUS_OK
    theta = np.diff(y[:, 0]) / np.diff(top)
    want = -k * np.diff(theta)
    # a hold is a penalty spring 1e8 times the stiffness around it: the kinks are
    # imposed through the holds' reactions, so the error is a few 1e-9 of the
    # moments the load puts on the holds (q L^2; 3e-9 seen with q L^2 = 1e5 N m)
    # plus a few 1e-7 of the kinks' own moment (1.2e-6 seen)
    load = np.abs(q).max() * max(L) ** 2
    np.testing.assert_allclose(out[:, 0], want,
                               atol=1e-5 * (np.abs(want).max() + 1.0) + 1e-7 * load)


@settings(max_examples=40, deadline=None)
@given(chains, st.integers(0, 2**31), st.floats(-3, 3), st.floats(-3, 3))
def test_chain_static_linear_in_the_load(L, seed, a, b) -> None:
    top = np.concatenate([[0.0], np.cumsum(L)])
    n = len(L)
    rng = np.random.default_rng(seed)
    hs = np.array([0.0, top[-1]])
    y = np.zeros((2, 2))
    k = rng.uniform(1e5, 5e6, n - 1)
    T = np.full(n, 2e4)
    q1 = rng.uniform(-2e3, 2e3, (n, 2))
    q2 = rng.uniform(-2e3, 2e3, (n, 2))
    outs = []
    for q in (q1, q2, a * q1 + b * q2):
        o = np.zeros((n - 1, 2))
        assert chain_static_moments(top, k, T, q, hs, y, o) == K.STATUS_OK
        outs.append(o)
    scale = 1.0 + (abs(a) + abs(b)) * max(np.abs(outs[0]).max(), np.abs(outs[1]).max())
    np.testing.assert_allclose(outs[2], a * outs[0] + b * outs[1], atol=1e-9 * scale)


@settings(max_examples=15, deadline=None)
@given(st.lists(st.floats(4.0, 12.0), min_size=2, max_size=4), st.integers(0, 2**31))
def test_chain_static_tends_to_the_continuous_beam(L, seed) -> None:
    """Spans on supports at different heights under a uniform load; the chain cut into
    4, 8, 16 segments per span, its bending springs EI over the distance between the
    segment centres (as the simulator's joints): the moments over the interior supports
    approach the beam's, the error falling as the segments shorten."""
    rng = np.random.default_rng(seed)
    L = np.array(L)
    sup = np.concatenate([[0.0], np.cumsum(L)])
    d = rng.uniform(-0.02, 0.02, (sup.size, 1))
    w = 1200.0
    beam = continuous_beam_moments(L, EI, np.array([[0.0, w]] * L.size),
                                   support_offsets_m=np.concatenate([0 * d, d], axis=1))
    want = beam.support_Nm[1:-1, 0]
    errs = []
    for per in (4, 8, 16):
        top = np.concatenate([np.linspace(a, b, per + 1)[:-1] for a, b in zip(sup[:-1], sup[1:],
                                                                             strict=True)]
                             + [[sup[-1]]])
        seg = np.diff(top)
        k = EI / (0.5 * (seg[:-1] + seg[1:]))
        out = np.zeros((seg.size - 1, 1))
        assert chain_static_moments(top, k, np.zeros(seg.size), np.full((seg.size, 1), w), sup,
                                    d.copy(), out) == K.STATUS_OK
        at = [int(np.argmin(np.abs(top[1:-1] - s))) for s in sup[1:-1]]
        errs.append(np.abs(out[at, 0] - want).max())
    scale = np.abs(want).max() + w * L.max() ** 2 / 12
    assert errs[2] < errs[0] and errs[2] < 0.05 * scale
