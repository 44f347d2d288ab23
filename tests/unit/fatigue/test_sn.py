"""S-N library, Miner and mean-stress corrections (fatigue.sn)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from drillfatigue.errors import InputError
from drillfatigue.fatigue import kernels as K
from drillfatigue.fatigue.rainflow import find_cycles
from drillfatigue.fatigue.sn import CURVE_NAMES, correct_mean_stress, get_curve, get_grade, user_curve
from drillfatigue.units import MPA_PA, PSI_PA


def test_dnv_d_curve_at_100_mpa() -> None:
    # DNV-RP-C203 check quoted in docs/fatigue.md: N = 10**(12.164 - 3*2) = 1.4588e6
    # (4 significant digits given, so rel 5e-5)
    assert get_curve("D").cycles_to_failure(100 * MPA_PA)[0] == pytest.approx(1.4588e6, rel=5e-5)


@pytest.mark.parametrize("name", ["B1", "C", "D", "F1", "W3"])
def test_air_curves_are_continuous_at_the_knee(name: str) -> None:
    c = get_curve(name)
    Sd = c.fatpack_curve.Sd
    # the tabulated log a2 agrees with the knee at 1e7 to the table's 3 decimals
    assert math.log10(c.cycles_to_failure(Sd * MPA_PA)[0]) == pytest.approx(7.0, abs=1e-9)
    assert 10 ** (c.log_a[1] - c.m[1] * math.log10(Sd)) == pytest.approx(1e7, rel=0.01)
    assert "DNV-RP-C203" in c.reference


def test_seawater_knee_and_free_corrosion_slope() -> None:
    sw = get_curve("D", "seawater_cp")
    assert math.log10(sw.cycles_to_failure(sw.fatpack_curve.Sd * MPA_PA)[0]) == pytest.approx(6.0)
    fc = get_curve("D", "free_corrosion")
    n1, n2 = fc.cycles_to_failure(np.array([10e6, 20e6]))
    assert n1 / n2 == pytest.approx(8.0, rel=1e-12)  # single slope m = 3 down to low stress


def test_thread_aliases_and_user_curve() -> None:
    assert get_curve("thread_rolled").name == "F1"
    assert get_curve("thread_cut").name == "W3"
    u = user_curve(3.0, 12.164, 5.0, 1e7, cutoff_N=1e8)
    np.testing.assert_allclose(u.cycles_to_failure([100e6])[0],
                               get_curve("D").cycles_to_failure([100e6])[0], rtol=1e-12)
    Sl = u.fatpack_curve.Sl
    assert np.isinf(u.cycles_to_failure([0.99 * Sl * MPA_PA])[0])


@pytest.mark.parametrize("bad", [("Z", "air"), ("D", "mud")])
def test_unknown_names_list_the_allowed(bad: tuple[str, str]) -> None:
    with pytest.raises(InputError, match="allowed"):
        get_curve(*bad)
    with pytest.raises(InputError, match="E-75, X-95, G-105, S-135"):
        get_grade("P-110")


def test_thickness_correction() -> None:
    c = get_curve("D")
    assert c.thickness_factor(0.020) == 1.0
    assert c.thickness_factor(0.050) == pytest.approx(2.0**0.2, rel=1e-15)


@pytest.mark.parametrize("name", ["B1", "D", "W3"])
@pytest.mark.parametrize("env", ["air", "seawater_cp", "free_corrosion"])
def test_kernel_curve_equals_fatpack(name: str, env: str) -> None:
    c = get_curve(name, env)
    seg = c.kernel_arrays()
    S = np.geomspace(5.0, 900.0, 40)
    inv = np.array([K.sn_inverse_life(s, *seg) for s in S])
    np.testing.assert_allclose(inv, 1.0 / c.cycles_to_failure(S * MPA_PA), rtol=1e-12)


@pytest.mark.parametrize("S_MPa", [60.0, 300.0])
def test_constant_amplitude_miner_is_n_over_N(S_MPa: float) -> None:
    n = 1000
    y = np.tile([S_MPa / 2, -S_MPa / 2], n) * MPA_PA
    y = np.r_[y, y[0]]  # n full cycles, closed
    c = find_cycles(y, "half")
    curve = get_curve("D")
    D = float(np.sum(c.count / curve.cycles_to_failure(c.ranges)))
    # every cycle has the same range: the sum is n/N(S) up to summation rounding
    assert D == pytest.approx(n / curve.cycles_to_failure(S_MPa * MPA_PA)[0], rel=1e-12)
    assert c.count.sum() == n


def test_mean_stress_corrections() -> None:
    S, Sm = np.array([100e6, 100e6, 100e6]), np.array([0.0, 200e6, -300e6])
    su = get_grade("S-135").tensile_Pa
    assert su == pytest.approx(145_000 * PSI_PA)
    np.testing.assert_array_equal(correct_mean_stress(S, Sm, "none", su), S)
    g = correct_mean_stress(S, Sm, "goodman", su)
    assert g[0] == S[0] and g[1] == pytest.approx(100e6 / (1 - 200e6 / su)) and g[2] == S[2]
    swt = correct_mean_stress(S, Sm, "swt", su)
    # SWT: sqrt(S_max * S_range) form of fatpack; zero for a fully compressive cycle
    assert swt[0] == pytest.approx(100e6) and swt[1] == pytest.approx(math.sqrt(500e6 * 100e6))
    assert swt[2] == 0.0
    comp = correct_mean_stress(S, Sm, "compressive", su, compressive_alpha=0.6)
    assert comp[2] < S[2] and comp[1] == S[1]
    with pytest.raises(InputError):
        correct_mean_stress(S, Sm, "gerber", su)


def test_library_names_are_documented() -> None:
    assert set(CURVE_NAMES) >= {"B1", "C", "D", "F1", "W3", "thread_rolled", "thread_cut"}
