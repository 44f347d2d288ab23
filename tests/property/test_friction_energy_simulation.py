"""Wall friction never adds energy in a full simulation (docs/model.md#friction, docs/validation.md).

A short string (5 segments, 10 m of collar) in a 60 deg hole, no drive (top
held, bit free), no mud or joint damping, wall contact on with any of the six
friction laws: it starts on the hole axis with a random lateral velocity and
spin, drops onto the low side, rubs and settles. The only energy sinks are the
contact dash-pot and friction, the only sources none, so the energy
(kinetic + springs + contact + gravity) never rises beyond the bounded
velocity-Verlet oscillation, and the dissipated-energy counter never
decreases (each law's force opposes the slip: F . v_slip <= 0).
"""

from __future__ import annotations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from drillfatigue.dynamics.core import layout as L
from drillfatigue.dynamics.run.examples import uniform_chain_case
from drillfatigue.dynamics.run.model import advance_model, build_model, straight_path, total_energy

MODELS = ("coulomb", "benson_hallquist", "karnopp", "tanh", "velocity_trig", "tanh_exp", "stick_band")


@settings(max_examples=12, deadline=None)
@given(model=st.sampled_from(MODELS), mu_d=st.floats(0.05, 0.8), ratio=st.floats(1.0, 1.5),
       v_lat=st.floats(-0.5, 0.5), spin=st.floats(-30.0, 30.0))
def test_friction_never_adds_energy_without_drive(model, mu_d, ratio, v_lat, spin) -> None:
    cfg = uniform_chain_case(5, 10.0, contact=True, damping=False, extra={
        "friction": {"model": model, "mu_static": min(mu_d * ratio, 1.5), "mu_dynamic": mu_d}})
    m, s = build_model(cfg, straight_path(30.0, inclination_deg=60.0))
    n = m.n0
    taper = 1.0 - np.arange(n) / n  # zero at the held top
    s.v[:n, 1] += v_lat * taper
    s.w[:n, 2] += spin * taper
    ke0 = 0.5 * float((m.seg[:n, L.S_M] * (s.v[:n] ** 2).sum(axis=1)).sum()
                      + (m.seg[:n, L.S_IA] * s.w[:n, 2] ** 2).sum())
    e0 = total_energy(m, s)
    ch = advance_model(m, s, int(round(0.5 / m.dt)), every=1)["channels"]
    e = ch[:, 1 + L.N_CH] + ch[:, 1 + L.H_PE] + ch[:, 1 + L.H_PG]
    diss = ch[:, 3 + L.N_CH]
    assert np.all(np.diff(diss) >= 0.0)
    # bounded Verlet oscillation: < 5 % of the kinetic energy put in plus 1 J for the
    # joint springs' own oscillation about the sagging shape (measured <= 1 J);
    # window means (50 steps, longer than the contact periods) never rise by more
    # than 20 % of that (measured rise 0.1 J)
    tol = 0.05 * ke0 + 1.0
    assert (e - e0).max() < tol
    means = e[: e.size // 50 * 50].reshape(-1, 50).mean(axis=1)
    assert np.diff(means).max() < 0.2 * tol
    assert e[-1] < e0
