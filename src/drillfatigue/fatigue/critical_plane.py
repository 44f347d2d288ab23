"""Multiaxial critical-plane damage on the tube surface (and the uniaxial route).

The outer surface is in plane stress (sigma = sigma_z, tau = tau_z-theta) in the
local axes (z axial, theta hoop, r radial, r the free-surface normal). Candidate
planes (docs/fatigue.md#critical-plane):

* family A, planes perpendicular to the surface, normal n = (cos t, sin t, 0) at
  angle t to the pipe axis: sigma_n = sigma cos^2 t + tau sin 2t; one shear
  component, along the surface, tau_u = -sigma sin t cos t + tau cos 2t;
* family B, planes inclined at 45 degrees to the surface (n = (cos t, sin t, 0)
  cos b + e_r sin b, b = 45 deg): sigma_n = cos^2 b sigma_nA; the shear vector
  has two components, tau_a = cos b tau_u and tau_b = -sin b cos b sigma_nA,
  and is projected on ``n_shear_axes`` axes psi in the plane (code_aster's
  projection of the shear path on axes).

Both families are symmetric under t -> t + 180 deg, so t runs over [0, 180).
Mud pressure (``pressure`` of :func:`evaluate_location`) turns the axial load
into the true wall force and adds the Lame hoop and radial stresses, constant
over a window: a constant normal stress per plane (their shear on a plane is
constant too and changes no cycle), so the rainflow counts are those of the
load-only stress and only the normal-stress terms of the criteria move.
Family B is off by default: in the load-varying part (sigma_theta = 0) the
in-surface principal stresses sigma/2 +- sqrt(sigma^2/4 + tau^2) have
opposite signs, so the largest shear, (sigma_1 - sigma_2)/2, is always on a
family-A plane (family B carries at most sigma_1/2); it can still
be switched on for Findley/Fatemi-Socie studies. The coarse grid has ``plane_step_deg``;
the governing plane of the most damaged surface points is refined to
``plane_step_deg / 2**n_refine`` around it (code_aster refines four times: 2, 1,
0.5, 0.25 deg): the first four halvings at once, as a dense local grid within
one coarse step (every plane the greedy halving search would visit, and the
rest of the window, in one pass over the history), further levels greedily.

Candidates whose shear coefficients are parallel share one rainflow count: a
plane and its conjugate at theta + 90 deg carry exactly opposite shear, so the
coarse family-A grid of 18 planes needs 9 counts (:func:`shear_groups`).

Per shear group the resolved shear is rainflow counted (numba kernel
:func:`drillfatigue.fatigue.kernels.multiplane_damage`), each cycle gets an
equivalent stress from its shear range and the normal stress at its two extreme
instants, and Miner damage comes from the tension S-N curve:

* ``matake``: sigma_eq = (f/t)[dtau/2 + a max(sigma_n1, sigma_n2, 0)],
  a = 2t/f - 1; the critical plane is the plane of largest shear damage
  (Matake's maximum-shear plane; sigma_eq = dtau there), so uniaxial loading
  gives exactly the uniaxial result (45 deg plane, sigma_eq = sigma_a);
* ``findley``: f = dtau/2 + k max(sigma_n1, sigma_n2) on the plane of largest
  damage, mapped to a tension amplitude by sigma_eq = 2 f/(k + sqrt(1 + k^2));
  closed forms: pure torsion f = tau_a sqrt(1 + k^2), pure tension
  f = sigma_a (k + sqrt(1 + k^2))/2;
* ``fatemi_socie`` (elastic, stress form): sigma_eq = dtau (1 + k
  max(sigma_n, 0)/sigma_y); the strain form (dgamma/2)(1 + k sigma_n,max/sigma_y)
  divided by the shear modulus;
* ``uniaxial``: rainflow of sigma_z at every point, with the configured
  mean-stress correction (the conventional route; ``uniaxial_damage``).

The normal stress is taken at the cycle's two turning instants (code_aster's
MATAKE_MODI_AV / FINDLEY convention), not its maximum over the whole span
(Bannantine-Socie); this is documented and exact for proportional loading.

References
----------
Matake, Bull. JSME 20 (1977) 257-263; Findley, J. Eng. Ind. 81 (1959) 301-306;
Fatemi & Socie, FFEMS 11 (1988) 149-165; Bannantine & Socie, ASTM STP 1122
(1992) 249-275; code_aster R7.04.04 (critères de fatigue multiaxiale).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from drillfatigue.errors import InputError, raise_for_status
from drillfatigue.fatigue import kernels as K
from drillfatigue.fatigue.rainflow import find_cycles_indexed, kernel_residue_mode
from drillfatigue.fatigue.sn import SNCurve, correct_mean_stress
from drillfatigue.fatigue.stress import (SCF, Pressure, Section, surface_coefficients,
                                         surface_pressure_stresses, true_wall_force_N)
from drillfatigue.status import OK, STACK_OVERFLOW
from drillfatigue.units import MPA_PA

CRITERIA: tuple[str, ...] = ("matake", "findley", "fatemi_socie", "uniaxial")
_CRIT_CODE = {"matake": K.CRIT_MATAKE, "findley": K.CRIT_FINDLEY,
              "fatemi_socie": K.CRIT_FATEMI_SOCIE}


def _check_criterion(criterion: str, allowed: tuple[str, ...] = CRITERIA) -> None:
    """InputError unless ``criterion`` is one of ``allowed`` (the message lists all)."""
    if criterion not in allowed:
        raise InputError("fatigue.criterion", f"unknown criterion {criterion!r}",
                         ", ".join(CRITERIA))


@dataclass(frozen=True)
class CriterionParams:
    """Constants of the criteria.

    Attributes
    ----------
    torsion_to_tension_ratio : float
        t/f, fully reversed torsion over tension fatigue limit (Matake);
        1/sqrt(3) (von Mises) for ductile steel; must be in [0.5, 1].
    findley_k : float
        Findley normal-stress sensitivity (0.2-0.3 for ductile steel).
    fs_k : float
        Fatemi-Socie k (0.5-1).
    yield_Pa : float
        Yield strength for Fatemi-Socie, Pa.
    """

    torsion_to_tension_ratio: float = 1.0 / math.sqrt(3.0)
    findley_k: float = 0.25
    fs_k: float = 0.6
    yield_Pa: float = 517e6

    def constants(self, criterion: str) -> tuple[float, float, float]:
        """(ca, cb, cc) for the kernel's ``_equivalent_batch``."""
        if criterion == "matake":
            r = self.torsion_to_tension_ratio
            return 1.0 / r, 2.0 * r - 1.0, 0.0
        if criterion == "findley":
            k = self.findley_k
            return k, 2.0 / (k + math.sqrt(1.0 + k * k)), 0.0
        _check_criterion(criterion, ("fatemi_socie",))
        return self.fs_k, 1.0 / self.yield_Pa, 0.0


