"""``string`` section of params.yaml: the drill string, listed from the bit up.

Defaults (docs/model.md#bodies; typical API values, the paper's Table 2 is not available):
5 in 19.5 lb/ft drill pipe (OD 127.0 mm, ID 108.6 mm, tool joint OD 168.3 mm,
ID 82.6 mm), 6 3/4 in drill collars (OD 171.45 mm, ID 71.4 mm) for an 8 1/2 in
(215.9 mm) hole; steel E = 207 GPa, nu = 0.3, rho = 7850 kg/m^3.
The default string is 180 m of collars in 20 segments and 800 m of drill pipe in
100 segments (the paper's 100 DP + 20 DC segment case); the bit is the lower end
of the first collar segment. A separate short ``bit`` component (e.g. 0.3 m)
is allowed but, being a light stiff body, it cuts the stable step about 3x.
"""

from __future__ import annotations

from typing import Literal

from pydantic import Field, model_validator

from drillfatigue.config.base import StrictModel

ComponentType = Literal["bit", "collar", "stabilizer", "hwdp", "drill_pipe", "sub"]

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
        return self

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
        """Contact radius actually used (m)."""
        if self.contact_radius_m is not None:
            return self.contact_radius_m
        return 0.5 * max(self.od_m, self.conn_od_m)


def _default_components() -> list[ComponentConfig]:
    return [
        ComponentConfig(type="collar", name="6.75in DC", od_m=0.17145, id_m=0.0714,
                        length_m=180.0, n_segments=20),
        ComponentConfig(type="drill_pipe", name="5in 19.5ppf DP", od_m=0.127, id_m=0.1086,
                        length_m=800.0, tool_joint_od_m=0.1683, tool_joint_id_m=0.0826,
                        tool_joint_length_fraction=0.05, n_segments=100),
    ]


class StringConfig(StrictModel):
    """Settings of the ``string`` section: components from the bit up.

    ``shear_coefficient`` is Timoshenko's kappa for the shear springs
    k = kappa G A / L (about 0.5 for thin tubes, docs/model.md#joints).
    """

    components: list[ComponentConfig] = Field(default_factory=_default_components, min_length=1)
    shear_coefficient: float = Field(0.5, gt=0.0, le=1.0)

    @property
    def total_length_m(self) -> float:
        """Sum of the component lengths (m)."""
        return float(sum(c.length_m for c in self.components))
