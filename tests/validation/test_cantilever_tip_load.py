"""Cantilever under a tip load: deflection -> P L^3 / (3 E I) as segments increase.

Euler-Bernoulli cantilever (e.g. Timoshenko & Gere, Mechanics of Materials,
Table G-1, case 1). The string lies in a horizontal hole, clamped at the top by
the parasitic lateral/tilt springs set to the half-segment stiffness
(parasitic_stiffness_scale = 2), free at the bit. The load is lateral and
horizontal (y), so gravity (vertical) adds no geometric stiffness; the
linearised lateral stiffness is taken by central differences of the force
kernel and solved for the tip load.
"""

from __future__ import annotations

import math

import numpy as np

from drillfatigue.dynamics.core import layout as L
from drillfatigue.dynamics.run.examples import COLLAR_ID_M, COLLAR_OD_M, uniform_chain_case
from drillfatigue.dynamics.run.model import build_model, evaluate_forces, straight_path
from drillfatigue.dynamics.core.rigid import quat_from_rot, quat_to_rot

E = 207e9
I_AREA = math.pi / 64 * (COLLAR_OD_M ** 4 - COLLAR_ID_M ** 4)


def tip_deflection(n: int, length: float, load: float) -> float:
    cfg = uniform_chain_case(n, length, extra={"solver": {"parasitic_stiffness_scale": 2.0}})
    model, state = build_model(cfg, straight_path(2 * length, inclination_deg=90.0))
    x0, q0 = state.x.copy(), state.q.copy()
    K = np.zeros((2 * n, 2 * n))

    def forces() -> np.ndarray:
        evaluate_forces(model, state)
        return np.concatenate([state.Fw[:, 1], state.Mw[:, 2]])

    for dof in range(2 * n):
        cols = []
        for sgn in (1.0, -1.0):
            state.x[...] = x0
            state.q[...] = q0
            i = dof % n
            if dof < n:
                state.x[i, 1] += sgn * 1e-7
            else:
                a = sgn * 1e-7
                rz = np.array([[math.cos(a), -math.sin(a), 0], [math.sin(a), math.cos(a), 0],
                               [0, 0, 1.0]])
                r = np.zeros((3, 3))
                quat_to_rot(q0[i], r)
                state.q[i] = quat_from_rot(rz @ r)
            cols.append(forces())
        K[:, dof] = -(cols[0] - cols[1]) / 2e-7
    h0 = model.seg[0, L.S_H]
    f = np.zeros(2 * n)
    f[0] = load          # y force at the bit face of segment 0
    f[n] = h0 * load     # its moment about z (lever arm h0 along +x)
    u = np.linalg.solve(K, f)
    return float(u[0] + h0 * u[n])


def test_cantilever_converges_to_beam_theory() -> None:
    length, load = 30.0, 1000.0
    exact = load * length ** 3 / (3 * E * I_AREA)
    errors = [abs(tip_deflection(n, length, load) / exact - 1.0) for n in (5, 10, 20, 40)]
    # the error falls monotonically with N ...
    assert all(b < a for a, b in zip(errors, errors[1:], strict=False)), errors
    # ... and is below 1 % at 40 segments (discrete beam: O(1/N^2) plus the
    # Timoshenko shear term P L / (kappa G A), ~1e-3 here)
    assert errors[-1] < 0.01, errors
