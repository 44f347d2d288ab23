"""Energy: conserved without damping, never increasing with it (docs/validation.md).

Velocity Verlet is symplectic: without dissipation the energy error stays
bounded, O((omega dt)^2), with no secular drift (Hairer, Lubich & Wanner,
Geometric Numerical Integration, 2006, ch. IX). The string hangs in an inclined
hole (all joint springs and the gravity potential active), top held, bit free,
and starts from random translational and angular velocities.
"""

from __future__ import annotations

import numpy as np

from drillfatigue.dynamics.core import layout as L
from drillfatigue.dynamics.run.examples import uniform_chain_case
from drillfatigue.dynamics.run.model import advance_model, build_model, straight_path, total_energy


def _perturbed(damping: bool):
    cfg = uniform_chain_case(5, 20.0, damping=damping,
                             extra={"operation": {"mud_density_kg_per_m3": 1100.0},
                                    # steel-only lateral inertia: the energy channels count
                                    # the steel's kinetic energy, not the mud moved with it
                                    "string": {"lateral_mud_mass": False}})
    model, state = build_model(cfg, straight_path(60.0, inclination_deg=30.0))
    # smooth initial velocities (free at the bit, zero at the held top): lateral,
    # axial, spin and tilt, so all joint springs and the gyroscopic term work
    s = 1.0 - np.arange(model.n) / model.n
    state.v[:, 0] += 0.02 * s
    state.v[:, 1] += 0.05 * s
    state.v[:, 2] += 0.01 * s
    state.w[:, 2] += 0.5 * s
    state.w[:, 0] += 0.01
    e0 = total_energy(model, state)
    ke0 = 0.5 * float((model.seg[:, L.S_M][:, None] * state.v ** 2).sum()
                      + (model.seg[:, L.S_IA] * state.w[:, 2] ** 2).sum()
                      + (model.seg[:, L.S_IT] * state.w[:, 0] ** 2).sum())
    return model, state, e0, ke0


def _energy(ch: np.ndarray) -> np.ndarray:
    return ch[:, 1 + L.N_CH] + ch[:, 1 + L.H_PE] + ch[:, 1 + L.H_PG]


def test_energy_drift_below_0p1_percent_over_1e5_steps_without_damping() -> None:
    model, state, e0, ke0 = _perturbed(damping=False)
    out = advance_model(model, state, 100_000, every=10)
    e = _energy(out["channels"])
    # Reference: the vibration energy put in (the gravity potential is an
    # arbitrary large offset). Drift = change of the mean energy between the
    # first and the last tenth of the 1e5 steps: < 0.1 % (the bound;
    # measured 2e-5). The bounded Verlet oscillation around it, O((omega dt)^2)
    # in the highest modes at half the stable step, stays below 5 % (measured 1.7 %).
    k = e.size // 10
    assert abs(e[-k:].mean() - e[:k].mean()) < 1e-3 * ke0
    assert np.abs(e - e0).max() < 0.05 * ke0
    assert out["channels"][-1, 3 + L.N_CH] == 0.0  # nothing dissipated


def test_energy_never_increases_with_damping() -> None:
    model, state, e0, ke0 = _perturbed(damping=True)
    out = advance_model(model, state, 20_000, every=1)
    ch = out["channels"]
    e = _energy(ch)
    diss = ch[:, 3 + L.N_CH]
    # every damper dissipates: the cumulative dissipation never decreases
    assert np.all(np.diff(diss) >= 0.0)
    # the energy, averaged over windows longer than the slowest period of the
    # bounded Verlet oscillation (200 steps), never increases
    means = e[: e.size // 200 * 200].reshape(-1, 200).mean(axis=1)
    assert np.all(np.diff(means) <= 0.0), np.diff(means).max()
    assert e[-1] < e0 - 0.1 * ke0
    # and the balance closes: E(t) + dissipated = E(0) (no work in: fixed top,
    # no drive) within the bounded oscillation (< 5 % of the vibration energy,
    # see above) plus 0.1 % of the dissipated energy (the dampers act on
    # half-step velocities: first order in the damping; measured 5e-5). The
    # string also sags in the inclined hole, so far more is dissipated than put in.
    assert np.abs(e + diss - e0).max() < 0.05 * ke0 + 1e-3 * diss[-1]