@dataclass(frozen=True)
class Planes:
    """Candidate planes and shear axes.

    Attributes
    ----------
    theta_deg : ndarray, shape (n,)
        Angle of the plane normal's surface projection to the pipe axis.
    beta_deg : ndarray, shape (n,)
        Inclination of the normal out of the surface (0 family A, 45 family B).
    psi_deg : ndarray, shape (n,)
        Shear projection axis within the plane (family B).
    c, n : ndarray, shape (n, 2)
        Resolved-shear and normal-stress coefficients on (sigma, tau).
    """

    theta_deg: np.ndarray
    beta_deg: np.ndarray
    psi_deg: np.ndarray
    c: np.ndarray
    n: np.ndarray

    def __len__(self) -> int:
        return int(self.theta_deg.shape[0])


def make_planes(theta_deg: np.ndarray, beta_deg: np.ndarray, psi_deg: np.ndarray) -> Planes:
    """Coefficients of the candidate planes (see module docstring)."""
    t = np.radians(np.asarray(theta_deg, dtype=float))
    b = np.radians(np.asarray(beta_deg, dtype=float))
    ps = np.radians(np.asarray(psi_deg, dtype=float))
    # sigma_nA = sigma cos^2 t + tau sin 2t ; tau_u = -sigma sin t cos t + tau cos 2t
    snA = np.column_stack([np.cos(t) ** 2, np.sin(2 * t)])
    tu = np.column_stack([-np.sin(t) * np.cos(t), np.cos(2 * t)])
    cb, sb = np.cos(b)[:, None], np.sin(b)[:, None]
    ta = cb * tu
    tb = -sb * cb * snA
    c = np.cos(ps)[:, None] * ta + np.sin(ps)[:, None] * tb
    n = cb**2 * snA
    return Planes(np.asarray(theta_deg, float), np.asarray(beta_deg, float),
                  np.asarray(psi_deg, float), np.ascontiguousarray(c), np.ascontiguousarray(n))


