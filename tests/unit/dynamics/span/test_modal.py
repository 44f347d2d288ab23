"""The span filter (drillfatigue.dynamics.span.modal) against closed forms of the
single-degree-of-freedom oscillator, and its bookkeeping in the integrator's state.

References (Biggs, *Introduction to Structural Dynamics*, 1964, ch. 2; Clough &
Penzien, *Dynamics of Structures*, 1993, ch. 3-4), for y'' + 2 zeta omega y' +
omega^2 y = omega^2 u:

* step u = u0 from rest: y = u0 [1 - e^(-zeta omega t) (cos wd t + zeta / sqrt(1 -
  zeta^2) sin wd t)], wd = omega sqrt(1 - zeta^2); first peak at t = pi / wd,
  overshoot exp(-pi zeta / sqrt(1 - zeta^2)).
* rectangular pulse u0 of duration tau, undamped: the free vibration after it has
  the amplitude 2 u0 sin(omega tau / 2) -- the factor omega tau of the quasi-static
  u0 for a short pulse, the dynamic load factor of an impact.
* first in-phase bending frequency of a span clamped at both ends: (beta L)^2
  sqrt(EI / (mu L^4)), beta L = 4.730 (Blevins 1979, table 8-1), and Rayleigh's
  quotient of that mode for the axial force.

Tolerances: the hold step is exact for a held input, so it is compared with the
closed forms to 1e-12 relative (round-off of a few hundred steps); the peak of a
sampled step response is within (omega T)^2 / 8 of the true one.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from drillfatigue.dynamics.run.examples import j_well_rotating_case
from drillfatigue.dynamics.core.layout import (
    CS_SQA, CS_SQF, CS_SQON, CS_SQT, P_SPANDYN, P_SPANZ, S_CL, S_H, S_M,
)
from drillfatigue.dynamics.run.simulation import _wellpath
from drillfatigue.dynamics.run.model import build_model
from drillfatigue.dynamics.span.modal import (
    ZETA_MAX, accumulate_span_load, sdof_hold_step, span_length_m, span_mode, span_modes,
    update_span_filters,
)


def _run(u: np.ndarray, T: float, omega: float, zeta: float) -> np.ndarray:
    y, yd = 0.0, 0.0
    out = np.zeros(u.size)
    for k in range(u.size):
        y, yd = sdof_hold_step(y, yd, float(u[k]), omega, zeta, T)
        out[k] = y
    return out


@pytest.mark.parametrize("zeta", [0.0, 0.05, 0.3, 0.9])
def test_step_response_is_the_closed_form(zeta: float) -> None:
    omega, T, n = 15.0, 0.005, 400
    y = _run(np.full(n, 2.5), T, omega, zeta)
    t = T * np.arange(1, n + 1)
    wd = omega * math.sqrt(1.0 - zeta ** 2)
    ref = 2.5 * (1.0 - np.exp(-zeta * omega * t) * (np.cos(wd * t) + zeta / math.sqrt(1.0 - zeta ** 2)
                                                       * np.sin(wd * t)))
    np.testing.assert_allclose(y, ref, rtol=1e-12, atol=1e-12)


@pytest.mark.parametrize("zeta", [0.05, 0.2])
def test_overshoot_and_static_gain(zeta: float) -> None:
    omega, T = 15.0, 0.001
    y = _run(np.ones(20000), T, omega, zeta)
    over = math.exp(-math.pi * zeta / math.sqrt(1.0 - zeta ** 2))
    assert y.max() - 1.0 == pytest.approx(over, abs=(omega * T) ** 2 / 8 * (1 + over))
    # static gain 1: a held load is reached (20 s >> 1 / (zeta omega))
    assert y[-1] == pytest.approx(1.0, abs=1e-6)


@pytest.mark.parametrize("omega_tau", [0.05, 0.1, 0.5])
def test_a_short_pulse_bends_the_span_by_the_factor_omega_tau(omega_tau: float) -> None:
    omega = 15.0
    tau = omega_tau / omega
    u = np.zeros(2000)
    u[0] = 1.0
    y = _run(u, tau, omega, 0.0)
    amp = 2.0 * math.sin(omega_tau / 2.0)
    # the free vibration after the pulse has exactly that amplitude
    yd_free = np.abs(y[1:]).max()
    assert yd_free <= amp * (1 + 1e-12)
    assert yd_free == pytest.approx(amp, rel=(omega * tau) ** 2)
    # a short pulse: about omega tau of the quasi-static answer (1.0)
    assert amp == pytest.approx(omega_tau, rel=omega_tau ** 2 / 20)


def test_in_phase_frequency_with_axial_force_and_damping_floor() -> None:
    # 5 in drill pipe body: EI = 207 GPa x pi / 64 (D^4 - d^4)
    ei = 207e9 * math.pi / 64.0 * (0.127 ** 4 - 0.1086 ** 4)
    L, mu = 9.144, 71.5
    mass = L * mu
    omega, zeta = span_mode(L, ei, mass, 0.0, 0.05, 0.0)
    # clamped-clamped first mode, beta L = 4.730041 (Blevins, Formulas for Natural
    # Frequency and Mode Shape, table 8-1): 2.267 x the pinned-pinned frequency
    assert omega == pytest.approx((4.730041 / L) ** 2 * math.sqrt(ei / mu), rel=1e-6)
    assert omega / ((math.pi / L) ** 2 * math.sqrt(ei / mu)) == pytest.approx(2.2669, rel=1e-4)
    assert zeta == 0.05
    # tension raises omega^2 by 12.30 T / (mu L^2) (Rayleigh's quotient of that mode;
    # the string limit pi^2 = 9.87 bounds it within 25 %)
    T = 2e5
    om_t = span_mode(L, ei, mass, 0.0, 0.05, T)[0]
    assert om_t ** 2 - omega ** 2 == pytest.approx(12.3026 * T / (mu * L ** 2), rel=1e-4)
    string = math.pi ** 2 * T / (mu * L ** 2)
    assert string < om_t ** 2 - omega ** 2 < 1.25 * string
    # in compression it falls, and stops at 0.3 of the value without axial force
    assert span_mode(L, ei, mass, 0.0, 0.05, -1e4)[0] < omega
    assert span_mode(L, ei, mass, 0.0, 0.05, -1e7)[0] == pytest.approx(0.3 * omega, rel=1e-12)
    # the drag sets the damping where it is larger, within the under-damped range
    c = 2.0 * mass * omega * 0.3
    assert span_mode(L, ei, mass, c, 0.05, 0.0)[1] == pytest.approx(0.3, rel=1e-14)
    assert span_mode(L, ei, mass, 100.0 * c, 0.05, 0.0)[1] == ZETA_MAX


@settings(max_examples=40, deadline=None)
@given(u0=st.floats(-1e5, 1e5), u1=st.floats(-1e5, 1e5), y0=st.floats(-1e5, 1e5),
       yd0=st.floats(-1e6, 1e6), zeta=st.floats(0.0, 0.94), wT=st.floats(1e-3, 5.0))
def test_hold_step_is_linear_and_composes(u0: float, u1: float, y0: float, yd0: float,
                                          zeta: float, wT: float) -> None:
    omega, T = 20.0, wT / 20.0
    a = sdof_hold_step(y0, yd0, u0 + u1, omega, zeta, T)
    b = sdof_hold_step(y0, yd0, u0, omega, zeta, T)
    c = sdof_hold_step(0.0, 0.0, u1, omega, zeta, T)
    scale = 1.0 + abs(u0) + abs(u1) + abs(y0) + abs(yd0) / omega
    assert a[0] == pytest.approx(b[0] + c[0], abs=1e-9 * scale)
    assert a[1] == pytest.approx(b[1] + c[1], abs=1e-9 * scale * omega)
    # two half steps with the same held load are one step
    h = sdof_hold_step(*sdof_hold_step(y0, yd0, u0, omega, zeta, T / 2), u0, omega, zeta, T / 2)
    one = sdof_hold_step(y0, yd0, u0, omega, zeta, T)
    assert h[0] == pytest.approx(one[0], abs=1e-9 * scale)
    assert h[1] == pytest.approx(one[1], abs=1e-9 * scale * omega)


def _tool_jointed_model(joints_per_segment: int) -> tuple:
    cfg = j_well_rotating_case(extra={
        "string": {"components": [
            {"type": "collar", "od_m": 0.17145, "id_m": 0.0714, "length_m": 24.0,
             "n_segments": 6},
            {"type": "drill_pipe", "od_m": 0.127, "id_m": 0.1086, "length_m": 9.144 * 24,
             "tool_joint_od_m": 0.1683, "tool_joint_id_m": 0.0826,
             "joints_per_segment": joints_per_segment}]},
        "operation": {"bit_md_m": 24.0 + 9.144 * 24 + 10.0}})
    return build_model(cfg, _wellpath(cfg))


@pytest.mark.parametrize("jps", [1, 3])
def test_the_span_is_the_tool_joint_spacing(jps: int) -> None:
    m, s = _tool_jointed_model(jps)
    p = m.params
    n = s.n_active
    spans = span_modes(p, n, 0.05)
    # flush collars: the segment (4 m); drill pipe: one joint, however many per segment
    assert np.allclose(spans[:6, 0], 4.0, rtol=1e-12)
    assert np.allclose(spans[6:n - 1, 0], 9.144, rtol=1e-9)
    # the growing top segment takes the span of the one below it
    assert span_length_m(n - 1, n, p) == spans[n - 2, 0]
    # on by default, on the loads record's grid, with the 5 % floor
    assert p.cpar[P_SPANDYN] == max(1, round(1.0 / (m.dt * 10.0)))  # loads at 10 Hz
    assert p.cpar[P_SPANZ] == 0.05


def test_impulses_count_once_wherever_they_fall_in_the_interval() -> None:
    m, s = _tool_jointed_model(1)
    p = m.params
    n = s.n_active
    dt = m.dt
    steps = 8

    def filtered(at: int) -> np.ndarray:
        st_ = s.copy()
        st_.cst[...] = 0.0
        st_.v[...] = 0.0
        # a held load first (the filter starts at rest on it), then one interval with
        # a 1 kN force on segment 3 during step ``at``
        st_.Fw[...] = 0.0
        for _ in range(steps):
            accumulate_span_load(n, st_, p, dt)
        update_span_filters(n, st_, p, m.work, True, 0.05)
        assert np.all(st_.cst[:n, CS_SQON] == 1.0)
        for k in range(steps):
            st_.Fw[3, 1] = 1e3 if k == at else 0.0
            accumulate_span_load(n, st_, p, dt)
        assert st_.cst[3, CS_SQT] == pytest.approx(steps * dt, rel=1e-12)
        assert st_.cst[3, CS_SQA + 1] == pytest.approx(-1e3 * dt, rel=1e-12)
        update_span_filters(n, st_, p, m.work, True, 0.05)
        assert st_.cst[3, CS_SQT] == 0.0 and st_.cst[3, CS_SQA + 1] == 0.0
        return st_.cst[:n, CS_SQF:CS_SQF + 3].copy()

    first = filtered(0)
    for at in range(1, steps):
        np.testing.assert_array_equal(filtered(at), first)
    # only segment 3 moved, by the hold step's answer to the interval's mean load
    T = steps * dt
    L = 2.0 * m.seg[3, S_H]
    ls = span_length_m(3, n, p)
    ax = 0.5 * (m.work.loads[2, 0] + m.work.loads[3, 0])
    om, z = span_mode(ls, m.ei[3], m.seg[3, S_M] * m.mlat[3] * ls / L, m.seg[3, S_CL] * ls / L,
                      0.05, ax)
    y, _ = sdof_hold_step(0.0, 0.0, -1e3 * dt / T, om, z, T)
    assert first[3, 1] == pytest.approx(y, rel=1e-12)
    assert not np.delete(first, 3, axis=0).any()
