"""API RP7G / Lubinski baseline against closed forms and the RP7G example."""

from __future__ import annotations

import math

import numpy as np
import pytest

from drillfatigue.errors import InputError
from drillfatigue.fatigue.rp7g import (E_RP7G_PA, endurance_bending_stress_Pa,
                                       hansford_lubinski_damage, lubinski_bending_stress_Pa,
                                       max_permissible_dogleg, rp7g_damage_rate_profile)
from drillfatigue.fatigue.sn import get_curve
from drillfatigue.units import FT_M, INCH_M, LBF_N, PSI_PA

D, DI = 4.5 * INCH_M, 3.826 * INCH_M  # 4 1/2 in 16.60 lb/ft drill pipe
A = math.pi * (D**2 - DI**2) / 4
I = math.pi * (D**4 - DI**4) / 64
L = 180 * INCH_M  # half of a 30 ft joint
KAPPA = math.radians(5.0) / (100 * FT_M)  # 5 deg/100 ft


def test_lubinski_tends_to_plain_beam_bending() -> None:
    beam = E_RP7G_PA * D * KAPPA / 2
    assert lubinski_bending_stress_Pa(E_RP7G_PA, D, KAPPA, 0.0, I, L) == pytest.approx(beam,
                                                                                     rel=1e-15)
    # KL/tanh(KL) = 1 + (KL)^2/3 + O(KL^4): with EI ~ 8.3e5 N m^2 and L = 4.57 m,
    # T = 1e-4 N gives KL ~ 5e-5 and a relative excess ~ 8e-10 < 1e-8
    small = lubinski_bending_stress_Pa(E_RP7G_PA, D, KAPPA, 1e-4, I, L)
    assert small == pytest.approx(beam, rel=1e-8) and small > beam


def test_lubinski_large_tension_limit() -> None:
    T = 200_000 * LBF_N
    K = math.sqrt(T / (E_RP7G_PA * I))
    got = lubinski_bending_stress_Pa(E_RP7G_PA, D, KAPPA, T, I, L)
    assert got == pytest.approx(E_RP7G_PA * D * KAPPA / 2 * K * L / math.tanh(K * L), rel=1e-14)
    assert got > E_RP7G_PA * D * KAPPA / 2


def test_grade_e_zero_tension_example_about_18_3_deg_per_100ft() -> None:
    # RP7G: 19,500 - 0.6 (33,500/670)^2 = 18,000 psi at zero tension;
    # 2 sigma / (E D) with E = 30e6 psi, D = 4.5 in: 18.33 deg/100 ft
    assert endurance_bending_stress_Pa("E-75", 0.0) == pytest.approx(18_000 * PSI_PA, rel=1e-14)
    kappa = max_permissible_dogleg("E-75", 0.0, D, I, A, L)
    deg_per_100ft = math.degrees(kappa) * 100 * FT_M
    assert deg_per_100ft == pytest.approx(18.33, abs=0.01)


def test_permissible_dogleg_falls_with_tension_and_s135_line() -> None:
    k0 = max_permissible_dogleg("E-75", 0.0, D, I, A, L)
    k1 = max_permissible_dogleg("E-75", 150_000 * LBF_N, D, I, A, L)
    assert k1 < k0
    assert endurance_bending_stress_Pa("S-135", 72_500 * PSI_PA) == pytest.approx(10_000 * PSI_PA)
    assert endurance_bending_stress_Pa("S-135", 140_000 * PSI_PA) == 0.0
    with pytest.raises(InputError, match="E-75, S-135"):
        endurance_bending_stress_Pa("G-105", 0.0)
    with pytest.raises(InputError):
        lubinski_bending_stress_Pa(E_RP7G_PA, D, KAPPA, -1.0, I, L)


def test_hansford_lubinski_counts_revolutions() -> None:
    curve = get_curve("D")
    sb = 80e6
    rpm, rop, Ldl = 120.0, 20.0 / 3600, 30.0  # 20 m/h through 30 m
    n = rpm / 60 * Ldl / rop  # 10,800 revolutions
    d = hansford_lubinski_damage(rpm, rop, Ldl, sb, curve)
    assert d == pytest.approx(n / curve.cycles_to_failure(2 * sb)[0], rel=1e-14)


def test_profile_rate_and_cumulative_damage() -> None:
    md = np.linspace(0, 300, 301)
    kap = np.where((md > 100) & (md < 200), KAPPA, 0.0)
    T = np.full_like(md, 50_000.0)
    out = rp7g_damage_rate_profile(md, kap, T, 120.0, 20.0 / 3600, D, DI, get_curve("D"))
    assert np.all(out["damage_rate_per_h"][kap == 0] == 0.0)
    inside = out["damage_rate_per_h"][kap > 0]
    assert np.all(inside > 0)
    # a joint crossing the 100 m build: revolutions 120 rpm * 100 m / (20 m/h)
    # = 36,000; cumulative damage = that / N (trapezoid error at the 2 edges: 1 %)
    N = 1.0 / (out["damage_per_m"][150] / (120 / 60 / (20 / 3600)))
    assert out["cumulative_damage"][-1] == pytest.approx(36_000 / N, rel=0.011)
