"""Buckling detected in a simulated run: windows along the string by the lateral offsets.

Detection in a simulated string: :func:`detect_buckling` works on the lateral
offsets of the segment centres from the hole axis (from a run's kinematics)
and classifies windows along the string as ``none``, ``sinusoidal`` (the pipe
snakes across the low side: the lateral swing changes sign along the string)
or ``helical`` (the angle of the offset round the axis turns through a full
turn inside the window while the pipe stays on the wall), with the wall
contact points per length.
"""


from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from drillfatigue.dynamics.core import layout as L
from drillfatigue.well.kernels import path_point

if TYPE_CHECKING:
    from drillfatigue.well.wellbore import Wellbore

#: Window states, by code.
STATE_NAMES = ("none", "sinusoidal", "helical")


@dataclass(frozen=True)
class BucklingDetection:
    """Buckling pattern of a simulated string at one instant, per window along it.

    Window arrays, shape (n_window,): ``s_start_m``, ``s_end_m`` (distance from
    the bit), ``state`` (0 none, 1 sinusoidal, 2 helical), ``max_swing``
    (largest sideways offset, fraction of the clearance), ``turn_rad`` (net
    turn of the offset round the hole axis), ``contacts_per_m`` (segments in
    wall contact per metre), ``wavelength_m`` (sinusoidal: twice the mean
    distance between sign changes of the swing; helical: pitch from the turn;
    NaN otherwise).
    """

    s_start_m: np.ndarray
    s_end_m: np.ndarray
    state: np.ndarray
    max_swing: np.ndarray
    turn_rad: np.ndarray
    contacts_per_m: np.ndarray
    wavelength_m: np.ndarray

    def state_names(self) -> list[str]:
        """Window states as words (:data:`STATE_NAMES`)."""
        return [STATE_NAMES[int(k)] for k in self.state]


