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
heavy-weight pipe are only ever cut at their joints (their tool joints are
the supports): when a listed segment is longer than ``L_fit`` for the hole it
can meet, the component is re-cut into whole joints, each segment taking as
many as fit the curvature where it can be (at most the listed length, at
least one joint), so pipe in the vertical keeps long segments.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from drillfatigue.config.string import (
    COMPONENT_TYPES, JOINTED_TYPES, ComponentConfig, StringConfig,
)
from drillfatigue.errors import InputError
from drillfatigue.units import STANDARD_GRAVITY_M_PER_S2


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


@dataclass(frozen=True)
class HoleFit:
    """The hole a string can meet during a run, for the hole-fit rule (module docstring).

    A string point ``s`` m from the bit sits between MD ``bit_md_lo_m - s`` and
    ``bit_md_hi_m - s`` (the bit's extreme positions over the run); the top of
    the top component reaches up to ``top_md_m``. ``md_m`` (P,): path stations;
    per interval between them (P - 1,): ``curvature_rad_per_m`` and
    ``radius_m`` (hole radius).
    """

    md_m: np.ndarray
    curvature_rad_per_m: np.ndarray
    radius_m: np.ndarray
    bit_md_lo_m: float
    bit_md_hi_m: float
    top_md_m: float

    def over(self, s_lo_m: float, s_hi_m: float, to_top: bool = False) -> tuple[float, float]:
        """Largest curvature (rad/m) and smallest hole radius (m) the string stretch
        ``s_lo_m .. s_hi_m`` (from the bit) can meet; ``to_top``: it reaches the top MD."""
        md = self.md_m
        md_top = self.top_md_m if to_top else self.bit_md_lo_m - s_hi_m
        md_bot = self.bit_md_hi_m - s_lo_m
        sel = (md[1:] >= md_top) & (md[:-1] <= md_bot)
        if not sel.any():  # beyond the path: its nearest interval
            sel = np.zeros(md.size - 1, dtype=bool)
            sel[int(np.clip(np.searchsorted(md, md_bot) - 1, 0, md.size - 2))] = True
        return float(self.curvature_rad_per_m[sel].max()), float(self.radius_m[sel].min())


def _clearance(comp: ComponentConfig, hole_radius_m: float) -> float:
    clearance = hole_radius_m - 0.5 * comp.od_m
    if not (clearance > 0.0):
        raise InputError("string.components.od_m",
                         f"body OD {comp.od_m} does not fit the hole {2.0 * hole_radius_m}",
                         f"< {2.0 * hole_radius_m}")
    return clearance


def _fits(length_m: float, comp: ComponentConfig, fit_fraction: float, hole: HoleFit,
          s_lo_m: float, s_hi_m: float, to_top: bool = False) -> bool:
    kappa, radius = hole.over(s_lo_m, s_hi_m, to_top)
    return length_m * length_m * kappa / 8.0 <= fit_fraction * _clearance(comp, radius)


def fitted_segment_lengths_m(comp: ComponentConfig, fit_fraction: float | None,
                             hole: HoleFit | None, s0_m: float = 0.0,
                             is_top: bool = False) -> list[float]:
    """Segment lengths of one component under the hole-fit rule (module docstring), m.

    ``s0_m``: distance bit -> the component's lower end; ``is_top``: the top
    component (it reaches the top MD). Collars and the other BHA components:
    the fewest equal segments (at least ``n_segments``) no longer than
    ``L_fit`` for the largest curvature the component can meet. Drill pipe and
    heavy-weight pipe keep whole joints: when a listed segment is longer than
    ``L_fit`` where it can be, the component is re-cut at its joints from the
    bit up, each segment taking as many whole joints as fit the hole it can
    meet (at most the listed length, never fewer than one: a single joint
    longer than ``L_fit`` stays whole, its tool joints are its supports,
    docs/bending.md). Every component keeps
    :attr:`ComponentConfig.segment_lengths_m` when ``fit_fraction`` or ``hole``
    is None.
    """
    base = comp.segment_lengths_m
    if fit_fraction is None or hole is None:
        return base
    if comp.type not in JOINTED_TYPES:
        kappa, radius = hole.over(s0_m, s0_m + comp.length_m, is_top)
        if kappa == 0.0:
            return base
        l_fit = hole_fit_length_m(_clearance(comp, radius), kappa, fit_fraction)
        n = max(comp.n_segments, math.ceil(comp.length_m / l_fit - 1e-9))
        return base if n == comp.n_segments else [comp.length_m / n] * n
    z = s0_m
    ok = True
    for length in base:
        ok = ok and _fits(length, comp, fit_fraction, hole, z, z + length)
        z += length
    if ok:
        return base
    jl = comp.joint_length_m
    k_cap = comp.joints_per_segment or max(1, int(max(base) / jl + 1e-9))
    n_full = comp.n_joints
    out: list[float] = []
    i = 0
    while i < n_full:
        k = min(k_cap, n_full - i)
        lo = s0_m + i * jl
        while k > 1 and not _fits(k * jl, comp, fit_fraction, hole, lo, lo + k * jl):
            k -= 1
        out.append(k * jl)
        i += k
    rest = comp.length_m - n_full * jl
    if rest > 1e-9 * comp.length_m:
        if out and rest < 0.5 * jl:
            out[-1] += rest  # a short pup joint rides with the last whole joints
        else:
            out.append(rest)
    return out


def build_segments(string_cfg: StringConfig, mud_density_kg_per_m3: float,
                   hole: HoleFit | None = None) -> Segments:
    """Cut the string into rigid segments.

    Parameters
    ----------
    string_cfg : StringConfig
        Components from the bit up.
    mud_density_kg_per_m3 : float
        Mud density, for the buoyed weight.
    hole : HoleFit, optional
        The hole the string can meet during the run: applies the hole-fit rule
        with ``string.segment_fit_fraction`` (module docstring). Without it
        each component keeps its listed segments (per-length properties, all a
        soft-string caller needs, are the same).

    Returns
    -------
    Segments
        Per-segment and per-joint arrays, index 0 at the bit end.
    """
    cols: dict[str, list[float]] = {k: [] for k in (
        "length_m", "od_m", "id_m", "mass_kg", "volume_m3", "contact_radius_m", "ia", "it",
        "ea", "ei", "gj", "kga", "mpl", "comp", "code", "conn_od", "conn_id")}
    types: list[str] = []
    kappa = string_cfg.shear_coefficient
    s0 = 0.0
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
        lengths = fitted_segment_lengths_m(comp, string_cfg.segment_fit_fraction, hole, s0,
                                           ci == len(string_cfg.components) - 1)
        s0 += comp.length_m
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
    buoyed = (mass - mud_density_kg_per_m3 * arr["volume_m3"]) * STANDARD_GRAVITY_M_PER_S2
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
