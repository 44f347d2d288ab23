"""``well`` section of params.yaml: named well profiles, hole sizes, resampling.

A case uses one profile (``well.profile``, default: the first defined). Profile
specifications are a union discriminated on ``kind``:

``vertical``
    Straight down to ``td_m``.
``j``
    Vertical to ``kop_m``, build at ``dls_deg_per_30m`` to ``inc_deg``, hold to
    ``td_m``.
``build_horizontal``
    Vertical to ``kop_m``, build at ``dls_deg_per_30m`` to 90 deg, then
    ``horizontal_length_m`` of horizontal hole.
``s_shape``
    Vertical, build to ``inc_deg``, hold ``hold_length_m``, drop at
    ``drop_dls_deg_per_30m`` to ``final_inc_deg``, hold ``final_hold_length_m``.
``build_turn``
    True 3D: vertical, build to ``inc1_deg`` at ``azi_start_deg``, then one
    constant-curvature build-and-turn arc to (``inc_deg``, ``azi_end_deg``),
    then hold ``hold_length_m``.
``family_member``
    One of the three profiles of the founding paper's case 2, which share the
    surface point and the end point given in ``well.family``: member 1 early
    kick-off and gradual build, member 2 later kick-off and higher dogleg,
    member 3 two builds with a tangent between them. The build rate is solved
    so each member lands horizontal at the shared end point (< 0.1 m).
``survey_file``
    A survey file, path relative to the working directory: CSV in m or ft
    with common header spellings (``md_m,inc_deg,azi_deg``, ``MD (ft), Incl,
    Azim, TVD, DLS (deg/100ft)``) or WITSML 1.4.1.1 trajectory XML, read by
    :mod:`drillfatigue.well.survey_file` (``depth_unit`` for depth columns whose
    header names no unit).

Hole tortuosity (``well.tortuosity``, off when absent): micro-doglegs added to
every profile's plan below ``md_start_m``, a sine wave or seeded random tilts of
the hole's direction with a stated amplitude and period
(:mod:`drillfatigue.well.tortuosity`, docs/wells.md#tortuosity). The contact
model, the soft-string torque and drag and the surrogate's geometry features
then see the tortuous hole.

Angles are given in degrees at this boundary and converted to radians once,
in :mod:`drillfatigue.well.profiles` and :mod:`drillfatigue.well.tortuosity`.
Lengths are metres.
"""

from __future__ import annotations

import math
from typing import Annotated, Any, Literal

from pydantic import (
    Field,
    SerializerFunctionWrapHandler,
    ValidationInfo,
    field_validator,
    model_serializer,
    model_validator,
)
from pydantic_core import PydanticCustomError

from drillfatigue.config.base import StrictModel
from drillfatigue.limits import FEATURE_BOUNDS, MD_MAX_M

# Typical oilfield build rates are 1-15 deg/30 m; short-radius wells reach
# ~60 deg/30 m, the upper limit we accept.
_DLS_MAX = 60.0
_DEPTH_MAX = 15000.0


def _bad(problem: str, allowed: str) -> PydanticCustomError:
    """A validation error whose ``allowed`` part the CLI prints after the problem."""
    # Braces would be read as template fields by pydantic; they never occur in
    # our messages but are escaped for safety.
    problem = problem.replace("{", "(").replace("}", ")")
    return PydanticCustomError("value_error", problem, {"expected": allowed})


class VerticalProfile(StrictModel):
    """Vertical hole from surface to ``td_m``."""

    kind: Literal["vertical"] = "vertical"
    td_m: float = Field(1000.0, gt=0.0, le=_DEPTH_MAX, description="total measured depth, m")


class JProfile(StrictModel):
    """Vertical -> build -> hold (J-shaped) profile."""

    kind: Literal["j"] = "j"
    kop_m: float = Field(400.0, ge=0.0, le=_DEPTH_MAX, description="kick-off MD, m")
    dls_deg_per_30m: float = Field(6.0, gt=0.0, le=_DLS_MAX)
    inc_deg: float = Field(45.0, gt=0.0, le=180.0, description="hold inclination, deg")
    azi_deg: float = Field(0.0, ge=0.0, lt=360.0)
    td_m: float = Field(1000.0, gt=0.0, le=_DEPTH_MAX, description="total measured depth, m")


