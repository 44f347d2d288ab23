"""Hole tortuosity: micro-doglegs added to a planned well path, and their measures.

A planned profile is a chain of smooth holds and arcs; a drilled hole is not.
Torque-and-drag practice adds small, regular or random doglegs to the plan
(micro-tortuosity) so that a smooth plan predicts the friction, torque and
bending of a real hole (Samuel & Liu, wellbore tortuosity in torque and drag,
2009; Gaynor et al., "Tortuosity versus micro-tortuosity - why little things
mean a lot", SPE/IADC 67818, 2001; Bang et al., "Analysis and quantification
of wellbore tortuosity", SPE 173103, 2016). The model here tilts the plan's
direction at every MD by a small angle ``delta(md)``:

- in the plan's vertical plane, towards its high side ``h = dt/dinc``
  (``direction: inclination``; on a hole in a vertical plane ``delta`` adds to
  the inclination), across it towards the right side ``r`` (the horizontal
  normal, ``azimuth``), or the same angle in each (``both``);
- ``t = cos|delta| t_plan + sin|delta| (delta_h h + delta_r r) / |delta|``,
  exactly unit length, so the hole keeps its measured depth;
- ``delta`` is a sine of amplitude A and period P starting at zero at
  ``md_start_m``, or seeded uniform draws in [-A, A] every P joined linearly.

A sine tilt of amplitude A (rad) and period P (m) added to a straight hole
turns the hole at ``2 pi A / P cos(...)`` rad/m: peak dogleg severity
``2 pi A / P``, mean ``4 A / P`` over whole periods (commercial torque-and-drag
programs quote the latter as the "maximum dogleg variation" of their sine
model). The tortuous survey has the plan's stations plus ``stations_per_period``
stations per period from ``md_start_m``, its positions by minimum curvature.

The tortuosity index (:func:`tortuosity_index_per_m`) follows the drilling form
of Zhou, Zheng, Ashok & van Oort (IADC/SPE-178869-MS, 2016), itself from the
retinal-vessel index of Grisan et al. (2008): the path is cut into curve turns,
``TI = n / (n + 1) / L sum_i (L_arc,i / L_chord,i - 1)`` over the n turns of
a path of length L, in 1/m (the SPE papers quote it in 1/ft times 1e7:
multiply by 0.3048e7). A turn here ends where the axis about which the hole
turns has swung more than 90 deg from the axis at the turn's start (for a
planar wave: where the turn reverses) or where the hole goes from straight to
curved or back; the index is measured directly in 3D, not as an inclination
and an azimuth part.

Angles in radians and lengths in metres inside; the configuration
(:class:`drillfatigue.config.well.TortuosityConfig`) gives degrees.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from drillfatigue.config.well import TortuosityConfig
from drillfatigue.errors import InputError
from drillfatigue.limits import FEATURE_BOUNDS
from drillfatigue.well.survey import (
    BETA_NEAR_PI_RAD,
    Survey,
    dogleg_rad,
    half_turn_normal,
    minimum_curvature,
)

__all__ = ["apply_tortuosity", "dls_statistics", "tilt_rad", "tortuosity_index_per_m",
           "tortuosity_report"]

_RAD_PER_M_TO_DEG_PER_30M = math.degrees(1.0) * 30.0
#: A grid station nearer a plan station than this fraction of the grid spacing
#: is left out (the plan station stays): no interval shorter than 1/8 of the spacing.
_MERGE_FRACTION = 0.125
#: An interval turning by less than this is straight for the tortuosity index, rad.
_STRAIGHT_RAD = 1e-9
#: Horizontal part of a unit tangent below which the azimuth is taken from the plan.
_VERTICAL = 1e-12


def tilt_rad(md_m: np.ndarray, spec: TortuosityConfig) -> tuple[np.ndarray, np.ndarray]:
    """Tilt of the hole from the plan towards its high side and its right side, rad.

    Parameters
    ----------
    md_m : ndarray, shape (n,)
        Measured depths, m.
    spec : TortuosityConfig

    Returns
    -------
    delta_h, delta_r : ndarray, shape (n,)
        Tilt in the plan's vertical plane (towards the high side) and across it
        (towards the right side), rad; zero above ``spec.md_start_m``.
    """
    md = np.asarray(md_m, dtype=np.float64)
    x = np.maximum(md - spec.md_start_m, 0.0) / spec.period_m  # periods from the start
    a = math.radians(spec.amplitude_deg)
    if spec.model == "sine":
        wave = a * np.sin(2.0 * math.pi * x)
        pair = (wave, wave)
    else:
        n_nodes = int(math.floor(float(x.max(initial=0.0)))) + 2
        rng = np.random.default_rng(spec.seed)
        # one (high side, right side) pair per node, drawn node after node, so a
        # deeper well with the same seed shares the shallower nodes' values
        draws = rng.uniform(-1.0, 1.0, size=(n_nodes, 2))
        draws[0] = 0.0  # no tilt where the tortuosity starts
        nodes = np.arange(n_nodes, dtype=np.float64)
        pair = (a * np.interp(x, nodes, draws[:, 0]), a * np.interp(x, nodes, draws[:, 1]))
    zero = np.zeros_like(md)
    delta_h = pair[0] if spec.direction in ("inclination", "both") else zero
    delta_r = pair[1] if spec.direction in ("azimuth", "both") else zero
    above = md <= spec.md_start_m
    return np.where(above, 0.0, delta_h), np.where(above, 0.0, delta_r)


def _station_md(plan_md: np.ndarray, spec: TortuosityConfig) -> np.ndarray:
    """The plan's stations and a grid of ``stations_per_period`` per period from the start."""
    td = float(plan_md[-1])
    start = max(spec.md_start_m, float(plan_md[0]))
    if start >= td:
        return plan_md.copy()
    k = np.arange(int(math.floor((td - start) * spec.stations_per_period / spec.period_m)) + 1)
    grid = start + k * spec.period_m / spec.stations_per_period
    h = spec.period_m / spec.stations_per_period
    keep = grid[(_distance_to_sorted(grid, plan_md) > _MERGE_FRACTION * h) & (grid < td)]
    return np.sort(np.concatenate([plan_md, keep]))


