"""The wellbore as a chain of straight cylinders for the contact model.

The survey's minimum-curvature path is resampled into nodes; consecutive
nodes are the end points of straight cylinders (docs/model.md#contact). Every
survey station and every hole-size change is a node, so each node interval
lies on a single circular arc of curvature ``kappa`` and a single hole size.
Inside an arc the node spacing ``L`` keeps the chord (sagitta) error
``L^2 kappa / 8`` below ``chord_error_fraction * min_clearance_m`` (default
1 % of the smallest radial clearance), and ``L <= max_cylinder_length_m``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from drillfatigue.config.well import WellConfig
from drillfatigue.errors import InputError
from drillfatigue.well.profiles import build_survey
from drillfatigue.well.survey import BETA_NEAR_PI_RAD, Survey, dogleg_rad, half_turn_normal

__all__ = ["Wellbore", "arc_points", "build_wellbore", "resample_path"]


def arc_points(p1: np.ndarray, t1: np.ndarray, t2: np.ndarray, ds: np.ndarray,
               s: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Points on minimum-curvature arcs (vectorised numpy form).

    Parameters
    ----------
    p1, t1, t2 : ndarray, shape (k, 3)
        Start point (m) and unit start/end tangents of each arc.
    ds : ndarray, shape (k,)
        Arc length (MD interval), m, > 0.
    s : ndarray, shape (k,)
        Arc length from ``p1`` to the wanted point, m.

    Returns
    -------
    pos : ndarray, shape (k, 3)
        Positions, m.
    tan : ndarray, shape (k, 3)
        Unit tangents (slerp of t1, t2).

    Notes
    -----
    Same formulas as :func:`drillfatigue.well.kernels.path_point`, including its
    form for doglegs within 1e-3 rad of pi; a point at ``s = ds`` is the
    minimum-curvature step of Sawaryn & Thorogood (2005).
    """
    beta = dogleg_rad(t1, t2)
    straight = beta < 1e-12
    b = np.where(straight, 1.0, beta)
    R = ds / b
    th = s / R
    sb = np.sin(b)
    ca = 2.0 * R * np.sin(b - 0.5 * th) * np.sin(0.5 * th) / sb
    cb = 2.0 * R * np.sin(0.5 * th) ** 2 / sb
    wa = np.sin(b - th) / sb
    wb = np.sin(th) / sb
    pos = p1 + ca[:, None] * t1 + cb[:, None] * t2
    tan = wa[:, None] * t1 + wb[:, None] * t2
    near_pi = beta > BETA_NEAR_PI_RAD
    if np.any(near_pi):
        # 1/sin(beta) is ill-conditioned here: t = cos(th) t1 + sin(th) u with u the
        # unit normal to t1 in the plane of the turn (the kernel's _half_turn_point)
        bn = near_pi.nonzero()[0]
        u = half_turn_normal(t1[bn], t2[bn])
        thh = th[bn]
        pos[bn] = p1[bn] + R[bn, None] * (np.sin(thh)[:, None] * t1[bn]
                                          + (2.0 * np.sin(0.5 * thh) ** 2)[:, None] * u)
        tan[bn] = np.cos(thh)[:, None] * t1[bn] + np.sin(thh)[:, None] * u
    if np.any(straight):
        f = (s / ds)[:, None]
        dt = t2 - t1
        pos_l = p1 + s[:, None] * t1 + 0.5 * s[:, None] * f * dt
        tan_l = t1 + f * dt
        tan_l /= np.linalg.norm(tan_l, axis=1, keepdims=True)
        pos = np.where(straight[:, None], pos_l, pos)
        tan = np.where(straight[:, None], tan_l, tan)
    return pos, tan