class BuildHorizontalProfile(StrictModel):
    """Vertical -> build to 90 deg -> horizontal."""

    kind: Literal["build_horizontal"] = "build_horizontal"
    kop_m: float = Field(350.0, ge=0.0, le=_DEPTH_MAX)
    dls_deg_per_30m: float = Field(6.0, gt=0.0, le=_DLS_MAX)
    azi_deg: float = Field(0.0, ge=0.0, lt=360.0)
    horizontal_length_m: float = Field(300.0, ge=0.0, le=_DEPTH_MAX)


class SShapeProfile(StrictModel):
    """Vertical -> build -> hold -> drop -> hold (S-shaped) profile."""

    kind: Literal["s_shape"] = "s_shape"
    kop_m: float = Field(300.0, ge=0.0, le=_DEPTH_MAX)
    dls_deg_per_30m: float = Field(5.0, gt=0.0, le=_DLS_MAX, description="build rate")
    inc_deg: float = Field(40.0, gt=0.0, le=180.0, description="tangent inclination, deg")
    hold_length_m: float = Field(200.0, ge=0.0, le=_DEPTH_MAX)
    drop_dls_deg_per_30m: float = Field(4.0, gt=0.0, le=_DLS_MAX)
    final_inc_deg: float = Field(0.0, ge=0.0, le=180.0)
    final_hold_length_m: float = Field(200.0, ge=0.0, le=_DEPTH_MAX)
    azi_deg: float = Field(0.0, ge=0.0, lt=360.0)

    @field_validator("final_inc_deg")
    @classmethod
    def _drop_below_build(cls, v: float, info: ValidationInfo) -> float:
        inc = info.data.get("inc_deg")
        if inc is not None and v >= inc:
            raise _bad(f"must be smaller than inc_deg={inc}", "0 <= final_inc_deg < inc_deg")
        return v


class BuildTurnProfile(StrictModel):
    """Vertical -> build -> build-and-turn arc -> hold (true 3D)."""

    kind: Literal["build_turn"] = "build_turn"
    kop_m: float = Field(300.0, ge=0.0, le=_DEPTH_MAX)
    dls_deg_per_30m: float = Field(5.0, gt=0.0, le=_DLS_MAX)
    inc1_deg: float = Field(30.0, gt=0.0, le=180.0, description="end of first build, deg")
    azi_start_deg: float = Field(0.0, ge=0.0, lt=360.0)
    inc_deg: float = Field(70.0, gt=0.0, le=180.0, description="end of turn arc, deg")
    azi_end_deg: float = Field(60.0, ge=0.0, lt=360.0)
    hold_length_m: float = Field(200.0, ge=0.0, le=_DEPTH_MAX)


class FamilyMemberProfile(StrictModel):
    """Member of the case-2 family sharing ``well.family``'s end point.

    Member 1: kick-off at ``kop_m``, one build to 90 deg. Member 2: the same
    with a later ``kop_m`` (hence a higher dogleg). Member 3: build to
    ``tangent_inc_deg``, hold ``tangent_length_m``, build to 90 deg, both builds
    at one solved dogleg.
    """

    kind: Literal["family_member"] = "family_member"
    member: Literal[1, 2, 3] = 1
    kop_m: float = Field(350.0, ge=0.0, le=_DEPTH_MAX)
    tangent_inc_deg: float = Field(45.0, gt=0.0, lt=90.0, description="member 3 only")
    tangent_length_m: float = Field(150.0, ge=0.0, le=_DEPTH_MAX, description="member 3 only")


class SurveyFileProfile(StrictModel):
    """Survey read from a file: CSV in m or ft, or WITSML trajectory XML."""

    kind: Literal["survey_file"] = "survey_file"
    path: str = Field(min_length=1, description="CSV or XML path, relative to the working "
                      "directory")
    depth_unit: Literal["m", "ft"] | None = Field(
        None, description="unit of depth columns whose header names none")


