"""Directional surveys: minimum curvature, dogleg severity, survey CSV files.

Frame: x = north, y = east, z = TVD positive down (metres). Inclination is
measured from vertical-down, azimuth clockwise from north, both in radians.

Survey CSV format
-----------------
A header line then one station per row, columns (any order, extra columns
are rejected)::

    md_m,inc_deg,azi_deg
    0.0,0.0,0.0
    30.0,1.5,45.0

``md_m`` measured depth in metres, strictly increasing; ``inc_deg``
inclination in degrees, in [0, 180]; ``azi_deg`` azimuth in degrees, in
[0, 360). At least two stations. No blank or NaN cells.

References
----------
Minimum curvature: Sawaryn & Thorogood, "A compendium of directional
calculations based on the minimum curvature method", SPE Drilling &
Completion 20(1), 2005, eqs. 1-4.
"""

from __future__ import annotations

import csv
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from drillfatigue.errors import InputError
from drillfatigue.files import atomic_output
from drillfatigue.limits import MD_MAX_M
from drillfatigue.units import FT_M

__all__ = [
    "BETA_NEAR_PI_RAD",
    "SURVEY_COLUMNS",
    "Survey",
    "atomic_output",
    "dogleg_rad",
    "half_turn_normal",
    "minimum_curvature",
    "read_survey_csv",
    "tangent_vectors",
    "write_survey_csv",
]

SURVEY_COLUMNS: tuple[str, str, str] = ("md_m", "inc_deg", "azi_deg")

_RAD_PER_M_TO_DEG_PER_30M = math.degrees(1.0) * 30.0
_RAD_PER_M_TO_DEG_PER_100FT = math.degrees(1.0) * 100.0 * FT_M


def tangent_vectors(inc_rad: np.ndarray, azi_rad: np.ndarray) -> np.ndarray:
    """Unit tangents (north, east, tvd) of stations, shape (n, 3)."""
    inc = np.asarray(inc_rad, dtype=float)
    azi = np.asarray(azi_rad, dtype=float)
    s = np.sin(inc)
    return np.stack([s * np.cos(azi), s * np.sin(azi), np.cos(inc)], axis=-1)


def dogleg_rad(t1: np.ndarray, t2: np.ndarray) -> np.ndarray:
    """Angle between unit tangents, rad, shape (...,).

    Uses ``2 atan2(|t2 - t1|, |t2 + t1|)``, accurate for tiny and near-pi
    angles (the arccos form loses half the digits near zero).
    """
    d = np.linalg.norm(np.asarray(t2) - np.asarray(t1), axis=-1)
    s = np.linalg.norm(np.asarray(t2) + np.asarray(t1), axis=-1)
    return 2.0 * np.arctan2(d, s)


def ratio_factor(beta: np.ndarray) -> np.ndarray:
    """Minimum-curvature ratio factor ``RF = (2/beta) tan(beta/2)``; 1 for beta -> 0."""
    beta = np.asarray(beta, dtype=float)
    small = beta < 1e-6
    safe = np.where(small, 1.0, beta)
    # Series 1 + beta^2/12 below 1e-6 (next term ~beta^4/120, < 1e-24).
    return np.where(small, 1.0 + beta * beta / 12.0, 2.0 / safe * np.tan(safe / 2.0))


# Above this dogleg (rad) per interval tan(beta/2) and |t1 + t2| are each
# ill-conditioned (beta carries an absolute error of ~ulp(pi) = 4.4e-16, so
# tan(beta/2) a relative one of ~4.4e-16 / (pi - beta), which reaches 1e-12 at
# pi - beta ~ 4e-4) and their product, the step, is no longer the chord: the
# step is taken as the end of the arc written in the basis of t1 and its unit
# normal in the plane of the turn instead.
BETA_NEAR_PI_RAD = math.pi - 1e-3