def plane_normal_offsets(planes: Planes, sigma_theta_Pa: float, sigma_r_Pa: float) -> np.ndarray:
    """Constant normal stress that fixed hoop and radial stresses put on each candidate, Pa.

    With sigma_theta and sigma_r constant over the window (mud pressure), a
    plane with normal cos b (cos t e_z + sin t e_theta) + sin b e_r carries
    cos^2 b sin^2 t sigma_theta + sin^2 b sigma_r more normal stress; its
    extra shear is constant too and changes no cycle.

    Returns
    -------
    ndarray, shape (n_planes,)
    """
    t = np.radians(planes.theta_deg)
    b = np.radians(planes.beta_deg)
    return np.cos(b) ** 2 * np.sin(t) ** 2 * sigma_theta_Pa + np.sin(b) ** 2 * sigma_r_Pa


def plane_grid(step_deg: float = 10.0, family_b: bool = False, n_shear_axes: int = 2) -> Planes:
    """Coarse candidate grid: family A every ``step_deg`` over [0, 180) and,
    optionally, family B (45 deg to the surface) with ``n_shear_axes`` axes
    psi = 0, 180/n, ... deg."""
    if not (0.0 < step_deg <= 45.0):
        raise InputError("fatigue.plane_step_deg", f"must be in (0, 45], got {step_deg}",
                         "0 < plane_step_deg <= 45")
    th = np.arange(0.0, 180.0 - 1e-9, step_deg)
    thetas, betas, psis = [th], [np.zeros_like(th)], [np.zeros_like(th)]
    if family_b:
        for psi in np.arange(n_shear_axes) * 180.0 / n_shear_axes:
            thetas.append(th)
            betas.append(np.full_like(th, 45.0))
            psis.append(np.full_like(th, psi))
    return make_planes(np.concatenate(thetas), np.concatenate(betas), np.concatenate(psis))


@dataclass(frozen=True)
class ShearGroups:
    """Candidates grouped by parallel resolved-shear coefficients.

    A plane and its conjugate (theta + 90 deg) have exactly opposite shear, and
    any two candidates with c_j = lambda c_i (lambda != 0) see the same rainflow
    cycles at the same instants, ranges scaled by |lambda|; the kernel counts
    each group once.

    Attributes
    ----------
    c : ndarray, shape (n_grp, 2)
        Representative shear coefficients (the first member's).
    ptr : ndarray, shape (n_grp + 1,), int64
    cand : ndarray, int64
        Members of group g: ``cand[ptr[g]:ptr[g + 1]]``.
    scale : ndarray
        |c_j| / |c_representative| of each member.
    """

    c: np.ndarray
    ptr: np.ndarray
    cand: np.ndarray
    scale: np.ndarray


