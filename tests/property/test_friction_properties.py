"""Property tests of the seven wall-friction models (docs/model.md#friction)."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from drillfatigue.config.friction import FrictionConfig
from drillfatigue.dynamics.core import status
from drillfatigue.dynamics.contact.friction import (
    KARNOPP,
    MODEL_IDS,
    friction_force,
    friction_force_split,
    pack_friction_params,
)

MODELS = sorted(MODEL_IDS)
vec = st.tuples(*(st.floats(-5.0, 5.0, allow_subnormal=False),) * 3)
small_vec = st.tuples(*(st.floats(-2e-3, 2e-3, allow_subnormal=False),) * 3)
force_vec = st.tuples(*(st.floats(-5e3, 5e3, allow_subnormal=False),) * 3)


def force(model, v, N, f_other=(0.0, 0.0, 0.0), cfg=None):
    mid, p = pack_friction_params(cfg or FrictionConfig(model=model))
    out = np.empty(3)
    assert friction_force(mid, p, np.array(v, float), N, np.array(f_other, float), 1e-4, out) == status.OK
    return out


@pytest.mark.parametrize("model", MODELS)
@settings(max_examples=40, deadline=None)
@given(v=st.one_of(vec, small_vec), N=st.floats(0.0, 1e4), f_other=force_vec)
def test_dissipative_bounded_odd(model, v, N, f_other):
    cfg = FrictionConfig(model=model)
    F = force(model, v, N, f_other)
    Fm = force(model, tuple(-c for c in v), N, tuple(-c for c in f_other))
    v = np.array(v)
    # never adds energy; tolerance: round-off of the projection step (relative 1e-12);
    # |v| by hypot, which does not underflow to 0 for components ~1e-238 (a plain
    # 2-norm squares them to 0 and leaves no room for the round-off of F . v)
    assert F @ v <= 1e-12 * N * np.hypot(np.hypot(v[0], v[1]), v[2])
    # |F| <= mu_s N: every shape is bounded by mu_s, so only round-off is allowed
    assert np.linalg.norm(F) <= cfg.mu_static * N * (1 + 1e-12) + 1e-12
    # odd in slip velocity (jointly with the applied force for Karnopp)
    np.testing.assert_allclose(Fm, -F, rtol=1e-13, atol=1e-12)


@pytest.mark.parametrize("model", MODELS)
def test_tends_to_dynamic_coefficient_at_high_slip(model):
    cfg = FrictionConfig(model=model)
    N = 1234.0
    for direction in ([1.0, 0, 0], [0.3, -0.4, 0.5]):
        d = np.array(direction) / np.linalg.norm(direction)
        F = force(model, 20.0 * d, N)
        # exp(-20/0.05) and 1 - tanh(2e4) are far below 1e-12
        np.testing.assert_allclose(F, -cfg.mu_dynamic * N * d, rtol=1e-12)


@pytest.mark.parametrize("model", MODELS)
def test_zero_normal_force_gives_zero(model):
    np.testing.assert_array_equal(force(model, (0.1, 0.2, 0.0), 0.0, (5.0, 0, 0)), 0.0)


@pytest.mark.parametrize("model", ["benson_hallquist", "velocity_trig", "tanh_exp", "stick_band"])
def test_static_peak_exceeds_dynamic(model):
    """The Stribeck-type models reach (close to) mu_s N at low slip: the stick-slip driver."""
    cfg = FrictionConfig(model=model)
    speeds = np.geomspace(1e-5, 1.0, 400)
    mags = [np.linalg.norm(force(model, (s, 0, 0), 1.0)) for s in speeds]
    assert max(mags) > cfg.mu_dynamic + 0.8 * (cfg.mu_static - cfg.mu_dynamic)
    # stick_band sits at mu_s itself inside its band: one rounding of -N mu v / |v|
    assert max(mags) <= cfg.mu_static * (1.0 + 1e-12)


@pytest.mark.parametrize("model", MODELS)
def test_continuous_in_slip_speed(model):
    """Friction magnitude has no jumps except the documented band edge of the Karnopp-style laws."""
    speeds = np.linspace(0.0, 0.3, 30001)
    mags = np.array([np.linalg.norm(force(model, (s, 0, 0), 1.0)) for s in speeds])
    jumps = np.abs(np.diff(mags))
    if model in ("karnopp", "stick_band"):
        cfg = FrictionConfig(model=model)
        # single jump at the band edge, from the stick value down to mu_d
        assert np.count_nonzero(jumps > 1e-2) == 1
        band = cfg.karnopp_dv_m_per_s if model == "karnopp" else cfg.stick_band_m_per_s
        assert mags[speeds > band][0] == pytest.approx(cfg.mu_dynamic)
    else:
        # the steepest slopes are ~mu/v_t = 0.25/1e-3 per m/s; step 1e-5 m/s
        assert jumps.max() < 4e-3


def test_axial_split_scales_only_the_axial_component():
    cfg = FrictionConfig(model="tanh", mu_axial=0.1)
    mid, p = pack_friction_params(cfg)
    v = np.array([0.3, 0.0, 0.4])
    axial = np.array([0.0, 0.0, 1.0])
    full = np.empty(3)
    split = np.empty(3)
    friction_force(mid, p, v, 100.0, np.zeros(3), 1e-4, full)
    friction_force_split(mid, p, v, axial, 100.0, np.zeros(3), 1e-4, split)
    assert split[0] == pytest.approx(full[0])
    assert split[2] == pytest.approx(full[2] * 0.1 / 0.25)
    assert split @ v < 0


def test_unknown_model_status():
    _, p = pack_friction_params(FrictionConfig())
    out = np.ones(3)
    assert friction_force(17, p, np.ones(3), 1.0, np.zeros(3), 1e-4, out) == status.UNKNOWN_FRICTION
    np.testing.assert_array_equal(out, 0.0)


def _block(model_cfg, load_N, t_end=0.5, dt=1e-5):
    """1-DOF block of mass m on a wall with normal force N under a constant tangential load."""
    mid, p = pack_friction_params(model_cfg)
    m, N = 10.0, 1000.0
    x = v = 0.0
    out = np.empty(3)
    vv = np.zeros(3)
    fo = np.zeros(3)
    for _ in range(int(t_end / dt)):
        vv[0] = v
        fo[0] = load_N
        friction_force(mid, p, vv, N, fo, dt, out)
        v += dt * (load_N + out[0]) / m  # symplectic Euler
        x += dt * v
    return x, v


def test_karnopp_holds_below_and_releases_above_static_limit():
    cfg = FrictionConfig(model="karnopp", mu_static=0.4, mu_dynamic=0.3)
    x, v = _block(cfg, 0.95 * 0.4 * 1000.0)
    assert abs(x) < 1e-9 and abs(v) < 1e-9  # held at rest: true stiction
    x, v = _block(cfg, 1.05 * 0.4 * 1000.0)
    # released: slides with a = (F - mu_d N)/m after break-away, 0.5 s -> v ~ 6 m/s
    assert v > 0.9 * (1.05 * 400.0 - 300.0) / 10.0 * 0.5
    assert KARNOPP == MODEL_IDS["karnopp"]