def half_turn_normal(t1: np.ndarray, t2: np.ndarray) -> np.ndarray:
    """Unit normal to t1 in the plane of a turn by nearly pi towards t2, shape (k, 3).

    The part of the tangents' unit bisector ``(t1 + t2) / |t1 + t2|`` normal to t1,
    normalised (its length is sin(beta/2), near 1). The direction of ``t1 + t2`` is
    only as good as eps / |t1 + t2|: the plane of a nearly reversed turn is
    ill-defined by its tangents, but the normal is a unit vector normal to t1 to
    rounding, so the arc built on it is a circle. When ``t1 + t2`` is zero (or its
    square underflows) the plane is undefined and the turn is taken in the vertical
    plane of t1 (the north-tvd plane when t1 is vertical), towards increasing tvd.
    :func:`drillfatigue.well.kernels.path_point` and
    :func:`drillfatigue.well.wellbore.arc_points` follow the same construction.
    """
    b = t1 + t2
    nb = np.sqrt(np.sum(b * b, axis=-1))
    undefined = nb == 0.0
    b = b / np.where(undefined, 1.0, nb)[:, None]
    if np.any(undefined):
        tu = t1[undefined]
        horizontal = np.stack([tu[:, 0], tu[:, 1], np.zeros(tu.shape[0])], axis=-1)
        h = np.linalg.norm(horizontal, axis=-1)
        # a unit vector perpendicular to t1 in its vertical plane (north when t1 is vertical)
        b[undefined] = np.where((h > 0.0)[:, None],
                                -tu[:, 2:3] * horizontal / np.where(h > 0.0, h, 1.0)[:, None]
                                + h[:, None] * np.array([0.0, 0.0, 1.0]),
                                np.array([1.0, 0.0, 0.0]))
    w = b - np.sum(b * t1, axis=-1)[:, None] * t1
    return w / np.linalg.norm(w, axis=-1, keepdims=True)


def _half_turn_steps(t1: np.ndarray, t2: np.ndarray, beta: np.ndarray,
                     dmd: np.ndarray) -> np.ndarray:
    """Minimum-curvature steps for doglegs near pi, shape (k, 3).

    The end of an arc of radius ``R = dMD / beta`` turning by beta from t1 towards
    the unit normal ``u`` (:func:`half_turn_normal`):
    ``R [sin(beta) t1 + 2 sin^2(beta/2) u]``, the chord ``2 R sin(beta/2)`` long along
    the bisector (the same step as ``dMD/2 (t1 + t2) (2/beta) tan(beta/2)`` in exact
    arithmetic). At beta = pi exactly the turn is taken in the vertical plane of t1.
    """
    u = half_turn_normal(t1, t2)
    r = dmd / beta
    return ((r * np.sin(beta))[:, None] * t1
            + (2.0 * r * np.sin(0.5 * beta) ** 2)[:, None] * u)


@dataclass(frozen=True)
class Survey:
    """A directional survey with positions by minimum curvature.

    Attributes
    ----------
    md_m : ndarray, shape (n,)
        Measured depth of the stations, m, strictly increasing.
    inc_rad, azi_rad : ndarray, shape (n,)
        Inclination (from vertical-down) and azimuth (from north), rad.
    pos_m : ndarray, shape (n, 3)
        Station positions [north, east, tvd], m.
    dls_rad_per_m : ndarray, shape (n,)
        Dogleg severity of the interval ending at each station, rad/m
        (``dls[0] = 0``).

    Arrays are float64, C-contiguous and writeable (numba specialises on
    read-only arrays separately); treat them as read-only.
    """

    md_m: np.ndarray
    inc_rad: np.ndarray
    azi_rad: np.ndarray
    pos_m: np.ndarray
    dls_rad_per_m: np.ndarray

    @property
    def n(self) -> int:
        """Number of stations."""
        return int(self.md_m.shape[0])

    @property
    def tangent(self) -> np.ndarray:
        """Unit tangents [north, east, tvd] at the stations, shape (n, 3)."""
        return tangent_vectors(self.inc_rad, self.azi_rad)

    @property
    def dls_deg_per_30m(self) -> np.ndarray:
        """Dogleg severity, deg/30 m, shape (n,)."""
        return self.dls_rad_per_m * _RAD_PER_M_TO_DEG_PER_30M

    @property
    def dls_deg_per_100ft(self) -> np.ndarray:
        """Dogleg severity, deg/100 ft, shape (n,)."""
        return self.dls_rad_per_m * _RAD_PER_M_TO_DEG_PER_100FT

    @property
    def max_dls_deg_per_30m(self) -> float:
        """Largest dogleg severity of the survey, deg/30 m."""
        return float(self.dls_deg_per_30m.max())