def shear_groups(c: np.ndarray, tol: float = 1e-12) -> ShearGroups:
    """Group candidates whose shear coefficient vectors are parallel or
    antiparallel (|sin| of the angle between them below ``tol``); candidates
    with zero shear coefficients belong to no group (they carry no cycles)."""
    norm = np.hypot(c[:, 0], c[:, 1])
    reps: list[int] = []
    members: list[list[int]] = []
    for j in np.flatnonzero(norm > 0.0):
        for gi, r in enumerate(reps):
            if abs(c[j, 0] * c[r, 1] - c[j, 1] * c[r, 0]) <= tol * norm[j] * norm[r]:
                members[gi].append(int(j))
                break
        else:
            reps.append(int(j))
            members.append([int(j)])
    ptr = np.zeros(len(reps) + 1, dtype=np.int64)
    ptr[1:] = np.cumsum([len(m) for m in members])
    cand = np.array([j for m in members for j in m], dtype=np.int64)
    rep_of = np.repeat(np.array(reps, dtype=np.int64), [len(m) for m in members])
    scale = norm[cand] / norm[rep_of] if cand.size else np.zeros(0)
    return ShearGroups(np.ascontiguousarray(c[reps].reshape(-1, 2)), ptr, cand,
                       np.ascontiguousarray(scale))


