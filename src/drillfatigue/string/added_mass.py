"""Lateral inertia of the mud: the mud inside the pipe and the hydrodynamic added mass.

A pipe moving sideways carries the mud in its bore with it and accelerates
some of the annular mud around it; whirl and lateral-vibration forces scale
with the total. Per unit length (docs/bending.md):

* internal mud: m_i = rho_mud pi r_i^2 (moves with the pipe);
* added mass: m_a = C_a rho_mud pi r_o^2, the displaced mud times an
  added-mass coefficient. For a cylinder of radius r_o moving inside a fixed
  concentric cylinder of radius R (the hole) in an inviscid fluid,

      C_a = (R^2 + r_o^2) / (R^2 - r_o^2)

  (Fritz, "The effect of liquids on the dynamic motions of immersed solids",
  J. Eng. Ind. 94 (1972) 167-173; Chen, Wambsganss & Jendrzejczyk, J. Appl.
  Mech. 43 (1976) 325-329), which tends to 1 (the unconfined cylinder) as R
  grows and rises steeply as the clearance closes: about 2.1 for 5 in pipe
  and 4.4 for 6 3/4 in collars in an 8 1/2 in hole. The potential-flow value
  is an upper estimate for the eccentric, viscous annulus; ``coefficient``
  overrides it (e.g. 1.0, the open-water value).

These act on lateral motion only (axial and torsional motion drag the mud
much less; their damping is the drag model's business).
"""

from __future__ import annotations

import math

import numpy as np

from drillfatigue.errors import InputError
from drillfatigue.string.segments import Segments


def confined_added_mass_coefficient(od_m: np.ndarray | float, hole_diameter_m: float
                                    ) -> np.ndarray | float:
    """C_a = (R^2 + r_o^2)/(R^2 - r_o^2) of a cylinder in a concentric hole."""
    ro = 0.5 * np.asarray(od_m, dtype=np.float64)
    R = 0.5 * hole_diameter_m
    if np.any(ro <= 0.0) or np.any(ro >= R):
        raise InputError("od_m", "must be > 0 and smaller than the hole diameter",
                         f"0 < od_m < {hole_diameter_m}")
    c = (R * R + ro * ro) / (R * R - ro * ro)
    return c if c.ndim else float(c)


def lateral_mud_mass_per_m(segments: Segments, mud_density_kg_per_m3: float,
                           hole_diameter_m: float, coefficient: float | None = None
                           ) -> tuple[np.ndarray, np.ndarray]:
    """Internal mud mass and hydrodynamic added mass of each segment, per length.

    Parameters
    ----------
    segments : Segments
    mud_density_kg_per_m3 : float
    hole_diameter_m : float
        For the confined added-mass coefficient.
    coefficient : float, optional
        C_a; None uses :func:`confined_added_mass_coefficient`.

    Returns
    -------
    internal_kg_per_m, added_kg_per_m : ndarray, shape (n_segments,)
        Multiply by ``segments.length_m`` for the mass of a segment.
    """
    if not (math.isfinite(mud_density_kg_per_m3) and mud_density_kg_per_m3 >= 0.0):
        raise InputError("mud_density_kg_per_m3", f"must be >= 0, got {mud_density_kg_per_m3}",
                         ">= 0")
    ri = 0.5 * segments.id_m
    ro = 0.5 * segments.od_m
    ca = (confined_added_mass_coefficient(segments.od_m, hole_diameter_m)
          if coefficient is None else np.full(ro.shape, float(coefficient)))
    if coefficient is not None and not (0.0 <= coefficient <= 50.0):
        raise InputError("coefficient", f"must be in [0, 50], got {coefficient}", "0 <= C_a <= 50")
    internal = mud_density_kg_per_m3 * math.pi * ri * ri
    added = np.asarray(ca) * mud_density_kg_per_m3 * math.pi * ro * ro
    return internal, added


def lateral_mass_kg(segments: Segments, mud_density_kg_per_m3: float, hole_diameter_m: float,
                    coefficient: float | None = None) -> np.ndarray:
    """Mass of each segment for lateral motion: steel + internal mud + added mass, kg."""
    internal, added = lateral_mud_mass_per_m(segments, mud_density_kg_per_m3, hole_diameter_m,
                                             coefficient)
    return segments.mass_kg + (internal + added) * segments.length_m