def minimum_curvature(
    md_m: np.ndarray,
    inc_rad: np.ndarray,
    azi_rad: np.ndarray,
    start_pos_m: tuple[float, float, float] | np.ndarray = (0.0, 0.0, 0.0),
) -> Survey:
    """Positions and dogleg severity of a survey by the minimum-curvature method.

    Parameters
    ----------
    md_m : array_like, shape (n,)
        Measured depth, m, strictly increasing, n >= 2.
    inc_rad, azi_rad : array_like, shape (n,)
        Inclination and azimuth, rad.
    start_pos_m : array_like, shape (3,)
        Position [north, east, tvd] of the first station, m.

    Returns
    -------
    Survey

    Raises
    ------
    InputError
        Shapes differ, fewer than 2 stations, NaN, or MD not increasing.

    References
    ----------
    Sawaryn & Thorogood (2005), SPE-84246-PA, eq. 1-4:
    ``dp = dMD/2 (t1 + t2) RF``, ``RF = 2/beta tan(beta/2)``.
    """
    md = np.asarray(md_m, dtype=float).reshape(-1)
    inc = np.asarray(inc_rad, dtype=float).reshape(-1)
    azi = np.asarray(azi_rad, dtype=float).reshape(-1)
    if not (md.shape == inc.shape == azi.shape):
        raise InputError("survey", f"md, inc, azi lengths differ: {md.size}, {inc.size}, "
                         f"{azi.size}", "equal lengths")
    if md.size < 2:
        raise InputError("survey", f"{md.size} station(s)", "at least 2 stations")
    if not (np.all(np.isfinite(md)) and np.all(np.isfinite(inc)) and np.all(np.isfinite(azi))):
        raise InputError("survey", "contains NaN or infinite values", "finite numbers")
    dmd = np.diff(md)
    if np.any(dmd <= 0.0):
        k = int(np.argmax(dmd <= 0.0)) + 1
        raise InputError("survey.md_m", f"not increasing at station {k} ({md[k]} m after "
                         f"{md[k - 1]} m)", "strictly increasing measured depth")
    t = tangent_vectors(inc, azi)
    beta = dogleg_rad(t[:-1], t[1:])
    rf = ratio_factor(beta)
    step = (0.5 * dmd * rf)[:, None] * (t[:-1] + t[1:])
    near_pi = beta > BETA_NEAR_PI_RAD
    if np.any(near_pi):
        step[near_pi] = _half_turn_steps(t[:-1][near_pi], t[1:][near_pi], beta[near_pi],
                                         dmd[near_pi])
    pos = np.empty((md.size, 3))
    pos[0] = np.asarray(start_pos_m, dtype=float)
    pos[1:] = pos[0] + np.cumsum(step, axis=0)
    dls = np.zeros(md.size)
    dls[1:] = beta / dmd
    return Survey(md_m=md, inc_rad=inc, azi_rad=azi, pos_m=pos, dls_rad_per_m=dls)