def _boundaries(c: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Sorted pseudo-angles where each group's shear increment changes sign
    (``c`` one row per group: the two directions perpendicular to it) and the
    group owning each.

    The pseudo-angle of -w is that of w plus 2 (mod 4), so each group has one
    boundary in [0, 2) and its antipode in [2, 4): the result is the sorted
    first half B followed by B + 2, which lets the kernel count sectors on the
    folded half only.
    """
    wx, wy = -c[:, 1], c[:, 0]
    pa = np.empty(wx.size)
    K.pseudo_angles(wx, wy, pa)
    half = np.where(pa >= 2.0, pa - 2.0, pa)
    order = np.argsort(half, kind="stable")
    b = half[order]
    owner = np.arange(c.shape[0], dtype=np.int64)[order]
    return (np.ascontiguousarray(np.concatenate([b, b + 2.0])),
            np.ascontiguousarray(np.concatenate([owner, owner])))


def loads_channels(loads: np.ndarray) -> np.ndarray:
    """Loads (n_time, 6) as contiguous channels (6, n_time) for the kernel."""
    L = np.asarray(loads, dtype=np.float64)
    if L.ndim != 2 or L.shape[1] != 6:
        raise InputError("loads", f"must have shape (n_time, 6), got {L.shape}", "(n_time, 6)")
    out = np.empty((6, L.shape[0]))
    K.channels_of(L, out)
    return out


def plane_damage(loads: np.ndarray, coef_sigma: np.ndarray, coef_tau: np.ndarray, planes: Planes,
                 curve: SNCurve, criterion: str, params: CriterionParams,
                 residue: str = "half", thickness_factor: float = 1.0,
                 loads_are_channels: bool = False, hoop_radial_Pa: tuple[float, float] = (0.0, 0.0)
                 ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Damage of every candidate plane at every surface point (numba kernel).

    Parameters
    ----------
    loads : ndarray, shape (n_time, 6)
        N and N m.
    coef_sigma, coef_tau : ndarray, shape (n_points, 6)
    planes : Planes
    curve : SNCurve
    criterion : {'matake', 'findley', 'fatemi_socie'}
    params : CriterionParams
    residue : {'half', 'repeat', 'carry'} ('carry' closes as half)
    thickness_factor : float
        DNV thickness factor on the stress.
    loads_are_channels : bool
        ``loads`` is already (6, n_time) from :func:`loads_channels`.
    hoop_radial_Pa : (float, float)
        Hoop and radial stress constant over the window (mud pressure, Lame),
        Pa: a constant normal stress per plane (:func:`plane_normal_offsets`).

    Returns
    -------
    damage, select, param : ndarray, shape (n_points, n_planes)
        Miner damage, plane-selection damage (shear damage for Matake) and the
        largest criterion parameter of any cycle (Pa).
    """
    _check_criterion(criterion, tuple(_CRIT_CODE))
    LT = loads if loads_are_channels else loads_channels(loads)
    ca, cb, cc = params.constants(criterion)
    crit = _CRIT_CODE[criterion]
    sel = K.CRIT_SHEAR if criterion == "matake" else crit
    grp = shear_groups(planes.c)
    seg = curve.kernel_arrays()
    n_p, n_c = coef_sigma.shape[0], len(planes)
    dmg = np.zeros((n_p, n_c))
    sel_d = np.zeros((n_p, n_c))
    par = np.zeros((n_p, n_c))
    if grp.c.shape[0] == 0 or LT.shape[1] < 2:
        return dmg, sel_d, par
    bpa, bgrp = _boundaries(grp.c)
    cand_n = np.empty((n_c, 3))
    cand_n[:, :2] = planes.n
    cand_n[:, 2] = (plane_normal_offsets(planes, *hoop_radial_Pa) if any(hoop_radial_Pa)
                    else 0.0)
    mode = kernel_residue_mode(residue)
    sectors = K.ShearSectors(grp.c, bpa, bgrp)
    law = K.DamageLaw(grp.ptr, grp.cand, grp.scale, cand_n, crit, ca, cb, cc, sel,
                      thickness_factor / MPA_PA, *seg)
    cap = 1024
    while True:
        st = K.multiplane_damage(LT, np.ascontiguousarray(coef_sigma),
                                 np.ascontiguousarray(coef_tau), sectors, law, mode, cap, dmg,
                                 sel_d, par)
        if st == OK:
            return dmg, sel_d, par
        if st != STACK_OVERFLOW or cap > 4 * LT.shape[1] + 16:  # pragma: no cover - cannot happen
            raise_for_status(st, "multiplane_damage")
        cap *= 8


@dataclass
class LocationResult:
    """Result of one location (one section, one SCF set) of one joint."""

    damage: float
    critical_angle_deg: float
    critical_plane_deg: float
    critical_plane_beta_deg: float
    critical_point: int
    point_damage: np.ndarray  # shape (n_points,)
    uniaxial_damage: float
    param_max_Pa: float


def pick_planes(dmg: np.ndarray, sel: np.ndarray, rtol: float = 1e-9) -> np.ndarray:
    """Governing candidate per row: the largest selection damage; among planes
    tied with it (within ``rtol``, e.g. conjugate maximum-shear planes under
    Matake) the one with the largest criterion damage (conservative, and
    independent of rounding)."""
    smax = sel.max(axis=1, keepdims=True)
    near = sel >= smax * (1.0 - rtol)
    return np.argmax(np.where(near, dmg, -np.inf), axis=1)


#: refinement levels done at once as a dense local grid (2 (2^k - 1) trial planes
#: per point in one pass); further levels halve the step greedily
DENSE_LEVELS = 4


@dataclass(frozen=True)
class PlaneLaw:
    """What :func:`plane_damage` evaluates on candidate planes besides the loads and
    points: S-N curve, criterion and its constants, residue closure, DNV
    thickness factor and the hoop and radial stress constant over the window, Pa."""

    curve: SNCurve
    criterion: str
    params: CriterionParams
    residue: str = "half"
    thickness_factor: float = 1.0
    hoop_radial_Pa: tuple[float, float] = (0.0, 0.0)

    def damage(self, loads_T: np.ndarray, cs_rows: np.ndarray, ct_rows: np.ndarray,
               planes: Planes) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """:func:`plane_damage` of loads given as channels (:func:`loads_channels`)."""
        return plane_damage(loads_T, cs_rows, ct_rows, planes, self.curve, self.criterion,
                            self.params, self.residue, self.thickness_factor,
                            loads_are_channels=True, hoop_radial_Pa=self.hoop_radial_Pa)


class Governing(NamedTuple):
    """Governing plane of R surface points, each an ndarray of shape (R,).

    Attributes
    ----------
    theta_deg : ndarray
        Plane angle, deg.
    damage, select, param : ndarray
        Its damage, selection damage and largest criterion parameter (Pa).
    """

    theta_deg: np.ndarray
    damage: np.ndarray
    select: np.ndarray
    param: np.ndarray


def _pick_rows(trial_theta: np.ndarray, d: np.ndarray, s_: np.ndarray, p_: np.ndarray,
               own: np.ndarray, best: Governing) -> Governing:
    """Keep each row's best of its current plane and its own trial columns ``own``."""
    rows = np.arange(own.shape[0])
    dd = np.column_stack([best.damage, d[rows[:, None], own]])
    ss = np.column_stack([best.select, s_[rows[:, None], own]])
    pp = np.column_stack([best.param, p_[rows[:, None], own]])
    k = pick_planes(dd, ss)
    moved = k > 0
    th = best.theta_deg.copy()
    th[moved] = trial_theta[own[rows[moved], k[moved] - 1]]
    return Governing(th, dd[rows, k], ss[rows, k], pp[rows, k])


def refine_planes(loads_T: np.ndarray, cs_rows: np.ndarray, ct_rows: np.ndarray,
                  start: Governing, beta: np.ndarray, psi: np.ndarray, step0: float,
                  n_refine: int, law: PlaneLaw) -> Governing:
    """Refine the governing plane of several points to ``step0 / 2**n_refine``.

    The first ``DENSE_LEVELS`` halvings are done at once: every plane of the
    local grid theta0 + k step0/2^n (0 < |k| < 2^n, n = min(n_refine,
    DENSE_LEVELS)) is evaluated in one pass over the history, and the best is
    kept. This visits every plane the greedy halving search would visit (and
    the rest of the window), so it finds at least the same damage in fewer
    passes. Further levels halve the step greedily (theta +- step around the
    current best). All points and their trial planes go through the kernel in
    one call (the points run in parallel).

    Parameters
    ----------
    loads_T : ndarray, shape (6, n_time)
        Loads as channels (:func:`loads_channels`).
    cs_rows, ct_rows : ndarray, shape (R, 6)
        Stress coefficients of the R points.
    start : Governing
        Coarse governing plane of each point, with its damages (from the
        coarse pass).
    beta, psi : ndarray, shape (R,)
        Its inclination and shear axis, deg (kept while theta is refined).
    step0 : float
        Coarse grid step, deg.
    n_refine : int
        Halvings of ``step0``.
    law : PlaneLaw

    Returns
    -------
    Governing
        The refined plane of each point.
    """
    best = Governing(*(np.asarray(a, dtype=float).copy() for a in start))
    beta = np.asarray(beta, dtype=float)
    psi = np.asarray(psi, dtype=float)
    if n_refine <= 0:
        return best
    n_dense = min(n_refine, DENSE_LEVELS)
    step = step0 / 2.0**n_dense
    k = np.arange(1, 2**n_dense)
    offsets = np.concatenate([-k[::-1], k]) * step
    # trial planes of every row, shared where rows coincide
    t_all = ((best.theta_deg[:, None] + offsets[None, :]) % 180.0)
    keys = np.stack([np.round(t_all, 9), np.broadcast_to(beta[:, None], t_all.shape),
                     np.broadcast_to(psi[:, None], t_all.shape)], axis=-1).reshape(-1, 3)
    uniq, inv = np.unique(keys, axis=0, return_inverse=True)
    pl = make_planes(uniq[:, 0], uniq[:, 1], uniq[:, 2])
    d, s_, p_ = law.damage(loads_T, cs_rows, ct_rows, pl)
    best = _pick_rows(pl.theta_deg, d, s_, p_, inv.reshape(t_all.shape), best)
    rows = np.arange(best.theta_deg.shape[0])
    for _ in range(n_refine - n_dense):
        step /= 2.0
        th = best.theta_deg
        trial = (np.stack([th - step, th + step], axis=1) % 180.0).ravel()  # (2R,)
        pl = make_planes(trial, np.repeat(beta, 2), np.repeat(psi, 2))
        d, s_, p_ = law.damage(loads_T, cs_rows, ct_rows, pl)
        own = np.stack([2 * rows, 2 * rows + 1], axis=1)  # each point's own two trials
        best = _pick_rows(pl.theta_deg, d, s_, p_, own, best)
    return best


def uniaxial_point_damage(loads: np.ndarray, coef_sigma: np.ndarray, curve: SNCurve,
                          residue: str, mean_stress: str, ultimate_Pa: float,
                          thickness_factor: float = 1.0, walker_gamma: float = 0.5,
                          compressive_alpha: float = 0.6) -> np.ndarray:
    """Uniaxial route: rainflow of sigma_z at each point, mean-stress correction, Miner.

    Returns
    -------
    ndarray, shape (n_points,)
        Damage per point.
    """
    L = np.asarray(loads, dtype=np.float64)
    out = np.zeros(coef_sigma.shape[0])
    for p in range(coef_sigma.shape[0]):
        sig = L @ coef_sigma[p]  # one point at a time: memory O(n_time)
        i0, i1, cnt = find_cycles_indexed(sig, residue)
        if cnt.size == 0:
            continue
        a, b = sig[i0], sig[i1]
        S = correct_mean_stress(np.abs(b - a), 0.5 * (a + b), mean_stress, ultimate_Pa,
                                walker_gamma, compressive_alpha)
        N = curve.cycles_to_failure(S * thickness_factor)
        out[p] = float(np.sum(cnt / N))
    return out


@dataclass(frozen=True)
class PlaneSearch:
    """Where :func:`evaluate_location` looks for the critical plane.

    Attributes
    ----------
    n_points : int
        Surface points (>= 36 in production).
    plane_step_deg, family_b, n_shear_axes
        Coarse candidate grid (:func:`plane_grid`).
    n_refine, n_refine_points : int
        Halvings of ``plane_step_deg`` around the governing plane of the
        ``n_refine_points`` most damaged points (:func:`refine_planes`).
    """

    n_points: int = 36
    plane_step_deg: float = 10.0
    family_b: bool = False
    n_shear_axes: int = 2
    n_refine: int = 4
    n_refine_points: int = 2


@dataclass(frozen=True)
class DamageOptions:
    """Counting and S-N options of :func:`evaluate_location`.

    Attributes
    ----------
    residue : {'half', 'repeat', 'carry'}
        Residue closure ('carry' closes as half).
    mean_stress, ultimate_Pa, walker_gamma, compressive_alpha
        Mean-stress correction of the uniaxial route
        (:func:`drillfatigue.fatigue.sn.correct_mean_stress`).
    thickness_m : float, optional
        Wall thickness for the S-N thickness correction (default: the
        section's).
    """

    residue: str = "half"
    mean_stress: str = "none"
    ultimate_Pa: float = 689e6
    thickness_m: float | None = None
    walker_gamma: float = 0.5
    compressive_alpha: float = 0.6


def evaluate_location(loads: np.ndarray, section: Section, scf: SCF, curve: SNCurve,
                      criterion: str, params: CriterionParams, *,
                      search: PlaneSearch = PlaneSearch(),
                      options: DamageOptions = DamageOptions(), with_uniaxial: bool = True,
                      channels: np.ndarray | None = None,
                      pressure: Pressure | None = None) -> LocationResult:
    """Damage of one location of one joint over one load window.

    Parameters
    ----------
    loads : ndarray, shape (n_time, 6)
        Internal loads, N and N m (order of :data:`stress.LOAD_COLUMNS`).
    section, scf, curve
        Section, stress concentration factors, S-N curve of the location.
    criterion : {'matake', 'findley', 'fatemi_socie', 'uniaxial'}
    params : CriterionParams
    search : PlaneSearch
        Surface points, plane grid and refinement.
    options : DamageOptions
        Counting and uniaxial-route options.
    with_uniaxial : bool
        Also run the uniaxial route (``uniaxial_damage``; NaN when False).
    channels : ndarray, shape (6, n_time), optional
        ``loads_channels(loads)``, computed once and shared by the locations
        of a joint (saves one transposition of the history per location).
    pressure : Pressure, optional
        Mud pressure inside and outside, constant over the window. The axial
        load becomes the true wall force (``loads`` axial column is the
        effective tension), and the Lame hoop and radial stresses of the outer
        surface add a constant normal stress on every candidate plane
        (:mod:`drillfatigue.fatigue.stress`). None or zero pressure leaves
        every result bit for bit as without it.

    Returns
    -------
    LocationResult
    """
    _check_criterion(criterion)
    n_points = search.n_points
    cs, ct, phi = surface_coefficients(section, scf, n_points)
    hoop_radial = (0.0, 0.0)
    if pressure is not None and not pressure.is_zero:
        _, s_t, s_r = surface_pressure_stresses(section, scf, pressure, "outer")
        hoop_radial = (s_t, s_r)
        d_f = float(true_wall_force_N(0.0, section, pressure))
        loads = np.array(loads, dtype=np.float64)  # a copy: the caller's loads stay effective
        loads[:, 0] += d_f
        if channels is not None:
            channels = channels.copy()
            channels[0] += d_f
    o = options
    tf = curve.thickness_factor(o.thickness_m if o.thickness_m is not None
                                else (section.od_m - section.id_m) / 2.0)
    if with_uniaxial or criterion == "uniaxial":
        uni = uniaxial_point_damage(loads, cs, curve, o.residue, o.mean_stress, o.ultimate_Pa,
                                    tf, o.walker_gamma, o.compressive_alpha)
    else:
        uni = np.full(n_points, np.nan)
    if criterion == "uniaxial":
        p = int(np.argmax(uni))
        return LocationResult(float(uni[p]), float(np.degrees(phi[p])), 0.0, 0.0, p, uni,
                              float(uni[p]), float("nan"))
    planes = plane_grid(search.plane_step_deg, search.family_b, search.n_shear_axes)
    LT = channels if channels is not None else loads_channels(loads)
    law = PlaneLaw(curve, criterion, params, o.residue, tf, hoop_radial)
    dmg, sel, par = law.damage(LT, cs, ct, planes)
    jbest = pick_planes(dmg, sel)
    rows = np.arange(dmg.shape[0])
    best = Governing(planes.theta_deg[jbest].copy(), dmg[rows, jbest].copy(),
                     sel[rows, jbest].copy(), par[rows, jbest].copy())
    if search.n_refine > 0:
        top = np.argsort(-best.select, kind="stable")[:max(1, search.n_refine_points)]
        jt = jbest[top]
        refined = refine_planes(LT, cs[top], ct[top], Governing(*(a[top] for a in best)),
                                planes.beta_deg[jt], planes.psi_deg[jt], search.plane_step_deg,
                                search.n_refine, law)
        for a, r in zip(best, refined, strict=True):
            a[top] = r
    theta, pdmg, psel, pmax = best
    # governing point: largest selection damage (= damage except for Matake)
    p = int(pick_planes(pdmg[None], psel[None])[0])
    return LocationResult(float(pdmg[p]), float(np.degrees(phi[p])), float(theta[p]),
                          float(planes.beta_deg[jbest[p]]), p, pdmg,
                          float(uni.max()), float(pmax[p]))
