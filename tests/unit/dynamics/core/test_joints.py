"""Kernel-level checks: quaternions, free rotation, joint signs, stable step."""

from __future__ import annotations

import math

import numpy as np
import pytest

from drillfatigue.dynamics.core import layout as L
from drillfatigue.dynamics.run.examples import uniform_chain_case
from drillfatigue.dynamics.core.joints import joint_force
from drillfatigue.dynamics.run.model import advance_model, build_model, straight_path
from drillfatigue.dynamics.core.rigid import free_rotation, quat_from_rot, quat_log, quat_to_rot
from drillfatigue.errors import SimulationError

def test_quaternion_round_trip_and_log() -> None:
    rng = np.random.default_rng(0)
    for _ in range(20):
        v = rng.normal(size=3)
        v *= 2.5 / np.linalg.norm(v)
        q = np.r_[math.cos(1.25), math.sin(1.25) * v / 2.5]
        r = np.zeros((3, 3))
        quat_to_rot(q, r)
        np.testing.assert_allclose(r @ r.T, np.eye(3), atol=1e-14)
        q2 = quat_from_rot(r)
        assert min(np.abs(q2 - q).max(), np.abs(q2 + q).max()) < 1e-12
        th = np.zeros(3)
        quat_log(q, th)
        np.testing.assert_allclose(th, v, atol=1e-12)


def test_free_rotation_conserves_world_angular_momentum_and_energy() -> None:
    it, ia = 9000.0, 6.0
    q = np.array([1.0, 0.0, 0.0, 0.0])
    w = np.array([0.3, -0.2, 15.0])
    inertia = np.array([it, it, ia])
    r = np.zeros((3, 3))
    quat_to_rot(q, r)
    l0 = r @ (inertia * w)
    e0 = 0.5 * (inertia * w * w).sum()
    for _ in range(1000):
        free_rotation(q, w, it, ia, 1e-3)
    quat_to_rot(q, r)
    np.testing.assert_allclose(r @ (inertia * w), l0, rtol=1e-12)
    assert math.isclose(0.5 * (inertia * w * w).sum(), e0, rel_tol=1e-12)


def _pair(gap_z: float = 0.0, twist: float = 0.0):
    """Two vertical segments (axis e3 = +z downhole), the upper above the lower."""
    h = 1.0
    q_lo = np.array([1.0, 0.0, 0.0, 0.0])
    q_up = np.array([math.cos(twist / 2), 0.0, 0.0, math.sin(twist / 2)])
    x_lo = np.array([0.0, 0.0, 10.0])
    x_up = np.array([0.0, 0.0, 10.0 - 2 * h + gap_z])
    r_lo, r_up = np.eye(3), np.zeros((3, 3))
    quat_to_rot(q_up, r_up)
    z = np.zeros(3)
    f, ml, mu, loads, ed = np.zeros(3), np.zeros(3), np.zeros(3), np.zeros(6), np.zeros(2)
    jrow = np.zeros(L.N_JP)
    jrow[[L.J_KA, L.J_KS, L.J_KB, L.J_KT]] = 100.0, 10.0, 5.0, 2.0  # springs only, no dampers
    joint_force((x_lo, z, r_lo, q_lo, z, h), (x_up, z, r_up, q_up, z, h), jrow,
                (f, ml, mu, loads, ed))
    return f, ml, loads, ed


def test_joint_sign_conventions() -> None:
    # the upper segment pulled up (gap_z < 0: its lower end above the lower's top): tension
    f, _, loads, ed = _pair(gap_z=-0.01)
    assert loads[0] == pytest.approx(100.0 * 0.01)
    assert f[2] == pytest.approx(-1.0)  # the lower segment is pulled up (-z)
    assert ed[0] == pytest.approx(0.5 * 100.0 * 1e-4)
    # upper twisted ahead in the drilling sense (+z): positive torque drives the lower one
    _, ml, loads, _ = _pair(twist=0.1)
    assert loads[5] == pytest.approx(2.0 * 0.1)
    assert ml[2] == pytest.approx(0.2)


def test_step_beyond_the_stable_bound_is_caught_as_divergence() -> None:
    cfg = uniform_chain_case(5, 20.0)
    model, state = build_model(cfg, straight_path(60.0))
    state.v[:, 2] += 0.01
    model.dt *= 4.0  # 2x beyond 2/omega_max at the default safety factor 0.5
    with pytest.raises(SimulationError, match="diverged"):
        advance_model(model, state, 20_000, every=100)


def test_stable_step_bound_holds_at_the_default_safety() -> None:
    cfg = uniform_chain_case(5, 20.0)
    model, state = build_model(cfg, straight_path(60.0))
    state.v[:, 0] += 0.01
    state.w[:, 2] += 1.0
    out = advance_model(model, state, 20_000, every=1000)
    assert np.isfinite(out["channels"]).all()
    assert model.bp[L.B_DT] == model.dt
