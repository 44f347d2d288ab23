"""Industry baseline: API RP7G / Lubinski bending in doglegs, Hansford-Lubinski damage.

All inputs are plain SI numbers or arrays (Pa, m, N, rad/m, rpm, m/s), so the
same well, string and operating point as the dynamic model can be passed in.

* Bending stress at a tool joint of pipe rotating in a dogleg under tension T
  (Lubinski 1961; API RP7G (16th ed., 1998) section A.8):
  sigma_b = (E D kappa / 2) K L / tanh(K L), K = sqrt(T/(E I)), L half the
  distance between tool joints; as T -> 0 it tends to E D kappa / 2.
* Allowable (endurance) bending stress versus buoyant tension stress
  sigma_t = T/A (RP7G Fig. A-6/A-7 lines, psi):
  Grade E:  19,500 - (10/67) sigma_t - (0.6/670^2)(sigma_t - 33,500)^2, sigma_t <= 67,000;
  S-135:    20,000 (1 - sigma_t/145,000), sigma_t <= 133,400.
* Maximum permissible dogleg: the curvature at which sigma_b equals the line.
* Hansford-Lubinski cumulative damage (Hansford & Lubinski, JPT 1966): every
  revolution in the dogleg is one fully reversed cycle of amplitude sigma_b; a
  joint crossing a dogleg of length L_dl at rotary speed rpm and rate of
  penetration ROP turns (rpm/60) L_dl / ROP times.

References
----------
Lubinski, A., Maximum permissible dog-legs in rotary boreholes, JPT 13 (1961)
175-194; Hansford, J. E., Lubinski, A., Cumulative fatigue damage of drill pipe
in dog-legs, JPT 18 (1966) 359-363; API RP7G 16th ed. (1998), Appendix A.
"""

from __future__ import annotations

import numpy as np

from drillfatigue.errors import InputError
from drillfatigue.fatigue.sn import SNCurve, correct_mean_stress
from drillfatigue.fatigue.stress import Section
from drillfatigue.units import PSI_PA

#: Young's modulus used by API RP7G for steel (30e6 psi), Pa.
E_RP7G_PA = 30.0e6 * PSI_PA
#: Half the tool-joint spacing of 30 ft joints, L = 180 in, m.
HALF_JOINT_SPACING_M = 4.572
RP7G_GRADES: tuple[str, ...] = ("E-75", "S-135")


def _kl_factor(KL: np.ndarray) -> np.ndarray:
    """KL / tanh(KL), with its series 1 + KL^2/3 near zero."""
    KL = np.asarray(KL, dtype=np.float64)
    small = KL < 1e-4
    out = np.empty_like(KL)
    out[small] = 1.0 + KL[small] ** 2 / 3.0
    big = ~small
    out[big] = KL[big] / np.tanh(KL[big])
    return out


def lubinski_bending_stress_Pa(E: float, D: float, curvature_rad_per_m: np.ndarray | float,
                               tension_N: np.ndarray | float, I: float,
                               half_joint_spacing_m: float) -> np.ndarray | float:
    """Lubinski tool-joint bending stress of pipe rotating in a dogleg.

    Parameters
    ----------
    E : float
        Young's modulus, Pa.
    D : float
        Pipe body outer diameter, m.
    curvature_rad_per_m : float or ndarray
        Hole curvature kappa, rad/m.
    tension_N : float or ndarray
        Buoyant tension at the dogleg, N (>= 0; compression is outside the
        method and raises).
    I : float
        Pipe body second moment of area, m^4.
    half_joint_spacing_m : float
        L, half the distance between tool joints, m (180 in for 30 ft joints).

    Returns
    -------
    float or ndarray
        sigma_b, Pa.
    """
    T = np.asarray(tension_N, dtype=np.float64)
    kap = np.asarray(curvature_rad_per_m, dtype=np.float64)
    if np.any(T < 0.0) or not np.all(np.isfinite(T)):
        raise InputError("tension_N", "must be finite and >= 0 (Lubinski's formula is for "
                         "pipe in tension)", ">= 0")
    if E <= 0 or D <= 0 or I <= 0 or half_joint_spacing_m <= 0:
        raise InputError("E, D, I, half_joint_spacing_m", "must all be > 0", "> 0")
    KL = np.sqrt(T / (E * I)) * half_joint_spacing_m
    out = E * D * np.abs(kap) / 2.0 * _kl_factor(np.atleast_1d(KL)).reshape(KL.shape)
    return float(out) if out.ndim == 0 else out


def endurance_bending_stress_Pa(grade: str, tension_stress_Pa: np.ndarray | float
                                ) -> np.ndarray | float:
    """API RP7G allowable bending stress versus tension stress (Grade E or S-135).

    Beyond the end of a line (sigma_t > 67,000 psi for E, 133,400 psi for S-135)
    the allowable is 0.

    Returns
    -------
    float or ndarray
        Allowable bending stress, Pa.
    """
    st = np.asarray(tension_stress_Pa, dtype=np.float64) / PSI_PA
    if grade == "E-75":
        sb = 19_500.0 - (10.0 / 67.0) * st - (0.6 / 670.0**2) * (st - 33_500.0) ** 2
        sb = np.where(st <= 67_000.0, sb, 0.0)
    elif grade == "S-135":
        sb = np.where(st <= 133_400.0, 20_000.0 * (1.0 - st / 145_000.0), 0.0)
    else:
        raise InputError("grade", f"API RP7G gives endurance lines only for {grade!r} in "
                         "E-75 and S-135", ", ".join(RP7G_GRADES))
    sb = np.maximum(sb, 0.0) * PSI_PA
    return float(sb) if sb.ndim == 0 else sb