def read_survey_csv(path: str | Path) -> Survey:
    """Read a survey CSV (``md_m,inc_deg,azi_deg``) and compute positions.

    Raises
    ------
    InputError
        Missing or non-UTF-8 file, missing column, unparsable or NaN cell, MD
        outside [0, 20 000] m or not strictly increasing, inclination outside
        [0, 180] or azimuth outside [0, 360);
        the field names ``file:row`` (row 1 is the header) and the column.
    """
    p = Path(path)
    if not p.is_file():
        raise InputError(str(p), "survey file not found", "an existing CSV file")
    try:
        with p.open(newline="", encoding="utf-8") as fh:
            rows = list(csv.reader(fh))
    except UnicodeDecodeError as exc:
        raise InputError(str(p), f"not UTF-8 text (byte 0x{exc.object[exc.start]:02x} at "
                         f"offset {exc.start})", "a UTF-8 encoded CSV file") from None
    if not rows:
        raise InputError(f"{p}:1", "empty survey file", "header md_m,inc_deg,azi_deg")
    header = [h.strip() for h in rows[0]]
    for col in SURVEY_COLUMNS:
        if col not in header:
            raise InputError(f"{p}:1", f"missing column {col!r}",
                             "columns md_m,inc_deg,azi_deg")
    extra = [h for h in header if h not in SURVEY_COLUMNS]
    if extra or len(header) != len(set(header)):
        raise InputError(f"{p}:1", f"unexpected or repeated columns {extra or header}",
                         "columns md_m,inc_deg,azi_deg")
    idx = [header.index(c) for c in SURVEY_COLUMNS]
    data: list[tuple[float, float, float]] = []
    for r, row in enumerate(rows[1:], start=2):
        if not row or all(not c.strip() for c in row):
            continue
        if len(row) != len(header):
            raise InputError(f"{p}:{r}", f"{len(row)} cells", f"{len(header)} cells per row")
        vals = []
        for col, i in zip(SURVEY_COLUMNS, idx, strict=True):
            cell = row[i].strip()
            try:
                v = float(cell)
            except ValueError:
                raise InputError(f"{p}:{r}:{col}", f"not a number: {cell!r}",
                                 "a finite number") from None
            if not math.isfinite(v):
                raise InputError(f"{p}:{r}:{col}", f"{cell!r} is not finite", "a finite number")
            vals.append(v)
        md, inc, azi = vals
        if not 0.0 <= md <= MD_MAX_M:
            raise InputError(f"{p}:{r}:md_m", f"MD {md:.6g} m out of range",
                             f"0 <= md_m <= {MD_MAX_M:.0f} (the deepest wells are about 15 km)")
        if not 0.0 <= inc <= 180.0:
            raise InputError(f"{p}:{r}:inc_deg", f"inclination {inc} out of range",
                             "0 <= inc_deg <= 180")
        if not 0.0 <= azi < 360.0:
            raise InputError(f"{p}:{r}:azi_deg", f"azimuth {azi} out of range",
                             "0 <= azi_deg < 360")
        if data and md <= data[-1][0]:
            raise InputError(f"{p}:{r}:md_m", f"MD {md} not greater than previous {data[-1][0]}",
                             "strictly increasing md_m")
        data.append((md, inc, azi))
    if len(data) < 2:
        raise InputError(str(p), f"{len(data)} station(s)", "at least 2 stations")
    arr = np.asarray(data)
    return minimum_curvature(arr[:, 0], np.radians(arr[:, 1]), np.radians(arr[:, 2]))


def write_survey_csv(survey: Survey, path: str | Path) -> None:
    """Write the survey as CSV ``md_m,inc_deg,azi_deg`` (full precision), atomically."""
    azi = np.degrees(survey.azi_rad) % 360.0
    azi = np.where(azi >= 360.0, 0.0, azi)
    with atomic_output(path) as tmp, tmp.open("w", newline="", encoding="utf-8") as fh:
        w = csv.writer(fh)
        w.writerow(SURVEY_COLUMNS)
        for md, inc, az in zip(survey.md_m, np.degrees(survey.inc_rad), azi, strict=True):
            w.writerow([repr(float(md)), repr(float(inc)), repr(float(az))])
