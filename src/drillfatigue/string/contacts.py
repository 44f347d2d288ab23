"""Contact points along each segment: where the string can touch the wall.

A rigid segment tested for wall contact only at its ends lets a straight
chord cut through the inside of a build unseen, and puts the supports of the
span bending (:mod:`drillfatigue.dynamics.span.bending`) in the wrong place.
:func:`contact_points` lists, for every segment, points along its axis with
the radius that touches the wall there:

* at a tool joint (every ``joint_length_m`` along drill pipe and heavy-weight
  pipe with a tool-joint OD larger than the body): the tool-joint radius, and
  never at a point that is not a tool joint;
* at a stabilizer: its blade radius at the blade centre and the two blade
  ends;
* at the centre upset of a heavy-weight joint: the upset radius;
* at both segment ends and at every extra point: the largest radius the
  component has there (the body radius, or the tool-joint radius where a tool
  joint sits at that end).

Spacing rule for the extra points. Between two tested points a distance
``s`` apart, a straight segment can meet the wall of a hole of curvature
kappa only by the arc's bulge over that chord, s^2 kappa / 8 (docs/model.md
section 10), so

    s <= sqrt(8 f c / kappa)            (curvature rule)

keeps what can pass the wall unseen below a fraction ``f`` of the radial
clearance ``c`` (hole radius minus body radius); default f = 0.25. With
22 mm collar clearance in a 8 deg/30 m build (kappa = 4.65e-3 rad/m) that is
3.1 m. A second bound puts a point where the pipe, sagging under its buoyed
weight w between supports, would reach the wall in a straight hole: the
clamped span deflects w s^4 / (384 EI), so

    s <= (384 EI c / w)^(1/4)            (sag rule)

(about 16 m for 5 in drill pipe, 15 m for 6 3/4 in collars in an 8 1/2 in
hole). Points are spread evenly between the fixed points (tool joints, blades,
segment ends) so that no gap exceeds the smaller bound. The simulator tests
these points against the wall with ``contact.points: string``
(:func:`drillfatigue.dynamics.contact.pack.pack_contact_points`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from drillfatigue.config.string import JOINTED_TYPES, StringConfig
from drillfatigue.errors import InputError
from drillfatigue.string.segments import Segments

KIND_BODY = 0
KIND_TOOL_JOINT = 1
KIND_BLADE = 2
KIND_UPSET = 3
#: Names of the point kinds (``ContactPoints.kind`` indexes this tuple).
KIND_NAMES: tuple[str, ...] = ("body", "tool_joint", "blade", "center_upset")
_TOL_M = 1e-6


@dataclass(frozen=True)
class ContactPoints:
    """Contact points of all segments, packed (SI).

    Points of segment k are ``ptr[k]:ptr[k + 1]``, sorted along the segment.

    Attributes
    ----------
    ptr : ndarray of int64, shape (n_segments + 1,)
    segment : ndarray of int64, shape (n_points,)
    s_m : ndarray, shape (n_points,)
        Position along the segment from its lower (bit-side) end, m.
    radius_m : ndarray, shape (n_points,)
        Contact radius at the point, m.
    kind : ndarray of int64, shape (n_points,)
        Index into :data:`KIND_NAMES`.
    max_spacing_m : ndarray, shape (n_segments,)
        The spacing bound used for each segment, m (inf: no extra points).
    """

    ptr: np.ndarray
    segment: np.ndarray
    s_m: np.ndarray
    radius_m: np.ndarray
    kind: np.ndarray
    max_spacing_m: np.ndarray

    def of_segment(self, k: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(s_m, radius_m, kind) of segment k."""
        a, b = int(self.ptr[k]), int(self.ptr[k + 1])
        return self.s_m[a:b], self.radius_m[a:b], self.kind[a:b]


def max_point_spacing_m(clearance_m: float, curvature_rad_per_m: float,
                        chord_fraction: float = 0.25, ei_Nm2: float | None = None,
                        weight_per_m_N: float | None = None) -> float:
    """Largest spacing of contact points (module docstring rule), m.

    min(sqrt(8 f c / kappa), (384 EI c / w)^(1/4)); a bound is dropped when
    its input is zero or not given (inf when both are).
    """
    if not (clearance_m > 0.0):
        raise InputError("clearance_m", f"must be > 0, got {clearance_m!r}",
                         "hole radius > body radius")
    if not (0.0 < chord_fraction <= 1.0):
        raise InputError("chord_fraction", f"must be in (0, 1], got {chord_fraction!r}",
                         "0 < f <= 1")
    s = math.inf
    if curvature_rad_per_m > 0.0:
        s = math.sqrt(8.0 * chord_fraction * clearance_m / curvature_rad_per_m)
    if ei_Nm2 is not None and weight_per_m_N is not None and abs(weight_per_m_N) > 0.0:
        s = min(s, (384.0 * ei_Nm2 * clearance_m / abs(weight_per_m_N)) ** 0.25)
    return s


