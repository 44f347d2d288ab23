"""``string`` section of params.yaml: the drill string, listed from the bit up.

Defaults (docs/model.md#bodies; typical API values, the paper's Table 2 is not available):
5 in 19.5 lb/ft drill pipe (OD 127.0 mm, ID 108.6 mm, tool joint OD 168.3 mm,
ID 82.6 mm), 6 3/4 in drill collars (OD 171.45 mm, ID 71.4 mm) for an 8 1/2 in
(215.9 mm) hole; steel E = 207 GPa, nu = 0.3, rho = 7850 kg/m^3.
The default string is 180 m of collars in 20 segments and 800 m of drill pipe in
100 segments (the paper's 100 DP + 20 DC segment case); the bit is the lower end
of the first collar segment. A separate short ``bit`` component (e.g. 0.3 m)
is allowed but, being a light stiff body, it cuts the stable step about 3x.

BHA components (docs/bending.md): a string is listed from the bit up with
bit, stabilizers (``blade_od_m``, ``blade_length_m``: near gauge), collars,
MWD/LWD subs (``mwd``), jars, heavy-weight pipe (tool joints and a centre
upset, ``center_upset_od_m``) and drill pipe. Drill pipe and heavy-weight
pipe with ``joints_per_segment`` are cut at their real joints
(``joint_length_m``, default 9.144 m = 30 ft, API range 2): each segment holds
that many whole joints, a shorter pup joint closes the component when its
length is not a whole number of joints. Without the new fields a component is
cut into ``n_segments`` equal segments exactly as before. ``preset`` names a
documented string (:data:`PRESETS`): ``bare_collars`` (the default: collars
and drill pipe, no stabilizers) or ``paper_bha`` (collars with a near-bit and
a string stabilizer, drill pipe cut at its joints).
"""

from __future__ import annotations

from typing import Any, Literal, get_args

from pydantic import Field, field_serializer, model_validator

from drillfatigue.config.base import StrictModel

ComponentType = Literal["bit", "collar", "stabilizer", "hwdp", "drill_pipe", "sub", "jar", "mwd"]
#: Component type names, in the order of ``ComponentType``: ``Segments.component_type_code``
#: indexes this tuple, so a new type goes at the end.
COMPONENT_TYPES: tuple[str, ...] = get_args(ComponentType)
#: Component types that may be cut at their joints (``joints_per_segment``).
JOINTED_TYPES: tuple[str, ...] = ("drill_pipe", "hwdp")
#: API range-2 joint length, 30 ft, m.
RANGE2_JOINT_LENGTH_M = 9.144

#: Default hole diameter used for the default contact radii: 8 1/2 in.
DEFAULT_HOLE_DIAMETER_M = 0.2159


class MaterialConfig(StrictModel):
    """Linear-elastic material of one component (SI)."""

    grade: str = Field("S-135", description="grade name, for the fatigue tables")
    youngs_modulus_Pa: float = Field(207e9, gt=1e9, le=1e12)
    poisson_ratio: float = Field(0.3, gt=0.0, lt=0.5)
    density_kg_per_m3: float = Field(7850.0, gt=500.0, le=25000.0)

    @property
    def shear_modulus_Pa(self) -> float:
        """G = E / (2 (1 + nu))."""
        return self.youngs_modulus_Pa / (2.0 * (1.0 + self.poisson_ratio))


