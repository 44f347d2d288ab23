"""Unit tests of the point-in-cylinder contact kernel (docs/model.md#contact)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from drillfatigue.dynamics.contact.wall import (
    OUTSIDE_CHAIN,
    build_cylinder_chain,
    damping_from_ratio,
    find_contact,
    normal_force,
    stable_dt,
)

R_HOLE = 0.108
R_PIPE = 0.0635


def bend_chain(theta_deg: float = 20.0, n_seg: int = 2, seg_len: float = 2.0):
    """Centre line in the x-z plane: straight down, then turned by theta_deg per joint."""
    pts = [np.zeros(3)]
    ang = 0.0
    for _ in range(n_seg):
        d = np.array([math.sin(ang), 0.0, math.cos(ang)])
        pts.append(pts[-1] + seg_len * d)
        ang += math.radians(theta_deg)
    return build_cylinder_chain(np.array(pts), R_HOLE)


def run(x, chain, hint=0, r=R_PIPE):
    out = np.empty(6)
    idx = find_contact(np.asarray(x, dtype=np.float64), r, *chain, hint, out)
    return idx, out


def test_straight_cylinder_no_contact_and_contact():
    chain = build_cylinder_chain(np.array([[0, 0, 0], [0, 0, 10.0]]), R_HOLE)
    idx, out = run([0.01, 0.0, 5.0], chain)
    assert idx == 0
    assert out[0] == pytest.approx(0.01 - (R_HOLE - R_PIPE))
    assert out[0] < 0
    assert out[5] == pytest.approx(0.01)
    idx, out = run([0.0, 0.05, 5.0], chain)
    assert out[0] == pytest.approx(0.05 - (R_HOLE - R_PIPE))
    assert out[0] > 0
    np.testing.assert_allclose(out[1:4], [0.0, 1.0, 0.0], atol=1e-15)
    assert out[4] == pytest.approx(5.0)


def test_outside_chain_returns_minus_one_but_fills_out():
    chain = build_cylinder_chain(np.array([[0, 0, 0], [0, 0, 10.0]]), R_HOLE)
    idx, out = run([0.05, 0.0, 10.5], chain)
    assert idx == OUTSIDE_CHAIN
    assert out[4] == pytest.approx(10.5)  # prolonged end cylinder
    assert out[5] == pytest.approx(0.05)
    idx, _ = run([0.0, 0.0, -0.1], chain)
    assert idx == OUTSIDE_CHAIN


def test_wedge_outside_bend_measured_from_shared_point():
    chain = bend_chain(30.0)
    p_joint = chain[0][1]
    # a point on the outside of the bend (negative x side), beyond both slabs
    x = p_joint + np.array([-0.06, 0.0, 0.0])
    idx, out = run(x, chain, hint=0)
    assert out[5] == pytest.approx(0.06, rel=1e-12)
    np.testing.assert_allclose(out[1:4], [-1.0, 0.0, 0.0], atol=1e-12)
    idx2, out2 = run(x, chain, hint=1)
    np.testing.assert_allclose(out2, out, atol=1e-14)


def test_inside_bend_overlap_takes_smaller_penetration():
    chain = bend_chain(30.0)
    p_joint = chain[0][1]
    x = p_joint + np.array([0.09, 0.0, 0.0])  # inside of the bend, in both slabs
    q_dist = []
    for i in range(2):
        v = x - chain[0][i]
        s = v @ chain[1][i]
        q_dist.append(math.sqrt(v @ v - s * s))
    idx, out = run(x, chain)
    assert out[5] == pytest.approx(min(q_dist), rel=1e-12)
    assert idx == int(np.argmin(q_dist))


def test_wall_continuous_through_bend():
    """Penetration along a line crossing the joint has no jumps."""
    chain = bend_chain(25.0)
    p_joint = chain[0][1]
    for off in (-0.07, 0.07, 0.03):
        xs = np.linspace(-0.3, 0.3, 6001)
        deltas = np.array([run(p_joint + np.array([off, 0.02, z]), chain, hint=0)[1][0] for z in xs])
        jumps = np.abs(np.diff(deltas))
        # a smooth wall: step in delta bounded by the step in position (1e-4 m)
        assert jumps.max() <= 1.0001e-4


def test_hint_walk_far_hint_same_result():
    chain = bend_chain(3.0, n_seg=40, seg_len=1.5)
    rng = np.random.default_rng(1)
    for _ in range(200):
        i = rng.integers(0, 40)
        x = chain[0][i] + rng.uniform(0, chain[2][i]) * chain[1][i] + rng.normal(0, 0.04, 3)
        ref_idx, ref = run(x, chain, hint=i)
        for h in (0, 39, -5, 100, i + 3):
            idx, out = run(x, chain, hint=h)
            np.testing.assert_allclose(out, ref, atol=1e-13)


def test_normal_force_never_pulls():
    assert normal_force(-1e-3, 10.0, 5e7, 5e4) == 0.0
    assert normal_force(1e-4, 0.0, 5e7, 5e4) == pytest.approx(5e3)
    assert normal_force(1e-4, -1.0, 5e7, 5e4) == 0.0  # separating fast: dash-pot would pull
    assert normal_force(1e-4, -0.05, 5e7, 5e4) == pytest.approx(5e3 - 2.5e3)


def test_stable_dt_matches_oscillator_limit():
    assert stable_dt(4.0, 1.0) == pytest.approx(1.0)
    assert stable_dt(5e7, 260.0, 0.2) < stable_dt(5e7, 260.0)
    assert damping_from_ratio(5e7, 260.0, 0.2) == pytest.approx(2 * 0.2 * math.sqrt(5e7 * 260))
    with pytest.raises(ValueError):
        stable_dt(-1.0, 1.0)


def test_stable_dt_is_the_explicit_limit():
    """Symplectic Euler on m x'' = -k x stays bounded just below dt_crit and blows up above."""
    k, m = 5e7, 30.0
    dtc = stable_dt(k, m)
    for factor, bounded in ((0.98, True), (1.02, False)):
        x, v, dt = 1e-3, 0.0, factor * dtc
        for _ in range(3000):
            v -= dt * k / m * x
            x += dt * v
        assert (abs(x) < 1e-2) is bounded


def test_build_chain_rejects_bad_shape():
    with pytest.raises(ValueError):
        build_cylinder_chain(np.zeros((1, 3)), 0.1)


def test_contact_config_defaults_and_damping():
    from drillfatigue.config.base import validate
    from drillfatigue.config.contact import ContactConfig
    from drillfatigue.dynamics.contact.wall import contact_damping
    from drillfatigue.errors import InputError

    cfg = ContactConfig()
    assert contact_damping(cfg, 260.0) == pytest.approx(2 * 0.2 * math.sqrt(5e7 * 260.0))
    assert contact_damping(ContactConfig(c_c_N_s_per_m=5e4), 1.0) == 5e4
    # default stiffness is softer than a 1 m drill-pipe joint's axial spring EA/L ~ 7e8 N/m
    assert stable_dt(cfg.k_c_N_per_m, 29.0) > 2 * math.sqrt(29.0 / 7e8)
    with pytest.raises(InputError) as exc:
        validate(ContactConfig, {"k_c_N_per_m": -1}, "contact")
    assert exc.value.field == "contact.k_c_N_per_m"