def _fixed_points(comp, z0: float, z1: float, c0: float, c1: float
                  ) -> list[tuple[float, float, int]]:
    """Tool joints, blades and centre upsets of a component inside [z0, z1] (string
    coordinates from the bit), as (z, radius, kind); c0, c1 the component's ends."""
    pts: list[tuple[float, float, int]] = []
    if comp.type in JOINTED_TYPES and comp.conn_od_m > comp.od_m:
        r_tj = 0.5 * comp.conn_od_m
        jl = comp.joint_length_m
        n = int((c1 - c0) / jl + 1e-9)
        for z in [c0 + i * jl for i in range(n + 1)] + [c1]:
            if z0 - _TOL_M <= z <= z1 + _TOL_M:
                pts.append((min(max(z, z0), z1), r_tj, KIND_TOOL_JOINT))
        if comp.center_upset_od_m is not None:
            for i in range(n):
                z = c0 + (i + 0.5) * jl
                if z0 <= z <= z1:
                    pts.append((z, 0.5 * comp.center_upset_od_m, KIND_UPSET))
    if comp.type == "stabilizer" and comp.blade_od_m is not None:
        mid = 0.5 * (c0 + c1)
        half = 0.5 * (comp.blade_length_m or 0.0)
        for z in sorted({mid - half, mid, mid + half}):
            if z0 - _TOL_M <= z <= z1 + _TOL_M:
                pts.append((min(max(z, z0), z1), 0.5 * comp.blade_od_m, KIND_BLADE))
    return pts


def contact_points(string_cfg: StringConfig, segments: Segments, hole_diameter_m: float,
                   curvature_rad_per_m: float | np.ndarray = 0.0,
                   chord_fraction: float = 0.25, sag_rule: bool = True) -> ContactPoints:
    """Contact points of every segment (module docstring for the rules).

    Parameters
    ----------
    string_cfg : StringConfig
        The components the segments were built from.
    segments : Segments
        ``build_segments(string_cfg, ...)``.
    hole_diameter_m : float
        Hole diameter for the clearance, m.
    curvature_rad_per_m : float or ndarray, shape (n_segments,)
        Hole curvature each segment may sit in (e.g. the well's largest, or
        the local one at each segment), rad/m.
    chord_fraction : float
        f of the curvature rule (share of the clearance a chord may pass unseen).
    sag_rule : bool
        Also bound the spacing by the own-weight sag rule.

    Returns
    -------
    ContactPoints
    """
    comps = string_cfg.components
    n = segments.n_segments
    if len(set(segments.component_index.tolist())) != len(comps) \
            or int(segments.component_index.max()) != len(comps) - 1:
        raise InputError("segments", "were not built from this string configuration",
                         "build_segments(string_cfg, ...)")
    kappa = np.broadcast_to(np.asarray(curvature_rad_per_m, dtype=np.float64), (n,))
    if np.any(~np.isfinite(kappa)) or np.any(kappa < 0.0):
        raise InputError("curvature_rad_per_m", "must be finite and >= 0", ">= 0")
    r_hole = 0.5 * hole_diameter_m
    top = np.cumsum(segments.length_m)
    bottom = top - segments.length_m
    comp_start: dict[int, float] = {}
    comp_end: dict[int, float] = {}
    for k in range(n):
        ci = int(segments.component_index[k])
        comp_start.setdefault(ci, float(bottom[k]))
        comp_end[ci] = float(top[k])
    ptr = [0]
    seg_l: list[int] = []
    s_l: list[float] = []
    r_l: list[float] = []
    k_l: list[int] = []
    spacing = np.empty(n)
    for k in range(n):
        ci = int(segments.component_index[k])
        comp = comps[ci]
        z0, z1 = float(bottom[k]), float(top[k])
        r_body = 0.5 * comp.od_m
        clearance = r_hole - r_body
        if clearance <= 0.0:
            raise InputError(f"string.components[{ci}].od_m",
                             f"body OD {comp.od_m} does not fit the hole {hole_diameter_m}",
                             f"< {hole_diameter_m}")
        w = float(segments.buoyed_weight_N[k] / segments.length_m[k])
        s_max = max_point_spacing_m(clearance, float(kappa[k]), chord_fraction,
                                    float(segments.ei_Nm2[k]) if sag_rule else None,
                                    w if sag_rule else None)
        spacing[k] = s_max
        pts = _fixed_points(comp, z0, z1, comp_start[ci], comp_end[ci])
        at = {round(p[0], 6) for p in pts}
        for z in (z0, z1):
            if round(z, 6) not in at:
                pts.append((z, r_body, KIND_BODY))
        pts.sort(key=lambda p: (p[0], -p[1]))
        # one point per position (the largest radius wins: a blade over a body end)
        uniq: list[tuple[float, float, int]] = []
        for p in pts:
            if uniq and abs(p[0] - uniq[-1][0]) <= _TOL_M:
                continue
            uniq.append(p)
        full: list[tuple[float, float, int]] = [uniq[0]]
        for a, b in zip(uniq[:-1], uniq[1:], strict=True):
            gap = b[0] - a[0]
            m = math.ceil(gap / s_max - 1e-9) if math.isfinite(s_max) else 1
            for i in range(1, m):
                full.append((a[0] + gap * i / m, r_body, KIND_BODY))
            full.append(b)
        length = float(segments.length_m[k])
        for z, r, kd in full:
            seg_l.append(k)
            # the ends exactly at 0 and the length (positions are sums of lengths)
            s_l.append(0.0 if z - z0 <= _TOL_M else length if z1 - z <= _TOL_M else z - z0)
            r_l.append(r)
            k_l.append(kd)
        ptr.append(len(s_l))
    return ContactPoints(np.asarray(ptr, dtype=np.int64), np.asarray(seg_l, dtype=np.int64),
                         np.asarray(s_l), np.asarray(r_l), np.asarray(k_l, dtype=np.int64),
                         spacing)
