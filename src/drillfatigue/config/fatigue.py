"""``fatigue`` section of params.yaml: criterion, S-N curves, SCFs, counting options.

Default stress concentration factors (all engineering ASSUMPTIONS, overridable
per component type and location under ``scf``; docs/fatigue.md#stresses):

* pipe body (every component type): 1.0 in tension, bending and torsion: the
  nominal body stress away from upsets (set ~2, literature range 1.5-2.5, to
  evaluate a drill-pipe upset run-out instead);
* connection (rotary-shouldered thread root): 3.5 in tension and bending
  (literature range 3-6) and 1.5 in torsion, for every type with a threaded
  connection; the thread-root section is approximated by the connection
  dimensions ``conn_od_m``/``conn_id_m`` of ``joints.parquet``;
* upset run-out (drill pipe and heavy-weight pipe only, :data:`UPSET_TYPES`):
  2.0 in tension and bending on the body section, the value docs/fatigue.md
  section 1 takes within the 1.5-2.5 range reported for the internal-upset
  taper of drill pipe (Tsukano et al., "Appropriate design of drill pipe
  upsets based on stress analysis, fatigue test and field failure data",
  IADC/SPE 17206, 1988; reviewed in Vaisberg et al., Oil & Gas Science and
  Technology 57 (2002) 7-37, where the run-out of the internal upset is the
  usual fatigue-crack site of drill pipe); 1.5 in torsion (assumption: a
  shoulder fillet concentrates shear about half as much as bending, Peterson's
  Stress Concentration Factors, 3rd ed., 2008, charts 3.8-3.12).

Mud pressure (``pressure``): when the run's ``case.yaml`` gives the well and
the mud density, each joint gets the hydrostatic pressure at its mean TVD
over the window, inside and outside, plus ``pump_pressure_Pa`` inside; the
axial load becomes the true wall force and the Lame hoop and radial stresses
enter the criteria (:mod:`drillfatigue.fatigue.stress`).

Default S-N curves: ``B1`` (DNV-RP-C203 base material) at both locations, used
with the local stress (SCF applied). ``thread_rolled`` (F1) and ``thread_cut``
(W3) are DNV's bolt curves for the NOMINAL thread stress: when choosing them for
the connection, set that location's SCFs to 1.
"""

from __future__ import annotations

import math
from typing import Any, Literal

from pydantic import Field, ValidationError, field_validator, model_validator

from drillfatigue.config.base import StrictModel
from drillfatigue.config.string import COMPONENT_TYPES, JOINTED_TYPES

#: Component types with an upset run-out location beside body and connection.
UPSET_TYPES: tuple[str, ...] = JOINTED_TYPES  # jointed pipe: a tube upset to its tool joints
_CURVE_NAMES: tuple[str, ...] = ("B1", "C", "D", "F1", "W3", "thread_rolled", "thread_cut")


class SCFConfig(StrictModel):
    """Stress concentration factors of one location (dimensionless)."""

    axial: float = Field(1.0, ge=1.0, le=10.0, description="factor on F/A")
    bending: float = Field(1.0, ge=1.0, le=10.0, description="factor on M r/I")
    torsion: float = Field(1.0, ge=1.0, le=10.0, description="factor on T r/J and 2V/A")


_CONNECTION_DEFAULT = {"axial": 3.5, "bending": 3.5, "torsion": 1.5}
_UPSET_DEFAULT = {"axial": 2.0, "bending": 2.0, "torsion": 1.5}


class ComponentSCF(StrictModel):
    """SCFs of a component type at its locations.

    A partial ``connection`` or ``upset`` mapping keeps that location's
    defaults for the keys it does not give. ``upset`` is read only for
    :data:`UPSET_TYPES`.
    """

    body: SCFConfig = Field(default_factory=SCFConfig)
    connection: SCFConfig = Field(
        default_factory=lambda: SCFConfig(**_CONNECTION_DEFAULT))
    upset: SCFConfig = Field(default_factory=lambda: SCFConfig(**_UPSET_DEFAULT))

    @model_validator(mode="before")
    @classmethod
    def _fill_connection(cls, data: Any) -> Any:
        if isinstance(data, dict):
            for loc, dflt in (("connection", _CONNECTION_DEFAULT), ("upset", _UPSET_DEFAULT)):
                if isinstance(data.get(loc), dict):
                    data = {**data, loc: {**dflt, **data[loc]}}
        return data


def _default_scf() -> dict[str, ComponentSCF]:
    return {t: ComponentSCF() for t in COMPONENT_TYPES}


class UserCurveConfig(StrictModel):
    """User-defined linear, bi-linear or tri-linear S-N curve, S range in MPa.

    log10 N = log_a1 - m1 log10 S above the knee; slope m2 below ``knee_N``;
    optional cut-off (no damage) below the stress at ``cutoff_N``.
    """

    name: str = "user"
    m1: float = Field(3.0, ge=1.0, le=20.0)
    log_a1: float = Field(12.164, gt=5.0, lt=40.0)
    m2: float | None = Field(None, ge=1.0, le=20.0)
    knee_N: float | None = Field(None, ge=1e3, le=1e12)
    cutoff_N: float | None = Field(None, ge=1e4, le=1e14)
    reference: str = "user-defined"

    @model_validator(mode="after")
    def _consistent(self) -> UserCurveConfig:
        if self.m2 is not None and self.knee_N is None:
            raise ValueError("knee_N is required with m2 (allowed: 1e3 <= knee_N <= 1e12)")
        if self.cutoff_N is not None and (self.m2 is None or self.knee_N is None
                                          or self.cutoff_N <= self.knee_N):
            raise ValueError("cutoff_N needs m2 and knee_N and must exceed knee_N "
                             "(allowed: knee_N < cutoff_N <= 1e14)")
        return self