ProfileSpec = Annotated[
    VerticalProfile
    | JProfile
    | BuildHorizontalProfile
    | SShapeProfile
    | BuildTurnProfile
    | FamilyMemberProfile
    | SurveyFileProfile,
    Field(discriminator="kind"),
]


class FamilySpec(StrictModel):
    """Shared surface and end point of the case-2 profile family.

    Every member starts at the surface (0, 0, 0) and ends horizontal at TVD
    ``tvd_end_m`` and horizontal displacement ``displacement_m`` along
    azimuth ``azi_deg``.
    """

    tvd_end_m: float = Field(650.0, gt=0.0, le=_DEPTH_MAX)
    displacement_m: float = Field(500.0, gt=0.0, le=_DEPTH_MAX)
    azi_deg: float = Field(0.0, ge=0.0, lt=360.0)


class HoleSection(StrictModel):
    """Hole diameter from ``md_top_m`` down to the next section's top."""

    md_top_m: float = Field(0.0, ge=0.0, le=_DEPTH_MAX)
    # 8 1/2 in = 0.2159 m. 50 mm .. 1 m covers slim holes to surface holes.
    diameter_m: float = Field(0.2159, ge=0.05, le=1.0)


_AMPLITUDE = FEATURE_BOUNDS["tortuosity_amplitude_deg"]
_PERIOD = FEATURE_BOUNDS["tortuosity_period_m"]


class TortuosityConfig(StrictModel):
    """Micro-doglegs added to the plan: hole tortuosity (docs/wells.md#tortuosity).

    Below ``md_start_m`` the direction of the hole is tilted away from the
    plan's by an angle ``delta(md)`` in the plane of the plan's inclination
    (``direction: inclination``, the high side), across it (``azimuth``, the
    right side) or in both at once (``both``, the same wave in each, as
    torque-and-drag programs add it to inclination and azimuth alike).

    ``sine``
        ``delta = amplitude sin(2 pi (md - md_start) / period)``: peak added
        dogleg severity 2 pi amplitude / period (times sqrt 2 for ``both``),
        mean 4 amplitude / period over whole periods.
    ``random``
        ``delta`` drawn uniformly in [-amplitude, amplitude] every ``period``
        from ``md_start_m`` (0 there), linear in between; the draws come from
        ``numpy.random.default_rng(seed)``, so a seed gives the same hole on
        every run. Added dogleg severity at most 2 amplitude / period (times
        sqrt 2 for ``both``).

    ``stations_per_period`` survey stations per period carry the wave (the
    plan's stations are kept); 32 resolve the sine's peak dogleg severity to
    within 1 % by minimum curvature.
    """

    model: Literal["sine", "random"] = Field(description="shape of the micro-doglegs")
    amplitude_deg: float = Field(ge=_AMPLITUDE.lo, le=_AMPLITUDE.hi,
                                 description="largest tilt from the plan's direction, deg")
    period_m: float = Field(ge=_PERIOD.lo, le=_PERIOD.hi,
                            description="wave length (sine) or spacing of the draws "
                                        "(random), m")
    md_start_m: float = Field(0.0, ge=0.0, le=MD_MAX_M,
                              description="MD where the tortuosity starts, m")
    direction: Literal["inclination", "azimuth", "both"] = "inclination"
    seed: int = Field(0, ge=0, le=2**32 - 1, description="random model only")
    stations_per_period: int = Field(32, ge=8, le=256)

    @model_validator(mode="after")
    def _dls_within_bound(self) -> TortuosityConfig:
        top = FEATURE_BOUNDS["dls_deg_per_30m"].hi
        added = self.peak_added_dls_deg_per_30m
        if added > top:
            raise _bad(f"amplitude_deg: {self.amplitude_deg:g} deg over period_m "
                       f"{self.period_m:g} m adds a dogleg severity of {added:.4g} deg/30m",
                       f"a peak added dogleg severity <= {top:g} deg/30m")
        return self

    @property
    def peak_added_dls_deg_per_30m(self) -> float:
        """Largest dogleg severity the tortuosity adds to a straight hole, deg/30 m."""
        rate = (2.0 * math.pi if self.model == "sine" else 2.0) * self.amplitude_deg / self.period_m
        if self.direction == "both":
            rate *= math.sqrt(2.0)
        return 30.0 * rate


