"""Critical-plane criteria against closed forms (docs/fatigue.md#critical-plane).

Loads are constant-amplitude cosines sampled with 400 points per period so
that every peak is a sample (cos(2 pi k / 400) = +-1 at k = 0, 200, ...).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from drillfatigue.fatigue.critical_plane import CriterionParams, DamageOptions, evaluate_location
from drillfatigue.fatigue.sn import get_curve
from drillfatigue.fatigue.stress import SCF, Section

SEC = Section(0.127, 0.1086)
N_PER, N_CYC = 400, 5
WAVE = np.cos(2 * np.pi * np.arange(N_PER * N_CYC + 1) / N_PER)
PARAMS = CriterionParams(findley_k=0.25)


def loads(sigma_a: float = 0.0, tau_a: float = 0.0) -> np.ndarray:
    L = np.zeros((WAVE.size, 6))
    L[:, 0] = sigma_a * SEC.area_m2 * WAVE
    L[:, 5] = tau_a * SEC.polar_m4 / SEC.r_m * WAVE
    return L


@pytest.mark.parametrize("sigma_a", [150e6, 40e6])  # above and below the B1 knee (107 MPa)
def test_matake_reduces_to_the_uniaxial_result(sigma_a: float) -> None:
    curve = get_curve("B1")
    res = evaluate_location(loads(sigma_a), SEC, SCF(), curve, "matake", PARAMS,
                            options=DamageOptions(mean_stress="none"))
    assert res.critical_plane_deg in (45.0, 135.0)  # 40/50 deg grid point refined by 5 deg
    n_over_N = N_CYC / curve.cycles_to_failure(2 * sigma_a)[0]
    # 4 full + 2 half cycles of range 2 sigma_a: Miner gives exactly n/N(S);
    # only floating-point rounding separates them (1e-12)
    assert res.uniaxial_damage == pytest.approx(n_over_N, rel=1e-12)
    assert res.damage == pytest.approx(n_over_N, rel=1e-12)
    assert res.param_max_Pa == pytest.approx(sigma_a, rel=1e-12)


def test_findley_pure_torsion_closed_form() -> None:
    tau_a, k = 80e6, PARAMS.findley_k
    res = evaluate_location(loads(tau_a=tau_a), SEC, SCF(), get_curve("B1"), "findley", PARAMS)
    # plane found to 0.3125 deg after 4 refinements of a 10 deg grid: the
    # parameter is flat at its maximum, error ~ (2 dtheta)^2 / 2 < 1e-4
    assert res.param_max_Pa == pytest.approx(tau_a * math.sqrt(1 + k * k), rel=1e-4)
    theta_star = math.degrees(math.atan(k)) / 2  # tan 2 theta = k
    d = min(abs(res.critical_plane_deg - theta_star), abs(res.critical_plane_deg - (180 - theta_star)))
    assert d <= 0.32


def test_findley_pure_tension_closed_form() -> None:
    sigma_a, k = 120e6, PARAMS.findley_k
    res = evaluate_location(loads(sigma_a), SEC, SCF(), get_curve("B1"), "findley", PARAMS)
    assert res.param_max_Pa == pytest.approx(sigma_a * (k + math.sqrt(1 + k * k)) / 2, rel=1e-4)


def test_proportional_axial_torsion_plane_is_the_maximum_shear_plane() -> None:
    sigma_a, tau_a = 100e6, 50e6
    res = evaluate_location(loads(sigma_a, tau_a), SEC, SCF(), get_curve("B1"), "matake", PARAMS,
                            options=DamageOptions(mean_stress="none"))
    # tau_u(theta) = -(sigma/2) sin 2theta + tau cos 2theta is largest at
    # 2 theta* = atan2(-sigma_a/2, tau_a) and at theta* + 90 (conjugate plane)
    t1 = (math.degrees(math.atan2(-sigma_a / 2, tau_a)) / 2) % 180
    cands = [t1, (t1 + 90) % 180]
    th = res.critical_plane_deg
    assert min(min(abs(th - c), 180 - abs(th - c)) for c in cands) <= 0.32
    # on the returned plane the Matake parameter is the closed form exactly
    t = math.radians(th)
    amp = abs(-sigma_a / 2 * math.sin(2 * t) + tau_a * math.cos(2 * t))
    sn = abs(sigma_a * math.cos(t) ** 2 + tau_a * math.sin(2 * t))
    r = PARAMS.torsion_to_tension_ratio
    assert res.param_max_Pa == pytest.approx((amp + (2 * r - 1) * sn) / r, rel=1e-9)


def test_fatemi_socie_pure_torsion_closed_form() -> None:
    tau_a = 60e6
    res = evaluate_location(loads(tau_a=tau_a), SEC, SCF(), get_curve("B1"), "fatemi_socie",
                            PARAMS)
    # family A planes: tau amplitude tau_a |cos 2t|, normal stress at the turning
    # instants +-tau_a sin 2t; the parameter tau_a|cos 2t|(1 + k tau_a|sin 2t|/sigma_y)
    # maximised on a dense grid (1e-4 deg); tolerance as for Findley
    t = np.radians(np.linspace(0, 90, 900_001))
    f = tau_a * np.abs(np.cos(2 * t)) * (1 + PARAMS.fs_k * tau_a * np.abs(np.sin(2 * t))
                                         / PARAMS.yield_Pa)
    assert res.param_max_Pa == pytest.approx(f.max(), rel=1e-4)
    assert res.param_max_Pa > tau_a  # the normal stress moves the plane off theta = 0