class LocationConfig(StrictModel):
    """S-N curve of one location: a library name or a user curve."""

    curve: str | UserCurveConfig = "B1"

    @field_validator("curve", mode="before")
    @classmethod
    def _known(cls, v: Any) -> Any:
        if isinstance(v, dict):
            try:
                return UserCurveConfig.model_validate(v)
            except ValidationError as exc:
                err = exc.errors(include_url=False)[0]
                where = ".".join(str(x) for x in err["loc"])
                msg = str(err["msg"]).removeprefix("Value error, ")
                raise ValueError(f"user curve {where + ': ' if where else ''}{msg}") from None
        if isinstance(v, UserCurveConfig):
            return v
        if not isinstance(v, str) or v not in _CURVE_NAMES:
            raise ValueError(f"unknown S-N curve {v!r} (allowed: {', '.join(_CURVE_NAMES)} "
                             "or a mapping with m1, log_a1[, m2, knee_N, cutoff_N])")
        return v


class FatigueConfig(StrictModel):
    """Settings of the ``fatigue`` section. Units: SI unless the field name says otherwise."""

    criterion: Literal["matake", "findley", "fatemi_socie", "uniaxial"] = "matake"
    grade: Literal["E-75", "X-95", "G-105", "S-135"] = "S-135"
    environment: Literal["air", "seawater_cp", "free_corrosion"] = "air"
    corrosive_mud: bool = Field(False, description="use the free-corrosion curves "
                                "(corrosive mud; overrides environment)")
    body: LocationConfig = Field(default_factory=LocationConfig)
    connection: LocationConfig = Field(default_factory=LocationConfig)
    upset: LocationConfig = Field(default_factory=LocationConfig)
    upset_location: bool = Field(True, description="evaluate the upset run-out of drill pipe "
                                 "and heavy-weight pipe beside body and connection")
    pressure: bool = Field(True, description="include mud pressure (true wall force, Lame "
                           "hoop and radial stress) when the run's case.yaml gives well and mud")
    pump_pressure_Pa: float = Field(0.0, ge=0.0, le=1e8, description="pressure inside the "
                                    "string above hydrostatic (circulating), Pa")
    mean_stress: Literal["none", "goodman", "walker", "swt", "compressive"] = Field(
        "goodman", description="mean-stress correction of the uniaxial route")
    walker_gamma: float = Field(0.5, gt=0.0, le=1.0)
    compressive_alpha: float = Field(0.6, ge=0.0, le=1.0)
    residue: Literal["half", "repeat", "carry"] = "half"
    load_classes: int | None = Field(None, ge=2, le=100_000,
                                     description="bin into load classes (None: exact)")
    n_surface_points: int = Field(36, ge=36, le=720)
    scf: dict[str, ComponentSCF] = Field(default_factory=_default_scf)
    torsion_to_tension_ratio: float = Field(1.0 / math.sqrt(3.0), ge=0.5, le=1.0,
                                            description="t/f for Matake")
    findley_k: float = Field(0.25, ge=0.0, le=1.0)
    fatemi_socie_k: float = Field(0.6, ge=0.0, le=2.0)
    plane_step_deg: float = Field(10.0, ge=0.5, le=45.0)
    family_b: bool = Field(False, description="also planes at 45 deg to the surface (off by "
                           "default: with sigma_theta = 0 the in-surface principal stresses have "
                           "opposite signs, so the maximum-shear plane is perpendicular to it)")
    n_shear_axes: int = Field(2, ge=1, le=8)
    n_refine: int = Field(4, ge=0, le=8, description="halvings of plane_step_deg around the "
                          "governing plane (the first 4 at once as a dense grid of "
                          "2 (2^n - 1) planes, further ones greedily)")
    n_refine_points: int = Field(2, ge=1, le=36, description="most damaged surface points "
                                 "whose plane is refined")
    joints: list[int] | None = Field(None, description="joints to evaluate (None: all)")
    chunk_length_s: float | None = Field(None, gt=0.0, le=1e6,
                                         description="streaming chunk for residue 'carry'")
    plots: bool = True

    @field_validator("scf", mode="before")
    @classmethod
    def _merge_scf(cls, v: Any) -> Any:
        if not isinstance(v, dict):
            return v
        unknown = sorted(set(v) - set(COMPONENT_TYPES))
        if unknown:
            raise ValueError(f"unknown component type {unknown[0]!r} "
                             f"(allowed: {', '.join(COMPONENT_TYPES)})")
        merged: dict[str, Any] = {t: ComponentSCF() for t in COMPONENT_TYPES}
        merged.update(v)
        return merged

    @field_validator("joints")
    @classmethod
    def _nonneg(cls, v: list[int] | None) -> list[int] | None:
        if v is not None and (len(v) == 0 or min(v) < 0):
            raise ValueError("must be a non-empty list of joint numbers >= 0 "
                             "(allowed: null or [0, 1, ...])")
        return v

    @property
    def effective_environment(self) -> str:
        """Environment of the S-N curves (corrosive mud selects free corrosion)."""
        return "free_corrosion" if self.corrosive_mud else self.environment