def _default_profiles() -> dict[str, ProfileSpec]:
    return {
        "profile_1": FamilyMemberProfile(member=1, kop_m=350.0),
        "profile_2": FamilyMemberProfile(member=2, kop_m=450.0),
        "profile_3": FamilyMemberProfile(member=3, kop_m=350.0, tangent_inc_deg=45.0,
                                         tangent_length_m=150.0),
    }


class WellConfig(StrictModel):
    """Settings of the ``well`` section. Units: SI unless the field name says otherwise.

    Defaults give the paper-like case-2 family: surface to a horizontal end at
    TVD 650 m, 500 m displacement; kick-offs at 350/450 m; total MD about
    1020-1090 m, so a string growing 480 -> 880 m drills through the build.
    """

    profiles: dict[str, ProfileSpec] = Field(default_factory=_default_profiles, min_length=1)
    profile: str | None = Field(None, description="profile a case uses; default: the first")
    family: FamilySpec = Field(default_factory=FamilySpec)
    hole: list[HoleSection] = Field(default_factory=lambda: [HoleSection()], min_length=1)
    min_clearance_m: float = Field(
        0.02, gt=0.0, le=0.5,
        description="smallest radial clearance hole - component contact radius, m")
    chord_error_fraction: float = Field(
        0.01, gt=0.0, le=0.5, description="allowed sagitta as a fraction of min_clearance_m")
    max_cylinder_length_m: float = Field(10.0, gt=0.0, le=100.0)
    station_spacing_m: float = Field(30.0, gt=0.0, le=500.0,
                                     description="survey station spacing of built profiles")
    tortuosity: TortuosityConfig | None = Field(
        None, description="micro-doglegs added to every profile's plan; None: off")

    @field_validator("profile")
    @classmethod
    def _profile_defined(cls, v: str | None, info: ValidationInfo) -> str | None:
        profiles = info.data.get("profiles")
        if v is not None and profiles is not None and v not in profiles:
            raise _bad("profile is not defined in well.profiles", ", ".join(profiles))
        return v

    @field_validator("hole")
    @classmethod
    def _hole_ordered(cls, v: list[HoleSection]) -> list[HoleSection]:
        if v[0].md_top_m != 0.0:
            raise _bad(f"hole[0].md_top_m must be 0, got {v[0].md_top_m}",
                       "first hole section starts at the surface, md_top_m = 0")
        for i in range(1, len(v)):
            if v[i].md_top_m <= v[i - 1].md_top_m:
                raise _bad(f"hole[{i}].md_top_m={v[i].md_top_m} is not deeper than "
                           f"hole[{i - 1}].md_top_m={v[i - 1].md_top_m}",
                           "strictly increasing md_top_m")
        return v

    @field_validator("min_clearance_m")
    @classmethod
    def _hole_fits_clearance(cls, v: float, info: ValidationInfo) -> float:
        for i, sec in enumerate(info.data.get("hole") or []):
            if sec.diameter_m / 2.0 <= v:
                raise _bad(f"hole[{i}].diameter_m={sec.diameter_m} m is too small for "
                           f"this clearance", "min_clearance_m < hole radius")
        return v

    @model_serializer(mode="wrap")
    def _leave_out_tortuosity_off(self, handler: SerializerFunctionWrapHandler) -> dict[str, Any]:
        """The dump without ``tortuosity`` while it is off, so that a well without it keeps
        its case id, configuration hash and written configuration."""
        data: dict[str, Any] = handler(self)
        if self.tortuosity is None:
            data.pop("tortuosity", None)
        return data

    @property
    def active_profile(self) -> str:
        """Name of the profile a case uses (``profile`` or the first defined)."""
        return self.profile if self.profile is not None else next(iter(self.profiles))
