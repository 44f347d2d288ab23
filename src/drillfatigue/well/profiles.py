"""Well profile builders: configuration -> survey stations -> :class:`Survey`.

A designed profile is a chain of *legs*: straight holds and constant-curvature
arcs (each arc a circle in the plane of its start and end tangents, which is
exactly what the minimum-curvature method assumes between stations). Stations
are placed at every leg boundary and every ``station_spacing_m`` inside legs,
with tangents interpolated by slerp, so the survey reproduces the design
exactly.

With ``well.tortuosity`` set, :func:`build_survey` returns the plan with its
micro-doglegs (:mod:`drillfatigue.well.tortuosity`): the hole every consumer
(the contact's cylinder chain, the soft-string torque and drag, the
surrogate's geometry features) sees; :func:`build_plan_survey` returns the
plan itself.

The case-2 family (founding paper, Liyanarachchi & Rideout) shares the
surface point and a horizontal end point; the dogleg of each member is
solved with :func:`scipy.optimize.brentq` so that it lands at the shared TVD,
and the horizontal length then reaches the shared displacement.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.optimize import brentq

from drillfatigue.config.well import (
    BuildHorizontalProfile,
    BuildTurnProfile,
    FamilyMemberProfile,
    FamilySpec,
    JProfile,
    SShapeProfile,
    SurveyFileProfile,
    VerticalProfile,
    WellConfig,
)
from drillfatigue.errors import InputError, SimulationError
from drillfatigue.well.survey_file import read_survey
from drillfatigue.well.survey import (
    Survey,
    dogleg_rad,
    minimum_curvature,
    tangent_vectors,
)
from drillfatigue.well.tortuosity import apply_tortuosity, tortuosity_report

__all__ = ["FAMILY_END_TOLERANCE_M", "KeyPoint", "build_plan_survey", "build_survey",
           "family_end_point", "key_points", "profile_report", "resolve_profile"]

_DEG_PER_30M_TO_RAD_PER_M = math.radians(1.0) / 30.0

#: Every family member ends within this distance of the shared end point, m.
FAMILY_END_TOLERANCE_M = 0.1


@dataclass(frozen=True)
class KeyPoint:
    """A named point of a designed profile (surface, KOP, end of build, TD)."""

    label: str
    md_m: float


@dataclass(frozen=True)
class _Leg:
    """Hold (``kappa == 0``) or arc to ``t_end`` at curvature ``kappa`` rad/m."""

    t_end: np.ndarray
    kappa: float
    length_m: float
    label: str


def _tan(inc_deg: float, azi_deg: float) -> np.ndarray:
    return tangent_vectors(np.radians(inc_deg), np.radians(azi_deg))


def _arc(t0: np.ndarray, t1: np.ndarray, kappa: float, label: str) -> _Leg:
    beta = float(dogleg_rad(t0, t1))
    return _Leg(t_end=t1, kappa=kappa, length_m=beta / kappa, label=label)


def _hold(t: np.ndarray, length_m: float, label: str) -> _Leg:
    return _Leg(t_end=t, kappa=0.0, length_m=length_m, label=label)


def _slerp(t0: np.ndarray, t1: np.ndarray, f: np.ndarray) -> np.ndarray:
    beta = float(dogleg_rad(t0, t1))
    if beta < 1e-12:
        return np.broadcast_to(t0, (f.size, 3)).copy()
    sb = math.sin(beta)
    return (np.sin((1.0 - f) * beta)[:, None] * t0 + np.sin(f * beta)[:, None] * t1) / sb


def _stations(legs: list[_Leg], spacing_m: float) -> tuple[np.ndarray, np.ndarray,
                                                           list[KeyPoint]]:
    """MD and unit tangents of stations along a chain of legs from the surface."""
    t = np.array([0.0, 0.0, 1.0])
    mds = [np.array([0.0])]
    tans = [t[None, :]]
    keys = [KeyPoint("surface", 0.0)]
    md = 0.0
    for leg in legs:
        if leg.length_m <= 0.0:
            continue
        n = max(1, math.ceil(leg.length_m / spacing_m - 1e-9))
        f = np.arange(1, n + 1) / n
        mds.append(md + f * leg.length_m)
        tans.append(_slerp(t, leg.t_end, f) if leg.kappa > 0.0
                    else np.broadcast_to(leg.t_end, (n, 3)).copy())
        md += leg.length_m
        t = leg.t_end
        keys.append(KeyPoint(leg.label, md))
    return np.concatenate(mds), np.concatenate(tans), keys


def _to_survey(md: np.ndarray, tan: np.ndarray, azi_default_rad: float) -> Survey:
    inc = np.arccos(np.clip(tan[:, 2], -1.0, 1.0))
    horiz = np.hypot(tan[:, 0], tan[:, 1])
    azi = np.where(horiz > 1e-12, np.arctan2(tan[:, 1], tan[:, 0]), azi_default_rad)
    azi = np.mod(azi, 2.0 * math.pi)
    azi = np.where(azi >= 2.0 * math.pi, 0.0, azi)
    return minimum_curvature(md, inc, azi)


def _family_legs(spec: FamilyMemberProfile, fam: FamilySpec, field: str,
                 spacing_m: float) -> list[_Leg]:
    """Legs of a family member, dogleg solved to land at the shared end point."""
    down = np.array([0.0, 0.0, 1.0])
    t_h = _tan(90.0, fam.azi_deg)
    t_tan = _tan(spec.tangent_inc_deg, fam.azi_deg)

    def legs_for(radius_m: float, horizontal_m: float) -> list[_Leg]:
        k = 1.0 / radius_m
        if spec.member in (1, 2):
            return [_hold(down, spec.kop_m, "KOP"), _arc(down, t_h, k, "end of build"),
                    _hold(t_h, horizontal_m, "TD")]
        return [_hold(down, spec.kop_m, "KOP"), _arc(down, t_tan, k, "end of build 1"),
                _hold(t_tan, spec.tangent_length_m, "end of tangent"),
                _arc(t_tan, t_h, k, "end of build 2"), _hold(t_h, horizontal_m, "TD")]

    def land(radius_m: float) -> np.ndarray:
        md, tan, _ = _stations(legs_for(radius_m, 0.0), spacing_m)
        return _to_survey(md, tan, math.radians(fam.azi_deg)).pos_m[-1]

    def miss(radius_m: float) -> float:
        return float(land(radius_m)[2]) - fam.tvd_end_m

    r_lo, r_hi = 1.0, 1.0e5
    if miss(r_lo) > 0.0 or miss(r_hi) < 0.0:
        raise InputError(f"{field}.kop_m",
                         f"no build radius in [{r_lo:g}, {r_hi:g}] m lands at "
                         f"family.tvd_end_m={fam.tvd_end_m} from kop_m={spec.kop_m}",
                         "kop_m (+ tangent TVD) well above family.tvd_end_m")
    # TVD at landing is linear in R, so brentq converges in a few steps.
    radius = brentq(miss, r_lo, r_hi, xtol=1e-9, rtol=1e-14)
    disp_land = float(np.dot(land(radius)[:2], t_h[:2]))
    horizontal = fam.displacement_m - disp_land
    if horizontal < 0.0:
        raise InputError(f"{field}", f"lands {disp_land:.1f} m out, beyond "
                         f"family.displacement_m={fam.displacement_m}",
                         "a displacement larger than the landing point's")
    return legs_for(radius, horizontal)


def _design(spec: object, cfg: WellConfig, field: str) -> tuple[Survey, list[KeyPoint]]:
    down = np.array([0.0, 0.0, 1.0])
    if isinstance(spec, SurveyFileProfile):
        sv = read_survey(spec.path, spec.depth_unit)
        keys = [KeyPoint("surface", float(sv.md_m[0])), KeyPoint("TD", float(sv.md_m[-1]))]
        return sv, keys
    azi_deg = 0.0
    if isinstance(spec, VerticalProfile):
        legs = [_hold(down, spec.td_m, "TD")]
    elif isinstance(spec, JProfile):
        azi_deg = spec.azi_deg
        k = spec.dls_deg_per_30m * _DEG_PER_30M_TO_RAD_PER_M
        t1 = _tan(spec.inc_deg, spec.azi_deg)
        arc = _arc(down, t1, k, "end of build")
        rest = spec.td_m - spec.kop_m - arc.length_m
        if rest < 0.0:
            raise InputError(f"{field}.td_m", f"{spec.td_m} m ends before the build does "
                             f"({spec.kop_m + arc.length_m:.1f} m)",
                             "td_m >= kop_m + build length")
        legs = [_hold(down, spec.kop_m, "KOP"), arc, _hold(t1, rest, "TD")]
    elif isinstance(spec, BuildHorizontalProfile):
        azi_deg = spec.azi_deg
        k = spec.dls_deg_per_30m * _DEG_PER_30M_TO_RAD_PER_M
        t1 = _tan(90.0, spec.azi_deg)
        legs = [_hold(down, spec.kop_m, "KOP"), _arc(down, t1, k, "end of build"),
                _hold(t1, spec.horizontal_length_m, "TD")]
    elif isinstance(spec, SShapeProfile):
        azi_deg = spec.azi_deg
        kb = spec.dls_deg_per_30m * _DEG_PER_30M_TO_RAD_PER_M
        kd = spec.drop_dls_deg_per_30m * _DEG_PER_30M_TO_RAD_PER_M
        t1 = _tan(spec.inc_deg, spec.azi_deg)
        t2 = _tan(spec.final_inc_deg, spec.azi_deg)
        legs = [_hold(down, spec.kop_m, "KOP"), _arc(down, t1, kb, "end of build"),
                _hold(t1, spec.hold_length_m, "start of drop"),
                _arc(t1, t2, kd, "end of drop"), _hold(t2, spec.final_hold_length_m, "TD")]
    elif isinstance(spec, BuildTurnProfile):
        azi_deg = spec.azi_start_deg
        k = spec.dls_deg_per_30m * _DEG_PER_30M_TO_RAD_PER_M
        t1 = _tan(spec.inc1_deg, spec.azi_start_deg)
        t2 = _tan(spec.inc_deg, spec.azi_end_deg)
        legs = [_hold(down, spec.kop_m, "KOP"), _arc(down, t1, k, "end of build"),
                _arc(t1, t2, k, "end of turn"), _hold(t2, spec.hold_length_m, "TD")]
    elif isinstance(spec, FamilyMemberProfile):
        azi_deg = cfg.family.azi_deg
        legs = _family_legs(spec, cfg.family, field, cfg.station_spacing_m)
    else:  # pragma: no cover - the config union is closed
        raise InputError(field, f"unknown profile kind {type(spec).__name__}")
    if sum(leg.length_m for leg in legs) <= 0.0:
        raise InputError(field, "profile has zero length", "a total MD > 0")
    md, tan, keys = _stations(legs, cfg.station_spacing_m)
    sv = _to_survey(md, tan, math.radians(azi_deg))
    if isinstance(spec, FamilyMemberProfile):
        miss = float(np.linalg.norm(sv.pos_m[-1] - family_end_point(cfg.family)))
        if miss >= FAMILY_END_TOLERANCE_M:  # pragma: no cover - guaranteed by the solve
            raise SimulationError(f"{field}: family end point missed by {miss:.3g} m")
    return sv, keys


def family_end_point(fam: FamilySpec) -> np.ndarray:
    """Shared end point [north, east, tvd] of the case-2 family, m, shape (3,)."""
    az = math.radians(fam.azi_deg)
    return np.array([fam.displacement_m * math.cos(az), fam.displacement_m * math.sin(az),
                     fam.tvd_end_m])


def resolve_profile(cfg: WellConfig, name: str | None = None) -> str:
    """Profile name to use: ``name`` (must be defined) or ``cfg.active_profile``."""
    if name is None:
        return cfg.active_profile
    if name not in cfg.profiles:
        raise InputError("profile", f"{name!r} is not defined in well.profiles",
                         ", ".join(cfg.profiles))
    return name


def build_plan_survey(cfg: WellConfig, name: str | None = None) -> Survey:
    """Survey of a named profile's plan, without ``cfg.tortuosity``.

    Parameters
    ----------
    cfg : WellConfig
        The ``well`` section.
    name : str, optional
        Profile name in ``cfg.profiles`` (default: ``cfg.profile`` or the first).

    Returns
    -------
    Survey
        Stations from the surface (0, 0, 0) to TD, positions by minimum
        curvature.
    """
    name = resolve_profile(cfg, name)
    return _design(cfg.profiles[name], cfg, f"well.profiles.{name}")[0]


def build_survey(cfg: WellConfig, name: str | None = None) -> Survey:
    """Survey of the hole of a named profile (default: ``cfg.profile`` or the first).

    The plan (:func:`build_plan_survey`) with the micro-doglegs of
    ``cfg.tortuosity`` added when it is set
    (:func:`drillfatigue.well.tortuosity.apply_tortuosity`); the plan itself
    when it is not.

    Parameters
    ----------
    cfg : WellConfig
        The ``well`` section.
    name : str, optional
        Profile name in ``cfg.profiles``.

    Returns
    -------
    Survey
        Stations from the surface (0, 0, 0) to TD, positions by minimum
        curvature.
    """
    plan = build_plan_survey(cfg, name)
    return plan if cfg.tortuosity is None else apply_tortuosity(plan, cfg.tortuosity)


def key_points(cfg: WellConfig, name: str | None = None) -> list[KeyPoint]:
    """Named points of a profile: surface, KOP, ends of builds/drops/turns, TD."""
    name = resolve_profile(cfg, name)
    return _design(cfg.profiles[name], cfg, f"well.profiles.{name}")[1]


def profile_report(cfg: WellConfig) -> dict[str, dict[str, object]]:
    """Per profile: kind, TD, end point and maximum DLS (deg/30 m, deg/100 ft).

    For the case-2 family this is the report of the shared end point (every
    ``family_member``'s ``end_pos_m`` equals the family end to < 0.1 m) and of
    each member's maximum dogleg. With ``cfg.tortuosity`` set, the numbers are
    those of the tortuous hole and ``tortuosity`` holds
    :func:`drillfatigue.well.tortuosity.tortuosity_report` (the plan beside it).
    """
    out: dict[str, dict[str, object]] = {}
    for name, spec in cfg.profiles.items():
        plan = build_plan_survey(cfg, name)
        sv = plan if cfg.tortuosity is None else apply_tortuosity(plan, cfg.tortuosity)
        out[name] = {
            "kind": spec.kind,
            "td_m": float(sv.md_m[-1]),
            "end_pos_m": [float(v) for v in sv.pos_m[-1]],
            "max_dls_deg_per_30m": sv.max_dls_deg_per_30m,
            "max_dls_deg_per_100ft": float(sv.dls_deg_per_100ft.max()),
            "n_stations": sv.n,
        }
        if cfg.tortuosity is not None:
            out[name]["tortuosity"] = tortuosity_report(plan, sv, cfg.tortuosity)
    return out
