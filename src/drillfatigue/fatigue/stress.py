"""Surface stresses of a tubular section from the six internal loads.

Sign conventions (fixed once, tested in ``tests/unit/test_fatigue_stress.py``):

* local frame of a joint: z along the pipe axis, x and y across it;
* a surface point sits at circumferential angle ``phi`` measured from +x
  towards +y, at position ``(r cos phi, r sin phi)``;
* axial force F > 0 is tension; bending moment vectors (Mx, My) follow the
  right-hand rule, so ``sigma_z = K_a F/A + K_b (Mx sin phi - My cos phi) r/I``
  (Mx > 0 stretches the +y fibre, My > 0 stretches the -x fibre);
* ``tau`` is the surface shear stress tau_z-theta (theta the hoop direction):
  ``tau = K_t [T r/J + (2/A)(-Vx sin phi + Vy cos phi)]``; T > 0 turns the
  +z face anticlockwise seen from +z; the transverse-shear term is the thin-tube
  shear flow (peak 2V/A at the neutral axis), whose resultant over the section
  is (Vx, Vy).

The outer surface is in plane stress (sigma_z, tau); internal/external
pressure is not included (Lame hoop/radial terms could be added later).

References
----------
Pilkey, W. D., *Formulas for Stress, Strain and Structural Matrices*, 2nd ed.,
Wiley 2005, ch. 15 (thin-walled shear flow); docs/fatigue.md#stresses.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from drillfatigue import rundir
from drillfatigue.errors import InputError

#: Load columns of ``loads.parquet`` in the order used by every array here.
LOAD_COLUMNS: tuple[str, ...] = rundir.LOAD_COLUMNS


@dataclass(frozen=True)
class Section:
    """Tube section properties (SI).

    Attributes
    ----------
    od_m, id_m : float
        Outer and inner diameter, m.
    """

    od_m: float
    id_m: float

    def __post_init__(self) -> None:
        if not (math.isfinite(self.od_m) and self.od_m > 0.0):
            raise InputError("section.od_m", f"must be a finite number > 0, got {self.od_m!r}",
                             "0 < od_m")
        if not (math.isfinite(self.id_m) and 0.0 <= self.id_m < self.od_m):
            raise InputError("section.id_m", f"must satisfy 0 <= id_m < od_m, got {self.id_m!r}",
                             f"0 <= id_m < {self.od_m}")

    @property
    def area_m2(self) -> float:
        """Cross-section area A = pi (Do^2 - Di^2)/4, m^2."""
        return math.pi * (self.od_m**2 - self.id_m**2) / 4.0

    @property
    def inertia_m4(self) -> float:
        """Second moment of area I = pi (Do^4 - Di^4)/64, m^4."""
        return math.pi * (self.od_m**4 - self.id_m**4) / 64.0

    @property
    def polar_m4(self) -> float:
        """Polar moment J = 2 I, m^4."""
        return 2.0 * self.inertia_m4

    @property
    def r_m(self) -> float:
        """Outer radius, m."""
        return self.od_m / 2.0


@dataclass(frozen=True)
class SCF:
    """Stress concentration factors of a location (dimensionless, >= 1 typically).

    Attributes
    ----------
    axial, bending, torsion : float
        Factors on the nominal axial, bending and shear (torsion and transverse
        shear) stresses.
    """

    axial: float = 1.0
    bending: float = 1.0
    torsion: float = 1.0


def surface_angles_rad(n_points: int) -> np.ndarray:
    """Equally spaced surface angles phi_k = 2 pi k / n, shape (n,), rad."""
    if n_points < 4:
        raise InputError("fatigue.n_surface_points", f"must be >= 4, got {n_points}", ">= 4")
    return 2.0 * np.pi * np.arange(n_points) / n_points


def surface_coefficients(section: Section, scf: SCF, n_points: int
                         ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Linear maps from the six loads to (sigma_z, tau) at each surface point.

    Returns
    -------
    coef_sigma, coef_tau : ndarray, shape (n_points, 6)
        ``sigma_z[p, t] = coef_sigma[p] @ loads[t]`` in Pa, loads ordered as
        :data:`LOAD_COLUMNS` (N, N, N, N m, N m, N m).
    phi : ndarray, shape (n_points,)
        Surface angles, rad.
    """
    phi = surface_angles_rad(n_points)
    A, I, J, r = section.area_m2, section.inertia_m4, section.polar_m4, section.r_m
    s, c = np.sin(phi), np.cos(phi)
    cs = np.zeros((n_points, 6))
    ct = np.zeros((n_points, 6))
    cs[:, 0] = scf.axial / A
    cs[:, 3] = scf.bending * r / I * s
    cs[:, 4] = -scf.bending * r / I * c
    ct[:, 1] = -scf.torsion * 2.0 / A * s
    ct[:, 2] = scf.torsion * 2.0 / A * c
    ct[:, 5] = scf.torsion * r / J
    return cs, ct, phi


def surface_stresses(loads: np.ndarray, section: Section, scf: SCF, n_points: int
                     ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Axial and shear stress histories round the outer surface.

    Parameters
    ----------
    loads : ndarray, shape (n_time, 6)
        Internal loads ordered as :data:`LOAD_COLUMNS`, N and N m.
    section : Section
    scf : SCF
    n_points : int
        Number of equally spaced surface points.

    Returns
    -------
    sigma, tau : ndarray, shape (n_points, n_time)
        sigma_z and tau_z-theta, Pa.
    phi : ndarray, shape (n_points,)
        Surface angles, rad.
    """
    loads = np.asarray(loads, dtype=np.float64)
    if loads.ndim != 2 or loads.shape[1] != 6:
        raise InputError("loads", f"must have shape (n_time, 6), got {loads.shape}",
                         "(n_time, 6) in the order " + ", ".join(LOAD_COLUMNS))
    cs, ct, phi = surface_coefficients(section, scf, n_points)
    return cs @ loads.T, ct @ loads.T, phi
