"""Mud-pressure stresses against Lame's thick-cylinder solution and the
effective/true tension identity.

References: Timoshenko & Goodier, Theory of Elasticity, 3rd ed., section 28
(thick-walled cylinder); docs/bending.md (outer-surface forms);
Lubinski's effective tension (Aadnoy, Mechanics of Drilling, ch. 2):
F_true = F_eff + p_i A_i - p_o A_o, and for a string hanging in mud the
effective tension is the buoyed weight below the section.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from drillfatigue.fatigue.critical_plane import CriterionParams, PlaneSearch, evaluate_location
from drillfatigue.fatigue.sn import get_curve
from drillfatigue.fatigue.stress import (SCF, Pressure, Section, hydrostatic_pressure_Pa,
                                         lame_stresses_Pa, surface_pressure_stresses,
                                         true_wall_force_N)

DP = Section(0.127, 0.1086)
DC = Section(0.17145, 0.0714)


@pytest.mark.parametrize("sec", [DP, DC])
@pytest.mark.parametrize("pi, po", [(30e6, 25e6), (25e6, 25e6), (0.0, 10e6), (12e6, 0.0)])
def test_surface_stresses_match_lame_closed_forms(sec: Section, pi: float, po: float) -> None:
    # closed form against closed form, rounding only: rel 1e-12
    ri, ro = sec.id_m / 2, sec.od_m / 2
    p = Pressure(pi, po)
    sr_o, st_o = lame_stresses_Pa(sec, p, ro)
    sr_i, st_i = lame_stresses_Pa(sec, p, ri)
    scale = max(pi, po)
    assert sr_o == pytest.approx(-po, abs=1e-12 * scale)
    assert sr_i == pytest.approx(-pi, abs=1e-12 * scale)
    assert st_o == pytest.approx((2 * pi * ri**2 - po * (ro**2 + ri**2)) / (ro**2 - ri**2),
                                 abs=1e-12 * scale)
    assert st_i == pytest.approx((pi * (ro**2 + ri**2) - 2 * po * ro**2) / (ro**2 - ri**2),
                                 abs=1e-12 * scale)
    # equilibrium of half the cylinder: the hoop force through the wall balances
    # the pressures on the projected bore and outside (integral of sigma_theta dr
    # = p_i r_i - p_o r_o); Simpson on 201 nodes of a smooth 1/r^2 profile: 1e-9
    r = np.linspace(ri, ro, 201)
    st = np.array([lame_stresses_Pa(sec, p, x)[1] for x in r])
    h = r[1] - r[0]
    integral = h / 3 * (st[0] + st[-1] + 4 * st[1:-1:2].sum() + 2 * st[2:-1:2].sum())
    assert integral == pytest.approx(pi * ri - po * ro, abs=1e-9 * scale * ro)


def test_thin_wall_limit_is_barlow() -> None:
    # a 1 mm wall on a 1 m diameter: sigma_theta -> p r / t within t/(2r) = 0.1 %
    sec = Section(1.0, 0.998)
    st = lame_stresses_Pa(sec, Pressure(1e6, 0.0), 0.5)[1]
    assert st == pytest.approx(1e6 * 0.499 / 0.001, rel=2e-3)


def test_equal_pressure_adds_a_hydrostatic_stress() -> None:
    # p_i = p_o = p: sigma_r = sigma_theta = -p everywhere and the true wall force
    # adds -p A to the axial force, so sigma_z also drops by exactly p
    p = 23.5e6
    dz, st, sr = surface_pressure_stresses(DP, SCF(), Pressure(p, p), "outer")
    assert (dz, st, sr) == pytest.approx((-p, -p, -p), rel=1e-12)
    dz, st, sr = surface_pressure_stresses(DP, SCF(), Pressure(p, p), "inner")
    assert (dz, st, sr) == pytest.approx((-p, -p, -p), rel=1e-12)


def test_hanging_string_true_vs_effective_tension() -> None:
    """A drill pipe of length H hanging open-ended in a vertical mud-filled hole.
    The true wall force at depth z is found by statics of the steel below z:
    its weight in air minus the mud pressure on its lower end ring; the
    effective tension is the buoyed weight below z. The identity
    F_true = F_eff + p_i A_i - p_o A_o must hold at every depth (rounding:
    1e-9 of the weight)."""
    H, rho_s, rho_m, g = 3000.0, 7850.0, 1200.0, 9.80665
    A = DP.area_m2
    for z in np.linspace(0.0, H, 7):
        below = H - z
        p_bottom = float(hydrostatic_pressure_Pa(H, rho_m))
        f_true_statics = rho_s * g * A * below - p_bottom * A
        f_eff = (rho_s - rho_m) * g * A * below
        p = float(hydrostatic_pressure_Pa(z, rho_m))
        got = true_wall_force_N(f_eff, DP, Pressure(p, p))
        assert got == pytest.approx(f_true_statics, abs=1e-9 * rho_s * g * A * H)
    # and with pump pressure inside: the bore pressure pushes on A_i
    assert true_wall_force_N(1e5, DP, Pressure(5e6, 0.0)) == pytest.approx(
        1e5 + 5e6 * math.pi * (DP.id_m / 2) ** 2, rel=1e-14)


def _bending_cycles(n_cyc: int = 40, amp_Nm: float = 9e3) -> np.ndarray:
    t = np.linspace(0.0, n_cyc, 40 * n_cyc + 1)
    L = np.zeros((t.size, 6))
    L[:, 4] = amp_Nm * np.cos(2 * np.pi * t)  # from a peak to a peak: 40 whole cycles
    return L


@pytest.mark.parametrize("p", [0.0, 5e6, 60e6])
def test_matake_under_hydrostatic_pressure_closed_form(p: float) -> None:
    """Fully reversed bending sigma_a under mud pressure p inside and out. The
    hydrostatic -p adds no shear, so the maximum-shear plane (45 deg) keeps
    dtau/2 = sigma_a/2 and its normal stress at the shear turning points drops
    by p: Matake sigma_eq = (f/t)[sigma_a/2 + a max(sigma_a/2 - p, 0)]. The
    kernel must give 40 cycles of that (rel 1e-9: exact arithmetic up to
    rounding; the 45 deg plane is on the refined grid)."""
    L = _bending_cycles()
    curve = get_curve("B1", "air")
    prm = CriterionParams()
    r = evaluate_location(L, DP, SCF(), curve, "matake", prm, search=PlaneSearch(n_refine=4),
                          pressure=Pressure(p, p))
    sig_a = 9e3 * DP.r_m / DP.inertia_m4
    ft = 1.0 / prm.torsion_to_tension_ratio
    a = 2.0 * prm.torsion_to_tension_ratio - 1.0
    s_eq = ft * (0.5 * sig_a + a * max(0.5 * sig_a - p, 0.0))
    expect = 40.0 / curve.cycles_to_failure(np.array([2.0 * s_eq]))[0]
    assert r.damage == pytest.approx(expect, rel=1e-9)