def lateral_offsets(pos_m: np.ndarray, centre_m: np.ndarray, tangent: np.ndarray,
                    clearance_m: float | np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Offset of segment centres from the hole axis: size (fraction of clearance) and angle.

    Parameters
    ----------
    pos_m, centre_m : ndarray, shape (n, 3)
        Segment centres and the hole axis points at their MDs, world frame (z down), m.
    tangent : ndarray, shape (n, 3)
        Unit hole-axis tangents there.
    clearance_m : float or ndarray, shape (n,)
        Radial clearance of each segment, m.

    Returns
    -------
    rho : ndarray, shape (n,)
        |offset| / clearance (1 = on the wall).
    theta_rad : ndarray, shape (n,)
        Angle of the offset round the axis from the low side (positive towards
        ``t x low``); in (near-)vertical hole (sin I < 0.02) measured from the
        north direction projected on the cross-section.
    """
    p = np.asarray(pos_m, float)
    c = np.asarray(centre_m, float)
    t = np.asarray(tangent, float)
    e = p - c
    e -= np.sum(e * t, axis=1, keepdims=True) * t
    z = np.array([0.0, 0.0, 1.0])
    low = z[None, :] - t[:, 2:3] * t
    nl = np.linalg.norm(low, axis=1)
    north = np.array([1.0, 0.0, 0.0])[None, :] - t[:, 0:1] * t
    ref = np.where((nl > 0.02)[:, None], low, north)
    ref /= np.linalg.norm(ref, axis=1, keepdims=True)
    side = np.cross(t, ref)
    theta = np.arctan2(np.sum(e * side, axis=1), np.sum(e * ref, axis=1))
    rho = np.linalg.norm(e, axis=1) / clearance_m
    return rho, theta


def detect_buckling(
    s_m: np.ndarray,
    rho: np.ndarray,
    theta_rad: np.ndarray,
    in_contact: np.ndarray,
    window_m: float,
    swing_threshold: float = 0.3,
    wall_fraction: float = 0.7,
) -> BucklingDetection:
    """Classify the lateral displacement pattern of a string along windows.

    Parameters
    ----------
    s_m : ndarray, shape (n,)
        Distance of the segment centres from the bit, m, increasing.
    rho, theta_rad : ndarray, shape (n,)
        From :func:`lateral_offsets`.
    in_contact : ndarray of bool, shape (n,)
        Segment touches the wall (e.g. the kinematics' ``normal_N > 0``).
    window_m : float
        Window length along the string, m; choose about one buckle wavelength
        or helix pitch (e.g. :func:`helix_pitch_m` at the onset load).
    swing_threshold : float
        Smallest sideways swing ``rho |sin(theta - theta_mean)|`` that counts
        as a sinusoidal buckle (fraction of the clearance; a pipe resting on
        the low side has swing ~ 0).
    wall_fraction : float
        Helical: the mean ``rho`` in the window must reach this (the helix
        lies on the wall).

    Returns
    -------
    BucklingDetection

    Notes
    -----
    Rules per window: ``helical`` if the unwrapped angle turns by at least
    2 pi (one full turn round the axis) and the pipe lies on the wall;
    ``sinusoidal`` if the sideways swing about the mean angle changes sign
    at least twice and reaches ``swing_threshold``; ``none`` otherwise.
    """
    s = np.asarray(s_m, float)
    if s.ndim != 1 or s.size < 3 or not np.all(np.diff(s) > 0):
        raise ValueError("s_m must be 1-D, increasing, with at least 3 segments")
    if not window_m > 0:
        raise ValueError(f"window_m must be > 0, got {window_m}")
    rho = np.asarray(rho, float)
    th = np.unwrap(np.asarray(theta_rad, float))
    con = np.asarray(in_contact, bool)
    starts = np.arange(s[0], s[-1], window_m)
    rows = []
    for a in starts:
        b = a + window_m
        sel = (s >= a) & (s < b)
        if sel.sum() < 3:
            continue
        ss, rr, tt = s[sel], rho[sel], th[sel]
        turn = float(tt[-1] - tt[0])
        mean_ang = math.atan2(float(np.mean(np.sin(tt))), float(np.mean(np.cos(tt))))
        swing = rr * np.sin(tt - mean_ang)
        sign = np.sign(swing[np.abs(swing) > 0.05 * max(swing_threshold, 1e-12)])
        crossings = int(np.count_nonzero(sign[1:] != sign[:-1])) if sign.size > 1 else 0
        wave = math.nan
        if abs(turn) >= 2.0 * math.pi and float(rr.mean()) >= wall_fraction:
            state = 2
            wave = float(ss[-1] - ss[0]) * 2.0 * math.pi / abs(turn)
        elif crossings >= 2 and float(np.abs(swing).max()) >= swing_threshold:
            state = 1
            zc = ss[:-1][np.diff(np.sign(swing)) != 0]
            if zc.size >= 2:
                wave = 2.0 * float(np.mean(np.diff(zc)))
        else:
            state = 0
        length = float(ss[-1] - ss[0]) + float(np.mean(np.diff(ss)))
        rows.append((a, b, state, float(np.abs(swing).max()), turn,
                     float(con[sel].sum()) / length, wave))
    arr = np.array(rows, dtype=float).reshape(-1, 7)
    return BucklingDetection(s_start_m=arr[:, 0], s_end_m=arr[:, 1], state=arr[:, 2].astype(np.int8),
                             max_swing=arr[:, 3], turn_rad=arr[:, 4], contacts_per_m=arr[:, 5],
                             wavelength_m=arr[:, 6])


def detect_buckling_in_run(
    wellbore: Wellbore,
    bit_md_m: float,
    s_from_bit_m: np.ndarray,
    pos_m: np.ndarray,
    normal_N: np.ndarray,
    contact_radius_m: np.ndarray,
    window_m: float,
    **kwargs: float,
) -> BucklingDetection:
    """:func:`detect_buckling` on one time of a run's kinematics.

    Parameters
    ----------
    wellbore : Wellbore
        The hole (:func:`drillfatigue.well.build_wellbore`).
    bit_md_m : float
        Bit MD at that time (``channels.bit_md_m``), m.
    s_from_bit_m, pos_m, normal_N : ndarray, shapes (n,), (n, 3), (n,)
        The kinematics rows of that time: ``s_from_bit_m``, ``x_m, y_m, z_m``, ``normal_N``.
    contact_radius_m : ndarray, shape (n,)
        Contact radius of each segment, m.
    window_m : float
    **kwargs
        ``swing_threshold``, ``wall_fraction`` of :func:`detect_buckling`.
    """
    s = np.asarray(s_from_bit_m, float)
    order = np.argsort(s)
    md = bit_md_m - s[order]
    centre, tan = wellbore.point_at_md(md)
    clear = np.asarray(wellbore.hole_radius_at_md(md)) - np.asarray(contact_radius_m, float)[order]
    rho, theta = lateral_offsets(np.asarray(pos_m, float)[order], centre, tan, clear)
    return detect_buckling(s[order], rho, theta, np.nan_to_num(np.asarray(normal_N, float)[order]) > 0.0,
                           window_m, **kwargs)


# --- detections over a run, for summary.json ---------------------------------------------


def true_runs(mask: np.ndarray) -> list[tuple[int, int]]:
    """Index ranges [a, b] of the runs of consecutive True entries of ``mask``."""
    out: list[tuple[int, int]] = []
    k = 0
    while k < mask.size:
        if mask[k]:
            a = k
            while k + 1 < mask.size and mask[k + 1]:
                k += 1
            out.append((a, k))
        k += 1
    return out


def detection_window_m(ei_Nm2: np.ndarray, w_N_per_m: np.ndarray, clearance_m: np.ndarray,
                       segment_length_m: np.ndarray, max_inc_rad: float) -> float:
    """Window length of the run's buckling detector, m.

    Twice the median Dawson-Paslay buckle wavelength ``2 pi (EI r_c / (w sin I))^(1/4)`` of
    the segments, with ``I`` the hole's largest inclination (at least 10 deg, so that a
    vertical hole gets a finite window), and at least three of the longest segments (the
    detector needs three points per window).
    """
    sin_i = max(math.sin(max_inc_rad), math.sin(math.radians(10.0)))
    ok = (w_N_per_m > 0) & (clearance_m > 0)
    if not ok.any():
        return float(3.0 * segment_length_m.max())
    lam = 2.0 * math.pi * (ei_Nm2[ok] * clearance_m[ok] / (w_N_per_m[ok] * sin_i)) ** 0.25
    return float(max(2.0 * np.median(lam), 3.0 * segment_length_m.max()))


class BucklingTracker:
    """Buckling detections over a run, sample by sample of its kinematics, for summary.json.

    Every kinematics sample goes through :func:`detect_buckling` on fixed windows along the
    string (measured from the bit segment's centre). Per window the tracker keeps the worst
    state seen (helical over sinusoidal), the first time a buckle was seen there, the
    largest sideways swing (fraction of the clearance and metres), the most wall contacts
    per metre and the wavelength or pitch at the worst state. :meth:`summary` merges
    neighbouring buckled windows into sections.

    Parameters
    ----------
    node_md_m, node_pos_m, node_tan : ndarray
        The well path of the simulator (``WellPath``).
    wall : ndarray, shape (c, N_WALL)
        Its hole cylinders, in MD order from ``node_md_m[0]``.
    window_m : float
        See :func:`detection_window_m`.
    """

    def __init__(self, node_md_m: np.ndarray, node_pos_m: np.ndarray, node_tan: np.ndarray,
                 wall: np.ndarray, window_m: float) -> None:
        self.node_md = np.ascontiguousarray(node_md_m, dtype=np.float64)
        self.node_pos = np.ascontiguousarray(node_pos_m, dtype=np.float64)
        self.node_tan = np.ascontiguousarray(node_tan, dtype=np.float64)
        lengths = wall[:, L.W_LEN]
        self.cyl_top = float(self.node_md[0]) + np.concatenate([[0.0], np.cumsum(lengths)[:-1]])
        self.cyl_r = wall[:, L.W_RAD].copy()
        self.window_m = float(window_m)
        self.samples = 0
        self.win: dict[int, dict[str, float]] = {}

    def _axis(self, md: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        pos = np.empty((md.size, 3))
        tan = np.empty((md.size, 3))
        p, t = np.zeros(3), np.zeros(3)
        hint = 0
        for k in range(md.size):
            hint = path_point(float(md[k]), self.node_md, self.node_pos, self.node_tan, hint, p, t)
            pos[k] = p
            tan[k] = t
        c = np.clip(np.searchsorted(self.cyl_top, md, side="right") - 1, 0, self.cyl_r.size - 1)
        return pos, tan, self.cyl_r[c]

    def add(self, t_s: float, bit_md_m: float, s_from_bit_m: np.ndarray, pos_m: np.ndarray,
            normal_N: np.ndarray, contact_radius_m: np.ndarray,
            joint_s_from_bit_m: np.ndarray) -> None:
        """One kinematics sample: segment centres (distance from the bit, position, wall force)."""
        order = np.argsort(s_from_bit_m)
        s = np.asarray(s_from_bit_m, float)[order]
        if s.size < 3:
            return
        centre, tan, r_hole = self._axis(bit_md_m - s)
        clear = r_hole - np.asarray(contact_radius_m, float)[order]
        if np.any(clear <= 0.0):
            return
        rho, theta = lateral_offsets(np.asarray(pos_m, float)[order], centre, tan, clear)
        det = detect_buckling(s, rho, theta, np.nan_to_num(np.asarray(normal_N, float)[order]) > 0.0,
                              self.window_m)
        self.samples += 1
        disp = rho * clear
        for k in range(det.state.size):
            key = int(round((det.s_start_m[k] - s[0]) / self.window_m))
            w = self.win.setdefault(key, {"s_start_m": float(det.s_start_m[k]),
                                          "s_end_m": float(det.s_end_m[k]), "state": 0.0,
                                          "onset_time_s": math.nan, "max_swing": 0.0,
                                          "max_offset_m": 0.0, "max_contacts_per_m": 0.0,
                                          "wavelength_m": math.nan})
            st = int(det.state[k])
            if st > 0 and math.isnan(w["onset_time_s"]):
                w["onset_time_s"] = float(t_s)
            if st > w["state"]:
                w["state"] = float(st)
                w["wavelength_m"] = float(det.wavelength_m[k])
            sel = (s >= det.s_start_m[k]) & (s < det.s_end_m[k])
            w["max_swing"] = max(w["max_swing"], float(det.max_swing[k]))
            w["max_offset_m"] = max(w["max_offset_m"], float(disp[sel].max()))
            w["max_contacts_per_m"] = max(w["max_contacts_per_m"], float(det.contacts_per_m[k]))
            js = np.nonzero((joint_s_from_bit_m >= det.s_start_m[k])
                            & (joint_s_from_bit_m < det.s_end_m[k]))[0]
            if js.size:
                w["joint_first"], w["joint_last"] = float(js[0]), float(js[-1])

    def summary(self) -> dict[str, Any]:
        """Sections of neighbouring buckled windows, with the lengths buckled per mode.

        Keys: ``window_m``, ``samples``, ``buckled_sinusoidal_m`` and ``buckled_helical_m``
        (length of the windows whose worst state was that mode, the names of ``drillfatigue
        tnd``'s margins), ``sections`` (list, from the bit up: ``s_from_bit_start_m``,
        ``s_from_bit_end_m``, ``joints`` [first, last] or None, ``mode`` (the worst state in
        the section), ``onset_time_s`` (first detection), ``max_swing_of_clearance``,
        ``max_lateral_offset_m`` (largest offset of a segment centre from the hole axis),
        ``max_contacts_per_m``, ``wavelength_m`` (sinusoidal wavelength or helix pitch at the
        worst state, None when not measured)).
        """
        keys = sorted(self.win)
        rows = [self.win[k] for k in keys]
        state = np.array([r["state"] for r in rows], dtype=int)
        lengths = np.array([r["s_end_m"] - r["s_start_m"] for r in rows])
        out: dict[str, Any] = {"window_m": self.window_m, "samples": self.samples,
                               "buckled_sinusoidal_m": float(lengths[state == 1].sum()),
                               "buckled_helical_m": float(lengths[state == 2].sum()),
                               "sections": []}
        for a, b in true_runs(state > 0):
            part = rows[a: b + 1]
            worst = max(part, key=lambda r: r["state"])
            firsts = [r["joint_first"] for r in part if "joint_first" in r]
            lasts = [r["joint_last"] for r in part if "joint_last" in r]
            wave = worst["wavelength_m"]
            out["sections"].append({
                "s_from_bit_start_m": part[0]["s_start_m"],
                "s_from_bit_end_m": part[-1]["s_end_m"],
                "joints": [int(min(firsts)), int(max(lasts))] if firsts else None,
                "mode": STATE_NAMES[int(worst["state"])],
                "onset_time_s": float(np.nanmin([r["onset_time_s"] for r in part])),
                "max_swing_of_clearance": max(r["max_swing"] for r in part),
                "max_lateral_offset_m": max(r["max_offset_m"] for r in part),
                "max_contacts_per_m": max(r["max_contacts_per_m"] for r in part),
                "wavelength_m": None if math.isnan(wave) else wave,
            })
        return out

    def state(self) -> dict[str, Any]:
        """JSON-able state for a checkpoint."""
        return {"samples": self.samples,
                "win": {str(k): {n: (None if isinstance(v, float) and math.isnan(v) else v)
                                 for n, v in w.items()} for k, w in self.win.items()}}

    def load(self, d: dict[str, Any]) -> None:
        """Restore :meth:`state`."""
        self.samples = int(d["samples"])
        self.win = {int(k): {n: (math.nan if v is None else float(v)) for n, v in w.items()}
                    for k, w in d["win"].items()}
