"""Segmentation of the string into rigid segments (docs/model.md#bodies, docs/model.md#joints).

Each component of ``n_segments`` is cut into equal rigid segments; drill pipe
and heavy-weight pipe with ``joints_per_segment`` are cut at their joints
(:attr:`drillfatigue.config.string.ComponentConfig.segment_lengths_m`). Segment
properties are those of a tube of the body section; tool joints (a fraction
``tool_joint_length_fraction`` of the length with the connection section) add
mass and set the contact radius but not stiffness (standard stiff-string
practice). Inertia of a tube segment (docs/model.md#bodies):
I_axial = m (r_o^2 + r_i^2) / 2, I_transverse = m (3 (r_o^2 + r_i^2) + L^2) / 12.
Buoyancy uses the displaced steel volume m / rho_steel (open-ended pipe, mud
inside and out: the buoyed weight is the effective weight).

Hole-fit rule (docs/bending.md). A straight rigid segment of length L in a
hole of curvature kappa departs from the arc by L^2 kappa / 8 at its middle.
When that approaches the diametral clearance 2c the segment cannot lie along
one wall: its ends touch one wall and its middle the other, and the supports
of the span bending sit on opposite walls. :func:`build_segments`, given the
largest curvature ``kappa_max`` each component can meet and the hole radius
there, cuts every component that is not cut at its joints into equal
segments no longer than

    L_fit = sqrt(8 f_seg c / kappa_max)

(``string.segment_fit_fraction`` = f_seg, c = hole radius - body radius),
keeping ``n_segments`` when that is already enough. Drill pipe and
heavy-weight pipe are left whole: their tool joints are the supports.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from drillfatigue.config.string import JOINTED_TYPES, ComponentConfig, StringConfig
from drillfatigue.errors import InputError

#: Component type names; ``Segments.component_type_code`` indexes this tuple.
COMPONENT_TYPES: tuple[str, ...] = ("bit", "collar", "stabilizer", "hwdp", "drill_pipe", "sub",
                                    "jar", "mwd")


@dataclass(frozen=True)
class Segments:
    """Rigid segments and the joints between neighbours, SI, index 0 at the bit.

    Per segment (shape (n,)): ``length_m``, ``od_m``, ``id_m`` (body section),
    ``mass_kg``, ``volume_m3`` (steel volume, for buoyancy), ``buoyed_weight_N``,
    ``contact_radius_m``, ``inertia_axial_kg_m2``, ``inertia_transverse_kg_m2``,
    ``ea_N``, ``ei_Nm2``, ``gj_Nm2``, ``kga_N`` (kappa G A), ``component_index``,
    ``component_type`` (list of names), ``component_type_code`` (index into
    :data:`COMPONENT_TYPES`), ``s_from_bit_m`` (distance bit -> segment centre),
    ``mass_per_length_kg_per_m``.

    Per joint between segment j and j+1 (shape (n-1,)): ``joint_s_from_bit_m``,
    ``body_od_m``, ``body_id_m``, ``conn_od_m``, ``conn_id_m`` and
    ``joint_component_type`` (of the weaker side, smaller EI), ``joint_component``.
    """

    length_m: np.ndarray
    od_m: np.ndarray
    id_m: np.ndarray
    mass_kg: np.ndarray
    volume_m3: np.ndarray
    buoyed_weight_N: np.ndarray
    contact_radius_m: np.ndarray
    inertia_axial_kg_m2: np.ndarray
    inertia_transverse_kg_m2: np.ndarray
    ea_N: np.ndarray
    ei_Nm2: np.ndarray
    gj_Nm2: np.ndarray
    kga_N: np.ndarray
    mass_per_length_kg_per_m: np.ndarray
    component_index: np.ndarray
    component_type: list[str]
    component_type_code: np.ndarray
    s_from_bit_m: np.ndarray
    joint_s_from_bit_m: np.ndarray
    body_od_m: np.ndarray
    body_id_m: np.ndarray
    conn_od_m: np.ndarray
    conn_id_m: np.ndarray
    joint_component_type: list[str]
    joint_component: np.ndarray

    @property
    def n_segments(self) -> int:
        """Number of segments."""
        return int(self.length_m.size)

    @property
    def n_joints(self) -> int:
        """Number of joints between neighbouring segments (n - 1)."""
        return int(self.joint_s_from_bit_m.size)

    @property
    def total_length_m(self) -> float:
        """Length bit -> top of the top segment (m)."""
        return float(self.length_m.sum())


def hole_fit_length_m(clearance_m: float, curvature_rad_per_m: float,
                      fit_fraction: float) -> float:
    """Longest rigid segment that follows a hole of curvature kappa: sqrt(8 f c / kappa), m.

    ``inf`` in a straight hole (kappa = 0).
    """
    if not (clearance_m > 0.0):
        raise InputError("clearance_m", f"must be > 0, got {clearance_m!r}",
                         "hole radius > body radius")
    if not (curvature_rad_per_m >= 0.0 and math.isfinite(curvature_rad_per_m)):
        raise InputError("curvature_rad_per_m", f"must be finite and >= 0, got "
                         f"{curvature_rad_per_m!r}", ">= 0")
    if curvature_rad_per_m == 0.0:
        return math.inf
    return math.sqrt(8.0 * fit_fraction * clearance_m / curvature_rad_per_m)


def fitted_segment_lengths_m(comp: ComponentConfig, fit_fraction: float | None,
                             curvature_rad_per_m: float, hole_radius_m: float) -> list[float]:
    """Segment lengths of one component under the hole-fit rule (module docstring), m.

    Components cut at their joints (``joints_per_segment``) and drill pipe or
    heavy-weight pipe keep :attr:`ComponentConfig.segment_lengths_m`; so does
    every component when ``fit_fraction`` is None.
    """
    base = comp.segment_lengths_m
    if fit_fraction is None or comp.type in JOINTED_TYPES or comp.joints_per_segment is not None \
            or curvature_rad_per_m == 0.0:
        return base
    clearance = hole_radius_m - 0.5 * comp.od_m
    if not (clearance > 0.0):
        raise InputError("string.components.od_m",
                         f"body OD {comp.od_m} does not fit the hole {2.0 * hole_radius_m}",
                         f"< {2.0 * hole_radius_m}")
    l_fit = hole_fit_length_m(clearance, curvature_rad_per_m, fit_fraction)
    n = max(comp.n_segments, math.ceil(comp.length_m / l_fit - 1e-9))
    if n == comp.n_segments:
        return base
    return [comp.length_m / n] * n


def build_segments(string_cfg: StringConfig, mud_density_kg_per_m3: float,
                   curvature_rad_per_m: np.ndarray | None = None,
                   hole_radius_m: np.ndarray | None = None) -> Segments:
    """Cut the string into rigid segments.

    Parameters
    ----------
    string_cfg : StringConfig
        Components from the bit up.
    mud_density_kg_per_m3 : float
        Mud density, for the buoyed weight.
    curvature_rad_per_m, hole_radius_m : ndarray, shape (n_components,), optional
        Largest hole curvature (rad/m) and smallest hole radius (m) over the MD
        range each component can occupy. Given together, they apply the
        hole-fit rule with ``string.segment_fit_fraction`` (module
        docstring); without them each component keeps its ``n_segments``
        (per-length properties, all a soft-string caller needs, are the same).

    Returns
    -------
    Segments
        Per-segment and per-joint arrays, index 0 at the bit end.
    """
    n_comp = len(string_cfg.components)
    fit = curvature_rad_per_m is not None and hole_radius_m is not None
    if fit:
        kap = np.asarray(curvature_rad_per_m, dtype=np.float64)
        rad = np.asarray(hole_radius_m, dtype=np.float64)
        if kap.shape != (n_comp,) or rad.shape != (n_comp,):
            raise InputError("curvature_rad_per_m", f"needs one value per component ({n_comp})",
                             "arrays of shape (n_components,)")
    cols: dict[str, list[float]] = {k: [] for k in (
        "length_m", "od_m", "id_m", "mass_kg", "volume_m3", "contact_radius_m", "ia", "it",
        "ea", "ei", "gj", "kga", "mpl", "comp", "code", "conn_od", "conn_id")}
    types: list[str] = []
    kappa = string_cfg.shear_coefficient
    for ci, comp in enumerate(string_cfg.components):
        mat = comp.material
        ro, ri = 0.5 * comp.od_m, 0.5 * comp.id_m
        a_body = math.pi * (ro * ro - ri * ri)
        a_conn = 0.25 * math.pi * (comp.conn_od_m ** 2 - comp.conn_id_m ** 2)
        f = comp.tool_joint_length_fraction
        mpl = comp.linear_mass_kg_per_m
        if mpl is None:
            mpl = mat.density_kg_per_m3 * ((1.0 - f) * a_body + f * a_conn)
        i_area = 0.25 * math.pi * (ro ** 4 - ri ** 4)
        lengths = (fitted_segment_lengths_m(comp, string_cfg.segment_fit_fraction,
                                            float(kap[ci]), float(rad[ci]))
                   if fit else comp.segment_lengths_m)
        for length in lengths:
            m = mpl * length
            cols["length_m"].append(length)
            cols["od_m"].append(comp.od_m)
            cols["id_m"].append(comp.id_m)
            cols["mass_kg"].append(m)
            cols["volume_m3"].append(m / mat.density_kg_per_m3)
            cols["contact_radius_m"].append(comp.outer_contact_radius_m)
            cols["ia"].append(0.5 * m * (ro * ro + ri * ri))
            cols["it"].append(m * (3.0 * (ro * ro + ri * ri) + length * length) / 12.0)
            cols["ea"].append(mat.youngs_modulus_Pa * a_body)
            cols["ei"].append(mat.youngs_modulus_Pa * i_area)
            cols["gj"].append(mat.shear_modulus_Pa * 2.0 * i_area)
            cols["kga"].append(kappa * mat.shear_modulus_Pa * a_body)
            cols["mpl"].append(mpl)
            cols["comp"].append(ci)
            cols["code"].append(COMPONENT_TYPES.index(comp.type))
            cols["conn_od"].append(comp.conn_od_m)
            cols["conn_id"].append(comp.conn_id_m)
            types.append(comp.type)
    arr = {k: np.asarray(v, dtype=np.float64) for k, v in cols.items()}
    length = arr["length_m"]
    top_end = np.cumsum(length)
    s_centre = top_end - 0.5 * length
    n = length.size
    # joint j between segment j and j+1: take the section of the weaker side
    weaker = np.where(arr["ei"][:-1] <= arr["ei"][1:], np.arange(n - 1), np.arange(1, n))
    mass = arr["mass_kg"]
    buoyed = (mass - mud_density_kg_per_m3 * arr["volume_m3"]) * 9.80665
    return Segments(
        length_m=length,
        od_m=arr["od_m"],
        id_m=arr["id_m"],
        mass_kg=mass,
        volume_m3=arr["volume_m3"],
        buoyed_weight_N=buoyed,
        contact_radius_m=arr["contact_radius_m"],
        inertia_axial_kg_m2=arr["ia"],
        inertia_transverse_kg_m2=arr["it"],
        ea_N=arr["ea"],
        ei_Nm2=arr["ei"],
        gj_Nm2=arr["gj"],
        kga_N=arr["kga"],
        mass_per_length_kg_per_m=arr["mpl"],
        component_index=arr["comp"].astype(np.int64),
        component_type=types,
        component_type_code=arr["code"].astype(np.int64),
        s_from_bit_m=s_centre,
        joint_s_from_bit_m=top_end[:-1].copy(),
        body_od_m=arr["od_m"][weaker],
        body_id_m=arr["id_m"][weaker],
        conn_od_m=arr["conn_od"][weaker],
        conn_id_m=arr["conn_id"][weaker],
        joint_component_type=[types[k] for k in weaker],
        joint_component=arr["comp"].astype(np.int64)[weaker],
    )
