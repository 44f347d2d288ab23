"""Surface stresses of a tubular section from the six internal loads.

Sign conventions (fixed once, tested in ``tests/unit/fatigue/test_stress.py``):

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

Mud pressure (docs/bending.md, docs/fatigue.md): with internal and
external pressure p_i, p_o the wall carries the thick-wall (Lame) radial and
hoop stresses

    sigma_r(r) = A - B/r^2, sigma_theta(r) = A + B/r^2,
    A = (p_i r_i^2 - p_o r_o^2)/(r_o^2 - r_i^2), B = (p_i - p_o) r_i^2 r_o^2/(r_o^2 - r_i^2),

so sigma_r = -p_o and sigma_theta = (2 p_i r_i^2 - p_o (r_o^2 + r_i^2))/(r_o^2 - r_i^2)
at the outer surface, sigma_r = -p_i at the inner one; and the axial stress
comes from the true wall force F_true = F_eff + p_i A_i - p_o A_o
(A_i = pi r_i^2, A_o = pi r_o^2) rather than the effective tension F_eff that
the dynamics records (buoyed-weight statics give the effective force). With
p_i = p_o = p the two together add exactly -p to sigma_r, sigma_theta and
sigma_z: a hydrostatic stress, no shear on any plane. The axial SCF applies to
the whole true wall force; the Lame stresses are taken without concentration
(an assumption: a notch raises them far less than the bending stress).

References
----------
Pilkey, W. D., *Formulas for Stress, Strain and Structural Matrices*, 2nd ed.,
Wiley 2005, ch. 15 (thin-walled shear flow); Timoshenko, S. P. & Goodier, J. N.,
*Theory of Elasticity*, 3rd ed., McGraw-Hill 1970, section 28 (thick-walled
cylinder, Lame); Aadnoy, B. S., *Mechanics of Drilling*, Shaker 2006, ch. 2
(effective and true axial force); docs/fatigue.md#stresses.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from drillfatigue import rundir
from drillfatigue.errors import InputError
from drillfatigue.units import STANDARD_GRAVITY_M_PER_S2

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


def hydrostatic_pressure_Pa(tvd_m: np.ndarray | float, mud_density_kg_per_m3: float,
                            surface_pressure_Pa: float = 0.0) -> np.ndarray | float:
    """Hydrostatic mud pressure p = p_surface + rho_mud g TVD, Pa.

    Parameters
    ----------
    tvd_m : float or ndarray
        True vertical depth below the fluid surface, m.
    mud_density_kg_per_m3 : float
    surface_pressure_Pa : float
        Pressure at TVD 0 (e.g. the pump pressure for the inside of the string).
    """
    if not (math.isfinite(mud_density_kg_per_m3) and mud_density_kg_per_m3 >= 0.0):
        raise InputError("mud_density_kg_per_m3",
                         f"must be a finite number >= 0, got {mud_density_kg_per_m3!r}", ">= 0")
    p = surface_pressure_Pa + mud_density_kg_per_m3 * STANDARD_GRAVITY_M_PER_S2 * np.asarray(
        tvd_m, dtype=np.float64)
    return p if p.ndim else float(p)


@dataclass(frozen=True)
class Pressure:
    """Mud pressure on a section, constant over a load window (Pa).

    Attributes
    ----------
    internal_Pa, external_Pa : float
        Pressure inside the bore and in the annulus, Pa (>= 0).
    """

    internal_Pa: float = 0.0
    external_Pa: float = 0.0

    def __post_init__(self) -> None:
        for name in ("internal_Pa", "external_Pa"):
            v = getattr(self, name)
            if not (math.isfinite(v) and v >= 0.0):
                raise InputError(f"pressure.{name}", f"must be a finite number >= 0, got {v!r}",
                                 ">= 0")

    @property
    def is_zero(self) -> bool:
        """True when both pressures are zero (the stresses are the load-only ones)."""
        return self.internal_Pa == 0.0 and self.external_Pa == 0.0


def true_wall_force_N(effective_N: np.ndarray | float, section: Section,
                      pressure: Pressure) -> np.ndarray | float:
    """True axial wall force F_true = F_eff + p_i A_i - p_o A_o, N.

    ``effective_N`` is the effective tension (what buoyed-weight statics and
    the dynamics give, tension > 0); A_i = pi r_i^2 and A_o = pi r_o^2 are the
    areas enclosed by the inner and outer surfaces.
    """
    a_i = math.pi * (0.5 * section.id_m) ** 2
    a_o = math.pi * (0.5 * section.od_m) ** 2
    return effective_N + (pressure.internal_Pa * a_i - pressure.external_Pa * a_o)


def lame_stresses_Pa(section: Section, pressure: Pressure, r_m: float) -> tuple[float, float]:
    """Thick-wall (Lame) radial and hoop stress at radius ``r_m``, Pa.

    Returns
    -------
    sigma_r, sigma_theta : float
        Radial and hoop stress (tension > 0) at r_i <= r <= r_o.
    """
    ri, ro = 0.5 * section.id_m, 0.5 * section.od_m
    if not (ri - 1e-12 <= r_m <= ro + 1e-12) or r_m <= 0.0:
        raise InputError("r_m", f"must lie in the wall, got {r_m!r}", f"{ri} <= r <= {ro}")
    pi, po = pressure.internal_Pa, pressure.external_Pa
    d = ro * ro - ri * ri
    A = (pi * ri * ri - po * ro * ro) / d
    B = (pi - po) * ri * ri * ro * ro / d
    return A - B / (r_m * r_m), A + B / (r_m * r_m)


def surface_pressure_stresses(section: Section, scf: SCF, pressure: Pressure,
                              surface: str = "outer") -> tuple[float, float, float]:
    """Constant stresses that mud pressure adds at a surface point, Pa.

    Parameters
    ----------
    section, scf : Section, SCF
    pressure : Pressure
    surface : {'outer', 'inner'}

    Returns
    -------
    d_sigma_z, sigma_theta, sigma_r : float
        Axial stress from the pressure end loads of the true wall force
        (K_a (p_i A_i - p_o A_o)/A), and the Lame hoop and radial stresses at
        the surface (sigma_r = -p_o outside, -p_i inside).
    """
    if surface not in ("outer", "inner"):
        raise InputError("surface", f"unknown surface {surface!r}", "outer, inner")
    r = 0.5 * (section.od_m if surface == "outer" else section.id_m)
    if surface == "inner" and r == 0.0:
        raise InputError("surface", "a solid section has no inner surface", "outer")
    d_f = float(true_wall_force_N(0.0, section, pressure))
    s_r, s_t = lame_stresses_Pa(section, pressure, r)
    return scf.axial * d_f / section.area_m2, s_t, s_r