class ComponentConfig(StrictModel):
    """One string component (a run of identical joints of pipe, a collar string, a bit).

    ``linear_mass_kg_per_m`` defaults to steel density x body area (plus the tool
    joints when given). ``contact_radius_m`` defaults to half the larger of the
    body OD and the tool-joint OD. ``n_segments`` rigid segments of equal length
    represent the component.
    """

    type: ComponentType
    name: str = ""
    od_m: float = Field(gt=0.0, le=1.0)
    id_m: float = Field(0.0, ge=0.0, le=1.0)
    length_m: float = Field(gt=0.0, le=20000.0)
    linear_mass_kg_per_m: float | None = Field(None, gt=0.0, le=5000.0)
    tool_joint_od_m: float | None = Field(None, gt=0.0, le=1.0)
    tool_joint_id_m: float | None = Field(None, ge=0.0, le=1.0)
    tool_joint_length_fraction: float = Field(0.0, ge=0.0, lt=0.5)
    contact_radius_m: float | None = Field(None, gt=0.0, le=1.0)
    n_segments: int = Field(1, ge=1, le=10000)
    material: MaterialConfig = Field(default_factory=MaterialConfig)
    joint_length_m: float = Field(RANGE2_JOINT_LENGTH_M, gt=1.0, le=15.0,
                                  description="length of one joint (range length), m")
    joints_per_segment: int | None = Field(None, ge=1, le=10, description="cut drill pipe or "
                                           "heavy-weight pipe at its joints, this many whole "
                                           "joints per segment (n_segments is then derived)")
    blade_od_m: float | None = Field(None, gt=0.0, le=1.0, description="stabilizer blade OD")
    blade_length_m: float | None = Field(None, gt=0.0, le=5.0,
                                         description="stabilizer blade length, centred")
    center_upset_od_m: float | None = Field(None, gt=0.0, le=1.0,
                                            description="heavy-weight pipe centre upset OD")

    @model_validator(mode="after")
    def _check_sections(self) -> ComponentConfig:
        if self.id_m >= self.od_m:
            raise ValueError(f"id_m must be < od_m, got id_m={self.id_m} od_m={self.od_m} "
                             "(allowed: 0 <= id_m < od_m)")
        tj_od = self.conn_od_m
        tj_id = self.conn_id_m
        if tj_id >= tj_od:
            raise ValueError(f"tool_joint_id_m must be < tool_joint_od_m, got {tj_id} >= {tj_od} "
                             "(allowed: 0 <= tool_joint_id_m < tool_joint_od_m)")
        if self.contact_radius_m is not None and self.contact_radius_m < 0.5 * self.od_m - 1e-12:
            raise ValueError(f"contact_radius_m must be >= od_m/2, got {self.contact_radius_m} "
                             f"(allowed: >= {0.5 * self.od_m})")
        if self.joints_per_segment is not None and self.type not in JOINTED_TYPES:
            raise ValueError(f"joints_per_segment is for {', '.join(JOINTED_TYPES)}, not "
                             f"{self.type} (allowed: null)")
        if (self.blade_od_m is not None or self.blade_length_m is not None) \
                and self.type != "stabilizer":
            raise ValueError(f"blade_od_m and blade_length_m are for stabilizers, not {self.type} "
                             "(allowed: null)")
        if self.blade_od_m is not None and self.blade_od_m < self.od_m:
            raise ValueError(f"blade_od_m must be >= od_m, got {self.blade_od_m} "
                             f"(allowed: >= {self.od_m})")
        if self.blade_length_m is not None and self.blade_length_m > self.length_m:
            raise ValueError(f"blade_length_m must be <= length_m, got {self.blade_length_m} "
                             f"(allowed: <= {self.length_m})")
        if self.center_upset_od_m is not None and (self.type != "hwdp"
                                                   or self.center_upset_od_m < self.od_m):
            raise ValueError("center_upset_od_m is for hwdp and must be >= od_m "
                             f"(allowed: hwdp, >= {self.od_m})")
        return self

    @property
    def n_joints(self) -> int:
        """Whole joints of a jointed component (a pup joint on top not counted)."""
        return int(self.length_m / self.joint_length_m + 1e-9)

    @property
    def segment_lengths_m(self) -> list[float]:
        """Lengths of this component's segments from its lower end, m.

        ``n_segments`` equal segments; with ``joints_per_segment``, groups of
        that many whole joints and a last, shorter segment holding the rest
        (and the pup joint, if any).
        """
        if self.joints_per_segment is None:
            return [self.length_m / self.n_segments] * self.n_segments
        k, jl = self.joints_per_segment, self.joint_length_m
        n_full = self.n_joints
        out = [k * jl] * (n_full // k)
        rest = self.length_m - len(out) * k * jl
        if rest > 1e-9 * self.length_m:
            if out and rest < 0.5 * jl:
                out[-1] += rest  # a short pup joint rides with the last whole joints
            else:
                out.append(rest)
        return out

    @property
    def conn_od_m(self) -> float:
        """Connection (tool joint) OD; the body OD when there is no tool joint."""
        return self.tool_joint_od_m if self.tool_joint_od_m is not None else self.od_m

    @property
    def conn_id_m(self) -> float:
        """Connection (tool joint) ID; the body ID when not given."""
        return self.tool_joint_id_m if self.tool_joint_id_m is not None else self.id_m

    @property
    def outer_contact_radius_m(self) -> float:
        """Contact radius actually used (m): the largest radius of the component."""
        if self.contact_radius_m is not None:
            return self.contact_radius_m
        return 0.5 * max(self.od_m, self.conn_od_m, self.blade_od_m or 0.0,
                         self.center_upset_od_m or 0.0)


def _default_components() -> list[ComponentConfig]:
    return [
        ComponentConfig(type="collar", name="6.75in DC", od_m=0.17145, id_m=0.0714,
                        length_m=180.0, n_segments=20),
        ComponentConfig(type="drill_pipe", name="5in 19.5ppf DP", od_m=0.127, id_m=0.1086,
                        length_m=800.0, tool_joint_od_m=0.1683, tool_joint_id_m=0.0826,
                        tool_joint_length_fraction=0.05, n_segments=100),
    ]


def _paper_bha_components() -> list[ComponentConfig]:
    """Collars with a near-bit and a string stabilizer, drill pipe cut at its joints.

    The founding paper lists collars below drill pipe with 20 collar and 100
    pipe segments; its BHA details are not available, so this is a typical
    packed-pendulum-free rotary BHA for an 8 1/2 in hole (typical values, not
    the paper's): near-bit stabilizer 1.5 m with 8 7/16 in (214.3 mm, 1/16 in
    under gauge) blades 0.45 m long; one 9.0 m collar; string stabilizer as
    the near-bit one; 168 m of 6 3/4 in collars in 18 segments (180 m of BHA
    as in the bare string); 800 m of 5 in drill pipe in range-2 joints, one
    joint per segment (87 joints and a 4.5 m pup joint riding on the top
    segment).
    """
    dc = dict(od_m=0.17145, id_m=0.0714)
    stab = dict(type="stabilizer", length_m=1.5, blade_od_m=0.2143, blade_length_m=0.45, **dc)
    return [
        ComponentConfig(name="near-bit stabilizer", **stab),
        ComponentConfig(type="collar", name="6.75in DC (short)", length_m=9.0, **dc),
        ComponentConfig(name="string stabilizer", **stab),
        ComponentConfig(type="collar", name="6.75in DC", length_m=168.0, n_segments=18, **dc),
        ComponentConfig(type="drill_pipe", name="5in 19.5ppf DP", od_m=0.127, id_m=0.1086,
                        length_m=800.0, tool_joint_od_m=0.1683, tool_joint_id_m=0.0826,
                        tool_joint_length_fraction=0.05, joints_per_segment=1),
    ]


#: Named strings: ``bare_collars`` (collars and drill pipe, the default) and
#: ``paper_bha`` (:func:`_paper_bha_components`).
PRESETS = {"bare_collars": _default_components, "paper_bha": _paper_bha_components}

# Typical 8 1/2 in hole BHA items (API RP 7G tables and makers' catalogues; typical
# values, not one maker's): 6 3/4 in collars (OD 171.45 mm, ID 71.4 mm), a 6 3/4 in MWD
# collar (ID 82.6 mm, 3 1/4 in: the tool's flow bore),
# integral-blade stabilizers 1.8 m long with 8 7/16 in blades (1/16 in under gauge)
# 0.45 m long, a 6 1/2 in drilling jar (OD 165.1 mm, ID 69.9 mm, 9.4 m), 5 in
# heavy-weight drill pipe (ID 76.2 mm, 6 5/8 in tool joints, 5 1/2 in centre upset,
# range-2 joints cut one per segment).
_DC = {"od_m": 0.17145, "id_m": 0.0714}
_STAB = {"type": "stabilizer", "length_m": 1.8, "blade_od_m": 0.2143, "blade_length_m": 0.45,
         **_DC}
_JAR = {"type": "jar", "name": "6.5in drilling jar", "od_m": 0.1651, "id_m": 0.0699,
        "length_m": 9.4}
_MWD = {"type": "mwd", "name": "6.75in MWD", "od_m": 0.17145, "id_m": 0.08255, "length_m": 9.0}


def _hwdp(n_joints: int) -> dict[str, Any]:
    return {"type": "hwdp", "name": "5in HWDP", "od_m": 0.127, "id_m": 0.0762,
            "length_m": n_joints * RANGE2_JOINT_LENGTH_M, "tool_joint_od_m": 0.1683,
            "tool_joint_id_m": 0.0762, "tool_joint_length_fraction": 0.1,
            "center_upset_od_m": 0.1397, "joints_per_segment": 1}


def _collars(name: str, length_m: float, n_segments: int) -> dict[str, Any]:
    return {"type": "collar", "name": name, "length_m": length_m, "n_segments": n_segments,
            **_DC}


#: Bottom-hole assemblies from the bit up (the bit itself not listed), for
#: ``string.bha``: ``slick`` (60 m of collars), ``pendulum`` (a string stabilizer
#: 18 m up, heavy-weight pipe above the collars), ``packed`` (near-bit and two string
#: stabilizers, a jar in the collars, heavy-weight pipe) and ``mwd_jar_hwdp`` (near-bit
#: stabilizer, MWD collar, string stabilizer, collars, jar, 10 joints of heavy-weight
#: pipe). docs/bending.md and docs/surrogate.md list them.
BHAS: dict[str, tuple[dict[str, Any], ...]] = {
    "slick": (_collars("6.75in DC", 60.0, 6),),
    "pendulum": (_collars("6.75in DC", 18.0, 2), {**_STAB, "name": "string stabilizer"},
                 _collars("6.75in DC", 42.0, 4), _hwdp(5)),
    "packed": ({**_STAB, "name": "near-bit stabilizer"}, _collars("6.75in short DC", 9.0, 1),
               {**_STAB, "name": "string stabilizer"}, _collars("6.75in DC", 9.0, 1),
               {**_STAB, "name": "string stabilizer"}, _collars("6.75in DC", 36.0, 4), _JAR,
               _collars("6.75in DC", 18.0, 2), _hwdp(5)),
    "mwd_jar_hwdp": ({**_STAB, "name": "near-bit stabilizer"}, _MWD,
                     {**_STAB, "name": "string stabilizer"}, _collars("6.75in DC", 27.0, 3),
                     _JAR, _collars("6.75in DC", 9.0, 1), _hwdp(10)),
}


class StringConfig(StrictModel):
    """Settings of the ``string`` section: components from the bit up.

    ``shear_coefficient`` is Timoshenko's kappa for the shear springs
    k = kappa G A / L (about 0.5 for thin tubes, docs/model.md#joints).
    ``lateral_mud_mass``: the segments' lateral inertia (translation across
    the axis and tilt) carries the mud inside the pipe and the confined added
    mass of the annular mud (:mod:`drillfatigue.string.added_mass`), axial and
    torsional inertia stay the steel's; default on. ``added_mass_coefficient``: C_a instead of the confined
    potential-flow value (R^2 + r^2)/(R^2 - r^2).
    ``segment_fit_fraction``: the share f_seg of the radial clearance c by
    which a rigid segment may depart from the hole's arc, L^2 kappa_max / 8
    <= f_seg c (:func:`drillfatigue.string.segments.hole_fit_length_m`); the
    simulator splits collars, stabilizers, subs, jars, MWD and the bit into
    more equal segments where the well's curvature needs it, and re-cuts drill
    pipe and heavy-weight pipe whose segments are too long at whole joints (as
    many per segment as fit, at least one: their tool joints are the
    supports). Default 0.5 (docs/bending.md); null keeps the listed segments.
    """

    preset: Literal["bare_collars", "paper_bha"] | None = Field(
        None, description="a named string (PRESETS) used when components are not given")
    bha: Literal["slick", "pendulum", "packed", "mwd_jar_hwdp"] | None = Field(
        None, description="a named bottom-hole assembly (BHAS) below the listed components: "
        "the string is the BHA from the bit up, then components")
    components: list[ComponentConfig] = Field(default_factory=_default_components, min_length=1)
    shear_coefficient: float = Field(0.5, gt=0.0, le=1.0)
    lateral_mud_mass: bool = True
    added_mass_coefficient: float | None = Field(None, ge=0.0, le=50.0)
    segment_fit_fraction: float | None = Field(
        0.5, gt=0.0, le=2.0, description="hole-fit rule of the segmentation: a rigid segment "
        "is at most sqrt(8 f c / kappa_max) long (c its radial clearance, kappa_max the largest "
        "curvature where it can be); drill pipe and HWDP are cut only at whole joints; null: "
        "segments as listed")

    @model_validator(mode="before")
    @classmethod
    def _fill_preset(cls, data: Any) -> Any:
        if isinstance(data, dict) and data.get("preset") is not None:
            if data.get("components") is not None:
                raise ValueError("give either preset or components, not both "
                                 "(allowed: one of them)")
            name = data["preset"]
            if name not in PRESETS:
                raise ValueError(f"unknown preset {name!r} (allowed: {', '.join(PRESETS)})")
            data = {**data, "components": PRESETS[name]()}
        return data

    @model_validator(mode="before")
    @classmethod
    def _prepend_bha(cls, data: Any) -> Any:
        if isinstance(data, dict) and data.get("bha") is not None:
            name = data["bha"]
            if name not in BHAS:
                raise ValueError(f"unknown bha {name!r} (allowed: {', '.join(BHAS)})")
            above = data.get("components")
            if above is None:
                raise ValueError("bha: the components above the BHA are missing "
                                 "(allowed: bha with a components list, e.g. the drill pipe)")
            data = {**data, "components": [dict(c) for c in BHAS[name]] + list(above)}
        return data

    @field_serializer("components")
    def _components_above_bha(self, components: list[ComponentConfig]) -> list[ComponentConfig]:
        """Written out as given: a named BHA's components are not repeated (re-reading the
        dump gives the same string)."""
        return components[len(BHAS[self.bha]):] if self.bha is not None else components

    @property
    def bha_length_m(self) -> float:
        """Length of the named BHA (m); 0 without one."""
        return float(sum(c["length_m"] for c in BHAS[self.bha])) if self.bha else 0.0

    @property
    def total_length_m(self) -> float:
        """Sum of the component lengths (m)."""
        return float(sum(c.length_m for c in self.components))