def resample_path(survey: Survey, max_length_m: np.ndarray | float, breaks_md_m: np.ndarray,
                  sagitta_m: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Nodes along the survey path at most ``L`` apart with sagitta <= ``sagitta_m``.

    Parameters
    ----------
    survey : Survey
    max_length_m : float
        Cap on the node spacing, m.
    breaks_md_m : ndarray
        Extra MDs that must be nodes (hole-size changes), m.
    sagitta_m : float
        Allowed chord error ``L^2 kappa / 8``, m.

    Returns
    -------
    node_md_m : ndarray, shape (m,)
    node_pos_m : ndarray, shape (m, 3)
    node_tan : ndarray, shape (m, 3)
    """
    md = survey.md_m
    t = survey.tangent
    beta = dogleg_rad(t[:-1], t[1:])
    dmd = np.diff(md)
    kappa = beta / dmd
    with np.errstate(divide="ignore"):
        l_sag = np.where(kappa > 0.0, np.sqrt(8.0 * sagitta_m / np.where(kappa > 0, kappa, 1.0)),
                         np.inf)
    l_max = np.minimum(l_sag, max_length_m)
    brk = np.asarray(breaks_md_m, dtype=float)
    seg_i: list[np.ndarray] = []
    seg_s: list[np.ndarray] = []
    for i in range(dmd.size):
        inner = brk[(brk > md[i]) & (brk < md[i + 1])] - md[i]
        edges = np.concatenate([[0.0], np.sort(inner), [dmd[i]]])
        parts = [np.array([0.0])]
        for a, b in zip(edges[:-1], edges[1:], strict=True):
            n = max(1, math.ceil((b - a) / l_max[i] - 1e-12))
            parts.append(a + (b - a) * np.arange(1, n + 1) / n)
        s = np.concatenate(parts)[:-1]  # the interval's end is the next interval's start
        seg_i.append(np.full(s.size, i))
        seg_s.append(s)
    idx = np.concatenate(seg_i)
    s = np.concatenate(seg_s)
    pos, tan = arc_points(survey.pos_m[idx], t[idx], t[idx + 1], dmd[idx], s)
    node_md = np.concatenate([md[idx] + s, md[-1:]])
    node_pos = np.concatenate([pos, survey.pos_m[-1:]])
    node_tan = np.concatenate([tan, t[-1:]])
    return node_md, node_pos, node_tan


@dataclass(frozen=True)
class Wellbore:
    """Chain of n straight cylinders along the well path.

    Attributes
    ----------
    p0_m, p1_m : ndarray, shape (n, 3)
        Centre-line end points [north, east, tvd] of each cylinder, m
        (``p1_m[i] == p0_m[i + 1]``).
    axis : ndarray, shape (n, 3)
        Unit axis ``(p1 - p0) / |p1 - p0|``.
    length_m : ndarray, shape (n,)
        Chord length ``|p1 - p0|``, m.
    radius_m : ndarray, shape (n,)
        Hole radius, m.
    md0_m : ndarray, shape (n,)
        MD at ``p0``, m.
    node_md_m : ndarray, shape (n + 1,)
        MD of the path nodes, m.
    node_pos_m : ndarray, shape (n + 1, 3)
        Node positions (on the minimum-curvature path), m.
    node_tan : ndarray, shape (n + 1, 3)
        True unit tangent of the path at each node.
    survey : Survey
        The survey the chain was built from.
    sagitta_limit_m : float
        The chord-error bound used for resampling, m.

    All arrays are float64 and C-contiguous (ready for numba kernels); treat
    them as read-only.
    """

    p0_m: np.ndarray
    p1_m: np.ndarray
    axis: np.ndarray
    length_m: np.ndarray
    radius_m: np.ndarray
    md0_m: np.ndarray
    node_md_m: np.ndarray
    node_pos_m: np.ndarray
    node_tan: np.ndarray
    survey: Survey
    sagitta_limit_m: float

    @property
    def n(self) -> int:
        """Number of cylinders."""
        return int(self.length_m.shape[0])

    @property
    def md1_m(self) -> np.ndarray:
        """MD at ``p1`` of each cylinder, m, shape (n,)."""
        return self.node_md_m[1:]

    def cylinder_index(self, md_m: float | np.ndarray) -> int | np.ndarray:
        """Index of the cylinder containing ``md_m`` (clamped to [0, n-1])."""
        i = np.clip(np.searchsorted(self.node_md_m, md_m, side="right") - 1, 0, self.n - 1)
        return int(i) if np.ndim(md_m) == 0 else i

    def curvature_at_md(self, md_m: float | np.ndarray) -> float | np.ndarray:
        """Path curvature (dogleg severity) at ``md_m``, rad/m; 0 beyond the ends."""
        i = np.atleast_1d(self.cylinder_index(md_m))
        beta = dogleg_rad(self.node_tan[i], self.node_tan[i + 1])
        k = beta / (self.node_md_m[i + 1] - self.node_md_m[i])
        mdv = np.atleast_1d(np.asarray(md_m, dtype=float))
        k = np.where((mdv < self.node_md_m[0]) | (mdv > self.node_md_m[-1]), 0.0, k)
        return float(k[0]) if np.ndim(md_m) == 0 else k

    def point_at_md(self, md_m: float | np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Position (m) and unit tangent of the path at ``md_m``.

        On the minimum-curvature arc between nodes (not the chord); beyond the
        ends the path continues straight along the end tangent. A scalar gives
        shapes (3,), (3,); an array of k MDs gives (k, 3), (k, 3).
        """
        mdv = np.atleast_1d(np.asarray(md_m, dtype=float))
        i = np.atleast_1d(self.cylinder_index(mdv))
        ds = self.node_md_m[i + 1] - self.node_md_m[i]
        s = np.clip(mdv - self.node_md_m[i], 0.0, ds)
        pos, tan = arc_points(self.node_pos_m[i], self.node_tan[i], self.node_tan[i + 1], ds, s)
        above = mdv < self.node_md_m[0]
        below = mdv > self.node_md_m[-1]
        if np.any(above):
            pos[above] = self.node_pos_m[0] + (mdv[above] - self.node_md_m[0])[:, None] \
                * self.node_tan[0]
            tan[above] = self.node_tan[0]
        if np.any(below):
            pos[below] = self.node_pos_m[-1] + (mdv[below] - self.node_md_m[-1])[:, None] \
                * self.node_tan[-1]
            tan[below] = self.node_tan[-1]
        if np.ndim(md_m) == 0:
            return pos[0], tan[0]
        return pos, tan

    def hole_radius_at_md(self, md_m: float | np.ndarray) -> float | np.ndarray:
        """Hole radius at ``md_m``, m."""
        i = self.cylinder_index(md_m)
        r = self.radius_m[i]
        return float(r) if np.ndim(md_m) == 0 else r


def build_wellbore(cfg: WellConfig, name: str | None = None, survey: Survey | None = None,
                   min_clearance_m: float | None = None) -> Wellbore:
    """Resample a profile's path into a chain of straight cylinders.

    Parameters
    ----------
    cfg : WellConfig
        The ``well`` section (hole sizes, resampling settings, profiles).
    name : str, optional
        Profile name (default: ``cfg.profile`` or the first); ignored when
        ``survey`` is given.
    survey : Survey, optional
        Use this survey instead of building one from ``cfg``.
    min_clearance_m : float, optional
        Smallest radial clearance hole - component contact radius, m
        (default ``cfg.min_clearance_m``). The chord error is kept below
        ``cfg.chord_error_fraction`` (1 %) of it.

    Returns
    -------
    Wellbore
    """
    clearance = cfg.min_clearance_m if min_clearance_m is None else float(min_clearance_m)
    if not (clearance > 0.0 and math.isfinite(clearance)):
        raise InputError("min_clearance_m", f"got {clearance}", "> 0")
    sv = build_survey(cfg, name) if survey is None else survey
    sagitta = cfg.chord_error_fraction * clearance
    tops = np.array([h.md_top_m for h in cfg.hole])
    radii = np.array([h.diameter_m for h in cfg.hole]) / 2.0
    node_md, node_pos, node_tan = resample_path(sv, cfg.max_cylinder_length_m, tops[1:], sagitta)
    p0 = node_pos[:-1]
    p1 = node_pos[1:]
    d = p1 - p0
    length = np.linalg.norm(d, axis=1)
    axis = d / length[:, None]
    mid = 0.5 * (node_md[:-1] + node_md[1:])
    radius = radii[np.searchsorted(tops, mid, side="right") - 1]
    # Arrays stay writeable on purpose: numba compiles a separate
    # specialisation for read-only arrays, and kernels receive these directly.
    return Wellbore(p0_m=p0, p1_m=p1, axis=axis, length_m=length, radius_m=radius,
                    md0_m=node_md[:-1], node_md_m=node_md, node_pos_m=node_pos,
                    node_tan=node_tan, survey=sv, sagitta_limit_m=sagitta)
