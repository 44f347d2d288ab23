"""Sign conventions of the surface stresses (fatigue.stress)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from drillfatigue.errors import InputError
from drillfatigue.fatigue.stress import SCF, Section, surface_stresses

SEC = Section(0.127, 0.1086)
N_PTS = 36  # phi = 0, 10, ..., 350 deg


def _one(load_index: int, value: float, scf: SCF = SCF()) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    L = np.zeros((1, 6))
    L[0, load_index] = value
    s, t, phi = surface_stresses(L, SEC, scf, N_PTS)
    return s[:, 0], t[:, 0], phi


def test_section_properties_match_closed_form() -> None:
    D, d = 0.127, 0.1086
    assert SEC.area_m2 == pytest.approx(math.pi * (D**2 - d**2) / 4, rel=1e-15)
    assert SEC.inertia_m4 == pytest.approx(math.pi * (D**4 - d**4) / 64, rel=1e-15)
    assert SEC.polar_m4 == pytest.approx(2 * SEC.inertia_m4, rel=1e-15)


def test_pure_tension_is_uniform_and_positive() -> None:
    s, t, _ = _one(0, 1e5, SCF(axial=2.0))
    np.testing.assert_allclose(s, 2.0 * 1e5 / SEC.area_m2, rtol=1e-14)
    np.testing.assert_allclose(t, 0.0, atol=0.0)


def test_bending_about_x_stretches_plus_y_fibre() -> None:
    s, t, phi = _one(3, 1e4)
    peak = 1e4 * SEC.r_m / SEC.inertia_m4
    assert s[9] == pytest.approx(peak, rel=1e-14)  # phi = 90 deg, +y fibre in tension
    assert s[27] == pytest.approx(-peak, rel=1e-14)
    assert abs(s[0]) < 1e-9 * peak and abs(s[18]) < 1e-9 * peak  # neutral axis on x
    np.testing.assert_allclose(t, 0.0, atol=0.0)


def test_bending_about_y_stretches_minus_x_fibre() -> None:
    s, _, _ = _one(4, 1e4)
    peak = 1e4 * SEC.r_m / SEC.inertia_m4
    assert s[18] == pytest.approx(peak, rel=1e-14)  # phi = 180 deg, the -x fibre
    assert s[0] == pytest.approx(-peak, rel=1e-14)


def test_pure_torsion_uniform_shear() -> None:
    s, t, _ = _one(5, 2e4, SCF(torsion=1.5))
    np.testing.assert_allclose(t, 1.5 * 2e4 * SEC.r_m / SEC.polar_m4, rtol=1e-14)
    np.testing.assert_allclose(s, 0.0, atol=0.0)


@pytest.mark.parametrize("index,direction", [(1, np.array([1.0, 0.0])), (2, np.array([0.0, 1.0]))])
def test_pure_shear_peaks_at_neutral_axis_and_sums_to_the_force(index: int,
                                                                 direction: np.ndarray) -> None:
    V = 3e3
    s, t, phi = _one(index, V)
    np.testing.assert_allclose(s, 0.0, atol=0.0)
    assert np.max(np.abs(t)) == pytest.approx(2 * V / SEC.area_m2, rel=1e-12)
    # resultant of the shear flow tau e_theta over the thin wall: A/n per point.
    # The midpoint rule on a trigonometric polynomial of degree 2 is exact for n >= 3.
    e_theta = np.column_stack([-np.sin(phi), np.cos(phi)])
    resultant = (t[:, None] * e_theta).sum(axis=0) * SEC.area_m2 / phi.size
    np.testing.assert_allclose(resultant, V * direction, atol=1e-9 * V)


def test_bad_section_and_shape_raise() -> None:
    with pytest.raises(InputError):
        Section(0.1, 0.2)
    with pytest.raises(InputError):
        surface_stresses(np.zeros((3, 5)), SEC, SCF(), 36)
