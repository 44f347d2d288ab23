"""Soft-string torque and drag (Johancsik et al., SPE 11380, JPT 1984).

The string is a cable lying on the low or high side of the hole: no bending
stiffness, contact all along. Cells are integrated from the bit up; for a cell
of length dL between the upper station (tangent t_u) and the lower station
(tangent t_l), with the tension T at its lower end (positive = tension),
buoyed weight W = w dL and friction coefficients mu::

    N dL = | T (t_l - t_u) + W (z - (z . t) t) |          side force of the cell
    T_up = T + W (z . t) + s mu_drag N dL                   s = +1 pick-up, -1 slack-off, 0 rotating
    M_up = M + mu_torque N dL r                             rotating only

with z the downward vertical and t the mean cell tangent. This is Johancsik's
cell equation in vector form: for small cells ``t_l - t_u`` has the
components ``(dI, sin(I) dA)`` of his ``sqrt((T dA sin I)^2 + (T dI + W sin I)^2)``
(the vector form needs no azimuth, which is ill-defined in vertical hole).
The bit end starts at ``T = -WOB`` (compression) and ``M = TOB`` when
drilling, 0 otherwise. Axial friction is zero when rotating (the slip is
almost all circumferential, so the friction vector is circumferential).

Closed forms that the discrete equations reproduce (docs/validation.md):
straight inclined hole ``dT/dL = w cos I +- mu w sin I``, rotating torque
``mu w sin I r`` per length; weightless pipe round a bend of angle theta:
``T_up / T_low -> exp(+- mu theta)`` as the cell size shrinks (the product of
``(1 +- mu 2 sin(dtheta/2))`` per cell, so the relative error is about
``mu^2 theta^2 / (2 n_cell)``); vertical hole hook load = buoyed weight - WOB.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numba import njit

from drillfatigue.dynamics.core.status import NONFINITE, OK



@njit(cache=True)
def soft_string_march(tan, md, w, r, mu_drag_signed, mu_torque, t_bit, m_bit, out_t, out_m, out_n):
    """Integrate the soft-string equations from the bit (last station) to the top.

    Parameters
    ----------
    tan : ndarray, shape (n, 3)
        Unit tangents of the well path at the stations, ordered by increasing
        MD (station n-1 is the bit), world frame (z down).
    md : ndarray, shape (n,)
        Station measured depths, m, strictly increasing.
    w : ndarray, shape (n-1,)
        Buoyed weight per length of each cell, N/m.
    r : ndarray, shape (n-1,)
        Contact radius of each cell (torque arm), m.
    mu_drag_signed : float
        ``s * mu_drag``: +mu for pick-up, -mu for slack-off, 0 rotating.
    mu_torque : float
        Friction coefficient for torque; 0 when not rotating.
    t_bit, m_bit : float
        Axial force (N, tension positive; ``-WOB`` on bottom) and torque
        (N m; ``TOB``) at the bit.
    out_t, out_m : ndarray, shape (n,)
        Written: tension (N) and torque (N m) at each station.
    out_n : ndarray, shape (n-1,)
        Written: normal (side) force per length of each cell, N/m.

    Returns
    -------
    int
        ``status.OK`` or ``status.NONFINITE`` (a non-finite tension appeared).
    """
    n = md.shape[0]
    T = t_bit
    M = m_bit
    out_t[n - 1] = T
    out_m[n - 1] = M
    for k in range(n - 2, -1, -1):
        dl = md[k + 1] - md[k]
        W = w[k] * dl
        # mean tangent of the cell
        tx = tan[k, 0] + tan[k + 1, 0]
        ty = tan[k, 1] + tan[k + 1, 1]
        tz = tan[k, 2] + tan[k + 1, 2]
        tn = math.sqrt(tx * tx + ty * ty + tz * tz)
        tx /= tn
        ty /= tn
        tz /= tn
        # side force: T (t_lower - t_upper) + W (z - (z.t) t)
        fx = T * (tan[k + 1, 0] - tan[k, 0]) - W * tz * tx
        fy = T * (tan[k + 1, 1] - tan[k, 1]) - W * tz * ty
        fz = T * (tan[k + 1, 2] - tan[k, 2]) + W * (1.0 - tz * tz)
        Ncell = math.sqrt(fx * fx + fy * fy + fz * fz)
        T = T + W * tz + mu_drag_signed * Ncell
        M = M + mu_torque * Ncell * r[k]
        if not (math.isfinite(T) and math.isfinite(M)):
            return NONFINITE
        out_t[k] = T
        out_m[k] = M
        out_n[k] = Ncell / dl
    return OK


@dataclass(frozen=True)
class TorqueDrag:
    """Soft-string torque and drag along the string, SI, ordered by increasing MD.

    Station arrays have shape (n,) (index 0 at the top of the string, n-1 at
    the bit); cell arrays (``normal_*``) have shape (n-1,) and belong to
    ``md_mid_m``. Modes: ``pickup`` and ``slackoff`` (tripping, no rotation),
    ``rotating`` (off bottom), ``drilling`` (rotating on bottom with WOB, TOB).
    """

    md_m: np.ndarray
    md_mid_m: np.ndarray
    tension_pickup_N: np.ndarray
    tension_slackoff_N: np.ndarray
    tension_rotating_N: np.ndarray
    tension_drilling_N: np.ndarray
    torque_rotating_Nm: np.ndarray
    torque_drilling_Nm: np.ndarray
    normal_pickup_N_per_m: np.ndarray
    normal_slackoff_N_per_m: np.ndarray
    normal_rotating_N_per_m: np.ndarray
    normal_drilling_N_per_m: np.ndarray
    wob_N: float
    tob_Nm: float

    def summary(self) -> dict[str, float]:
        """Surface values: hook loads (N) and surface torques (N m), plus WOB/TOB."""
        return {
            "hookload_pickup_N": float(self.tension_pickup_N[0]),
            "hookload_slackoff_N": float(self.tension_slackoff_N[0]),
            "hookload_rotating_N": float(self.tension_rotating_N[0]),
            "hookload_drilling_N": float(self.tension_drilling_N[0]),
            "surface_torque_rotating_Nm": float(self.torque_rotating_Nm[0]),
            "surface_torque_drilling_Nm": float(self.torque_drilling_Nm[0]),
            "wob_N": float(self.wob_N),
            "tob_Nm": float(self.tob_Nm),
        }


def path_tangents(inc_rad: np.ndarray, azi_rad: np.ndarray) -> np.ndarray:
    """Unit tangents, shape (..., 3) (north, east, down), from inclination and azimuth (rad)."""
    s = np.sin(inc_rad)
    return np.stack([s * np.cos(azi_rad), s * np.sin(azi_rad), np.cos(inc_rad)], axis=-1)


def _check_arrays(md: np.ndarray, tan: np.ndarray, w: np.ndarray, r: np.ndarray) -> None:
    n = md.shape[0]
    if md.ndim != 1 or n < 2:
        raise ValueError(f"md_m must be 1-D with at least 2 stations, got shape {md.shape}")
    if not np.all(np.diff(md) > 0):
        raise ValueError("md_m must increase strictly")
    if tan.shape != (n, 3):
        raise ValueError(f"inc/azi must have the shape of md_m {md.shape}")
    if w.shape != (n - 1,) or r.shape != (n - 1,):
        raise ValueError(f"per-cell arrays must have shape ({n - 1},), got {w.shape}, {r.shape}")
    if not (np.all(np.isfinite(w)) and np.all(r >= 0) and np.all(np.isfinite(tan))):
        raise ValueError("weights, radii and angles must be finite, radii >= 0")


def soft_string_torque_drag(
    md_m: np.ndarray,
    inc_rad: np.ndarray,
    azi_rad: np.ndarray,
    w_N_per_m: np.ndarray,
    r_contact_m: np.ndarray,
    mu_torque: float,
    mu_drag: float,
    wob_N: float = 0.0,
    tob_Nm: float = 0.0,
) -> TorqueDrag:
    """Soft-string tension, torque and side force for the four standard modes.

    Parameters
    ----------
    md_m, inc_rad, azi_rad : ndarray, shape (n,)
        Stations along the string from its top (index 0) to the bit (n-1):
        MD (m), inclination and azimuth (rad). Use cells short compared with
        the radius of curvature (e.g. <= 10 m); see :func:`resample_path`.
    w_N_per_m : ndarray, shape (n-1,)
        Buoyed weight per length of each cell, N/m.
    r_contact_m : ndarray, shape (n-1,)
        Contact radius of each cell (torque arm, e.g. tool-joint OD / 2), m.
    mu_torque, mu_drag : float
        Friction coefficients for rotation and for axial motion.
    wob_N, tob_Nm : float
        Weight and torque on bit of the drilling mode (N, N m).

    Returns
    -------
    TorqueDrag

    Raises
    ------
    ValueError
        Inconsistent array shapes or values.
    RuntimeError
        The march produced a non-finite tension.

    References
    ----------
    Johancsik, Friesen & Dawson, Torque and drag in directional wells --
    prediction and measurement, JPT 36 (1984) 987-992 (SPE 11380).
    """
    md = np.ascontiguousarray(md_m, dtype=np.float64)
    tan = np.ascontiguousarray(path_tangents(np.asarray(inc_rad, float), np.asarray(azi_rad, float)))
    w = np.ascontiguousarray(w_N_per_m, dtype=np.float64)
    r = np.ascontiguousarray(r_contact_m, dtype=np.float64)
    _check_arrays(md, tan, w, r)
    n = md.shape[0]
    res: dict[str, np.ndarray] = {}
    modes = {
        "pickup": (mu_drag, 0.0, 0.0, 0.0),
        "slackoff": (-mu_drag, 0.0, 0.0, 0.0),
        "rotating": (0.0, mu_torque, 0.0, 0.0),
        "drilling": (0.0, mu_torque, -float(wob_N), float(tob_Nm)),
    }
    for name, (mud, mut, tb, mb) in modes.items():
        t = np.empty(n)
        m = np.empty(n)
        nn = np.empty(n - 1)
        status = soft_string_march(tan, md, w, r, mud, mut, tb, mb, t, m, nn)
        if status != OK:
            raise RuntimeError(f"soft-string {name}: non-finite tension in the march from the bit "
                               f"at MD {md[-1]:.1f} m upward (check weights and friction)")
        res[f"t_{name}"], res[f"m_{name}"], res[f"n_{name}"] = t, m, nn
    return TorqueDrag(
        md_m=md,
        md_mid_m=0.5 * (md[1:] + md[:-1]),
        tension_pickup_N=res["t_pickup"],
        tension_slackoff_N=res["t_slackoff"],
        tension_rotating_N=res["t_rotating"],
        tension_drilling_N=res["t_drilling"],
        torque_rotating_Nm=res["m_rotating"],
        torque_drilling_Nm=res["m_drilling"],
        normal_pickup_N_per_m=res["n_pickup"],
        normal_slackoff_N_per_m=res["n_slackoff"],
        normal_rotating_N_per_m=res["n_rotating"],
        normal_drilling_N_per_m=res["n_drilling"],
        wob_N=float(wob_N),
        tob_Nm=float(tob_Nm),
    )


def resample_path(
    survey_md_m: np.ndarray,
    survey_inc_rad: np.ndarray,
    survey_azi_rad: np.ndarray,
    md_m: np.ndarray,
) -> tuple[np.ndarray, np.ndarray]:
    """Inclination and azimuth at ``md_m`` on the minimum-curvature path of a survey.

    Between stations the tangent turns at a constant rate in the plane of the
    two station tangents (spherical linear interpolation), which is the
    minimum-curvature assumption. MDs outside the survey are clamped to its
    end tangents.

    Returns
    -------
    inc_rad, azi_rad : ndarray, shape like ``md_m``
    """
    smd = np.asarray(survey_md_m, float)
    t = path_tangents(np.asarray(survey_inc_rad, float), np.asarray(survey_azi_rad, float))
    q = np.asarray(md_m, float)
    i = np.clip(np.searchsorted(smd, q, side="right") - 1, 0, smd.size - 2)
    f = np.clip((q - smd[i]) / (smd[i + 1] - smd[i]), 0.0, 1.0)
    t0, t1 = t[i], t[i + 1]
    beta = 2.0 * np.arctan2(np.linalg.norm(t1 - t0, axis=-1), np.linalg.norm(t1 + t0, axis=-1))
    sb = np.sin(beta)
    small = sb < 1e-12
    safe = np.where(small, 1.0, sb)
    a = np.where(small, 1.0 - f, np.sin((1.0 - f) * beta) / safe)
    b = np.where(small, f, np.sin(f * beta) / safe)
    tv = a[:, None] * t0 + b[:, None] * t1
    tv /= np.linalg.norm(tv, axis=-1, keepdims=True)
    inc = np.arccos(np.clip(tv[:, 2], -1.0, 1.0))
    azi = np.arctan2(tv[:, 1], tv[:, 0])
    return inc, azi