def max_permissible_dogleg(grade: str, tension_N: float, D: float, I: float, A: float,
                           half_joint_spacing_m: float, E: float = E_RP7G_PA) -> float:
    """Maximum permissible hole curvature (rad/m) for rotating pipe in tension.

    Solves sigma_b(kappa) = allowable(sigma_t = T/A); sigma_b is linear in kappa.
    Multiply by ``180/pi * 30`` for deg/30 m (see ``units``).
    """
    allow = endurance_bending_stress_Pa(grade, tension_N / A)
    per_kappa = lubinski_bending_stress_Pa(E, D, 1.0, tension_N, I, half_joint_spacing_m)
    return float(allow / per_kappa)


def _inverse_life(sigma_b_Pa: np.ndarray, curve: SNCurve, mean_Pa: np.ndarray | float,
                  ultimate_Pa: float | None, scf: float) -> np.ndarray:
    S = 2.0 * scf * np.atleast_1d(np.asarray(sigma_b_Pa, dtype=np.float64))
    Sm = np.broadcast_to(np.asarray(mean_Pa, dtype=np.float64), S.shape)
    if ultimate_Pa is not None:
        S = correct_mean_stress(S, Sm, "goodman", ultimate_Pa)
    return 1.0 / curve.cycles_to_failure(S)


def hansford_lubinski_damage(rpm: float, rop_m_per_s: float, dogleg_length_m: float,
                             sigma_b_Pa: float, curve: SNCurve, mean_Pa: float = 0.0,
                             ultimate_Pa: float | None = None, scf: float = 1.0) -> float:
    """Miner damage of one joint crossing a dogleg (Hansford-Lubinski).

    Revolutions n = (rpm/60) L_dl / ROP; each is one fully reversed cycle of
    stress range 2 scf sigma_b (Goodman on ``mean_Pa`` when ``ultimate_Pa`` is
    given); damage = n / N.
    """
    if rpm < 0 or rop_m_per_s <= 0 or dogleg_length_m < 0:
        raise InputError("rpm, rop_m_per_s, dogleg_length_m",
                         "need rpm >= 0, ROP > 0 and length >= 0", "rpm >= 0, ROP > 0")
    n = rpm / 60.0 * dogleg_length_m / rop_m_per_s
    return float(n * _inverse_life(np.array([sigma_b_Pa]), curve, mean_Pa, ultimate_Pa, scf)[0])


def rp7g_damage_rate_profile(md_m: np.ndarray, curvature_rad_per_m: np.ndarray,
                             tension_N: np.ndarray, rpm: float, rop_m_per_s: float, od_m: float,
                             id_m: float, curve: SNCurve, *, E: float = 207e9,
                             half_joint_spacing_m: float = HALF_JOINT_SPACING_M,
                             scf: float = 1.0,
                             ultimate_Pa: float | None = None) -> dict[str, np.ndarray]:
    """RP7G/Lubinski baseline along the hole, for the side-by-side report column.

    Parameters
    ----------
    md_m, curvature_rad_per_m, tension_N : ndarray, shape (n,)
        Measured depth, hole curvature and buoyant tension (compression is
        clipped to 0: the baseline's plain-beam limit) at each position.
    rpm, rop_m_per_s : float
        Operating point.
    od_m, id_m : float
        Pipe body diameters.
    curve : SNCurve
    E, half_joint_spacing_m, scf, ultimate_Pa
        Modulus, L (default 180 in), SCF on the bending stress, Goodman.

    Returns
    -------
    dict of ndarray, shape (n,)
        ``sigma_b_Pa``; ``damage_rate_per_h`` of a joint sitting at that depth
        while rotating (rpm 60 cycles per hour); ``damage_per_m`` of a joint
        travelling through that depth at ROP (Hansford-Lubinski);
        ``cumulative_damage`` integrated from the first position (trapezoid).
    """
    md = np.asarray(md_m, dtype=np.float64)
    kap = np.asarray(curvature_rad_per_m, dtype=np.float64)
    T = np.clip(np.asarray(tension_N, dtype=np.float64), 0.0, None)
    if not (md.shape == kap.shape == T.shape) or md.ndim != 1:
        raise InputError("md_m, curvature_rad_per_m, tension_N", "must be 1-D of equal length",
                         "arrays of shape (n,)")
    if rpm < 0 or rop_m_per_s <= 0:
        raise InputError("rpm, rop_m_per_s", "need rpm >= 0 and ROP > 0", "rpm >= 0, ROP > 0")
    sec = Section(od_m, id_m)
    A = sec.area_m2
    I = sec.inertia_m4
    sb = np.atleast_1d(lubinski_bending_stress_Pa(E, od_m, kap, T, I, half_joint_spacing_m))
    inv_n = _inverse_life(sb, curve, T / A, ultimate_Pa, scf)
    rate_h = rpm * 60.0 * inv_n
    per_m = rpm / 60.0 / rop_m_per_s * inv_n
    cum = np.concatenate([[0.0], np.cumsum(0.5 * (per_m[1:] + per_m[:-1]) * np.diff(md))])
    return {"md_m": md, "sigma_b_Pa": sb, "damage_rate_per_h": rate_h, "damage_per_m": per_m,
            "cumulative_damage": cum}