def _distance_to_sorted(x: np.ndarray, sorted_md: np.ndarray) -> np.ndarray:
    """Distance of each ``x`` to the nearest value of the sorted ``sorted_md``."""
    i = np.clip(np.searchsorted(sorted_md, x), 1, sorted_md.size - 1)
    return np.minimum(np.abs(x - sorted_md[i - 1]), np.abs(sorted_md[i] - x))


def _plan_tangents(plan: Survey, md: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Unit tangents of the plan's minimum-curvature arcs at ``md`` and the azimuth
    of the station starting each one's interval (the plan's azimuth of a vertical
    hole), shapes (n, 3) and (n,)."""
    t = plan.tangent
    i = np.clip(np.searchsorted(plan.md_m, md, side="right") - 1, 0, plan.n - 2)
    t1, t2 = t[i], t[i + 1]
    f = np.clip((md - plan.md_m[i]) / (plan.md_m[i + 1] - plan.md_m[i]), 0.0, 1.0)
    beta = dogleg_rad(t1, t2)
    out = t1 + f[:, None] * (t2 - t1)  # straight intervals: the two tangents are equal
    arc = beta >= 1e-12
    if np.any(arc):
        b = beta[arc]
        sb = np.sin(b)
        out[arc] = (np.sin((1.0 - f[arc]) * b)[:, None] * t1[arc]
                    + np.sin(f[arc] * b)[:, None] * t2[arc]) / sb[:, None]
    near_pi = beta > BETA_NEAR_PI_RAD
    if np.any(near_pi):
        # 1/sin(beta) is ill-conditioned: turn t1 towards the unit normal of the turn
        u = half_turn_normal(t1[near_pi], t2[near_pi])
        th = (f * beta)[near_pi]
        out[near_pi] = np.cos(th)[:, None] * t1[near_pi] + np.sin(th)[:, None] * u
    out /= np.linalg.norm(out, axis=1, keepdims=True)
    return out, plan.azi_rad[i]


def apply_tortuosity(plan: Survey, spec: TortuosityConfig) -> Survey:
    """The plan with the micro-doglegs of ``spec`` added (module docstring).

    Parameters
    ----------
    plan : Survey
        The planned survey (stations, inclination, azimuth, positions).
    spec : TortuosityConfig
        Model, amplitude, period, start MD, direction, seed.

    Returns
    -------
    Survey
        Stations: the plan's and ``spec.stations_per_period`` per period below
        ``spec.md_start_m``; the same measured depths end to end. Above the
        start its stations, angles and positions are the plan's, bit for bit.
        A zero amplitude returns ``plan`` itself.

    Raises
    ------
    InputError
        The tortuous hole exceeds the largest dogleg severity of the well
        profiles (60 deg/30 m) somewhere.
    """
    if spec.amplitude_deg == 0.0:
        return plan
    md = _station_md(plan.md_m, spec)
    t_plan, azi_plan = _plan_tangents(plan, md)
    inc_p = np.arctan2(np.hypot(t_plan[:, 0], t_plan[:, 1]), t_plan[:, 2])
    vertical = np.hypot(t_plan[:, 0], t_plan[:, 1]) <= _VERTICAL
    azi_p = np.where(vertical, azi_plan, np.arctan2(t_plan[:, 1], t_plan[:, 0]))
    ci, si, ca, sa = np.cos(inc_p), np.sin(inc_p), np.cos(azi_p), np.sin(azi_p)
    high = np.stack([ci * ca, ci * sa, -si], axis=1)   # d t / d inc
    right = np.stack([-sa, ca, np.zeros_like(sa)], axis=1)  # horizontal, d t / d azi / sin inc
    d_h, d_r = tilt_rad(md, spec)
    size = np.hypot(d_h, d_r)
    # sin|d| / |d| -> 1 as |d| -> 0
    k = np.where(size > 0.0, np.sin(size) / np.where(size > 0.0, size, 1.0), 1.0)
    t = (np.cos(size)[:, None] * t_plan
         + (k * d_h)[:, None] * high + (k * d_r)[:, None] * right)
    horiz = np.hypot(t[:, 0], t[:, 1])
    inc = np.arctan2(horiz, t[:, 2])
    azi = np.where(horiz > _VERTICAL, np.arctan2(t[:, 1], t[:, 0]), azi_p)
    azi = np.mod(azi, 2.0 * math.pi)
    azi = np.where(azi >= 2.0 * math.pi, 0.0, azi)
    # above the start the plan's own angles, so that part of the hole is the plan's
    plan_station = np.isin(md, plan.md_m)
    untouched = (md <= spec.md_start_m) & plan_station
    j = np.searchsorted(plan.md_m, md[untouched])
    inc[untouched] = plan.inc_rad[j]
    azi[untouched] = plan.azi_rad[j]
    out = minimum_curvature(md, inc, azi, plan.pos_m[0])
    top = FEATURE_BOUNDS["dls_deg_per_30m"].hi
    worst = float(out.dls_deg_per_30m.max())
    if worst > top:
        at = float(out.md_m[int(np.argmax(out.dls_deg_per_30m))])
        raise InputError("well.tortuosity.amplitude_deg",
                         f"the tortuous hole turns at {worst:.4g} deg/30m at MD {at:.1f} m",
                         f"plan and tortuosity together <= {top:g} deg/30m")
    return out


def dls_statistics(survey: Survey, md_from_m: float = 0.0) -> tuple[float, float]:
    """Largest and mean dogleg severity of the hole below ``md_from_m``, deg/30 m.

    The mean is the total turning angle over the length (sum of the interval
    doglegs / sum of their MD lengths) of the intervals that end below
    ``md_from_m``; both are 0 when there is none.
    """
    md = survey.md_m
    beta = survey.dls_rad_per_m[1:] * np.diff(md)
    sel = md[1:] > md_from_m
    if not np.any(sel):
        return 0.0, 0.0
    length = float(np.sum(np.diff(md)[sel]))
    mean = float(np.sum(beta[sel])) / length * _RAD_PER_M_TO_DEG_PER_30M
    return float(survey.dls_deg_per_30m[1:][sel].max()), mean


def tortuosity_index_per_m(survey: Survey) -> float:
    """Tortuosity index of a survey's path, 1/m (module docstring).

    ``n / (n + 1) / L * sum (arc / chord - 1)`` over the path's n curve turns;
    0 for a straight hole or a single arc of small angle's limit.
    """
    t = survey.tangent
    beta = dogleg_rad(t[:-1], t[1:])
    axis = np.cross(t[:-1], t[1:])
    norm = np.linalg.norm(axis, axis=1)
    straight = (beta < _STRAIGHT_RAD) | (norm == 0.0)
    axis = axis / np.where(straight, 1.0, norm)[:, None]
    starts = [0]
    ref = 0
    for k in range(1, beta.size):
        if straight[k] != straight[ref] or (not straight[k] and float(axis[k] @ axis[ref]) < 0.0):
            starts.append(k)
            ref = k
    bounds = np.array([*starts, beta.size])
    md, pos = survey.md_m, survey.pos_m
    arc = md[bounds[1:]] - md[bounds[:-1]]
    chord = np.linalg.norm(pos[bounds[1:]] - pos[bounds[:-1]], axis=1)
    n = arc.size
    length = float(md[-1] - md[0])
    return float(n / (n + 1) * np.sum(arc / chord - 1.0) / length)


def tortuosity_report(plan: Survey, path: Survey, spec: TortuosityConfig | None
                      ) -> dict[str, Any]:
    """What the tortuosity of a well does to its hole, for ``well show`` and the ``wells`` stage.

    Returns
    -------
    dict
        The model and its parameters, the peak dogleg severity it adds to a
        straight hole, and for the plan and the tortuous hole: the largest and
        mean dogleg severity below the start MD (deg/30 m) and the tortuosity
        index of the whole path (1/m).
    """
    md_from = spec.md_start_m if spec is not None else 0.0
    out: dict[str, Any] = {}
    if spec is not None:
        out.update(model=spec.model, amplitude_deg=spec.amplitude_deg, period_m=spec.period_m,
                   md_start_m=spec.md_start_m, direction=spec.direction,
                   peak_added_dls_deg_per_30m=spec.peak_added_dls_deg_per_30m)
        if spec.model == "random":
            out["seed"] = spec.seed
    for name, sv in (("plan", plan), ("tortuous", path)):
        mx, mean = dls_statistics(sv, md_from)
        out[name] = {"max_dls_deg_per_30m": mx, "mean_dls_deg_per_30m": mean,
                     "tortuosity_index_per_m": tortuosity_index_per_m(sv),
                     "n_stations": sv.n}
    return out
