"""Events of a run: wall contact statistics, whirl detection and classification, bit bounce.

Detection runs inside the force kernels, per step, into the per-segment
statistics ``cst`` (n, N_CST) of the state (columns ``CS_*`` of
:mod:`layout`): :func:`record_contact` (onset time and bit MD, largest normal
force, impulse, time in contact) and :func:`track_whirl` (orbit and spin
angles of the segment centre about the hole axis, after the event window
opens at ``bp[B_TWIN]``); :func:`count_bounce` counts the bit lifting off
bottom (``sc[C_BOUNCE]``, ``sc[C_OFFB]``). Classification and the summary
figures run once, in Python, at the end of a run: :func:`classify_whirl`,
:func:`events_summary`, with the streaming channel statistics
:class:`RunningStats` kept by the run driver.

Whirl classes (docs/model.md#case-studies; a pipe of radius r rolling without slip
round a hole of radius R orbits against its spin at r / (R - r) of the spin
rate: backward whirl): see :func:`classify_whirl`. Stick-slip severity is
(max - min) / mean bit rpm over the window.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from numba import njit

from drillfatigue.dynamics.core.layout import (
    B_TWIN, C_BOUNCE, C_NACT, C_OFFB, CS_D, CS_FMAX, CS_IMP, CS_N, CS_ONMD, CS_ONT, CS_ORB, CS_ORBABS,
    CS_SPIN, CS_TCON, CS_TH, CS_THOK, S_H, W_RAD,
)

#: Event figures copied to the top level of summary.json (read by the sweep's dataset).
EVENT_KEYS = ("stick_slip_severity", "whirl_class", "bit_bounce_count", "max_contact_force_N",
              "rms_surface_torque_Nm", "peak_surface_torque_Nm")


@njit(cache=True, inline="always")
def record_contact(i, t, md_bit, nsum, dmax, dt, cst):
    """Contact statistics of segment ``i`` this step; returns whether it touches the wall.

    ``nsum``: the normal force (N) summed over its contact points; ``dmax``:
    the largest distance (m) of a contact point from the hole centre line.
    Writes ``cst[i, CS_N], cst[i, CS_D]``; in contact also the onset (time s
    and bit MD m, once), the largest force, the impulse (N s) and the time in
    contact (s).
    """
    cst[i, CS_N] = nsum
    cst[i, CS_D] = dmax
    if nsum > 0.0:
        if cst[i, CS_ONT] < 0.0:
            cst[i, CS_ONT] = t
            cst[i, CS_ONMD] = md_bit
        if nsum > cst[i, CS_FMAX]:
            cst[i, CS_FMAX] = nsum
        cst[i, CS_IMP] += nsum * dt
        cst[i, CS_TCON] += dt
        return True
    return False


@njit(cache=True, inline="always")
def track_whirl(i, xc, wW, r_contact, wall, ic, dt, cst, dirn):
    """Orbit and spin angles of segment ``i`` about the axis of hole cylinder ``ic``.

    The centre ``xc`` (3,) is projected on the plane normal to the cylinder's
    axis (no search: the cylinder its first contact point was last found in);
    the spin ``wW . a`` (rad/s) is integrated over ``dt`` into
    ``cst[i, CS_SPIN]``. While the centre is off the axis by more than a
    quarter of the clearance ``radius - r_contact``, the angle of the offset
    about the axis (from a reference normal: world z, or x in a vertical hole)
    is tracked, its wrapped increments summed into ``cst[i, CS_ORB]`` and their
    magnitudes into ``cst[i, CS_ORBABS]``. ``dirn`` (4,) is scratch: the unit
    offset and its length (kept from the last segment where the length is 0).
    """
    a0 = wall[ic, 3]
    a1 = wall[ic, 4]
    a2 = wall[ic, 5]
    r0 = xc[0] - wall[ic, 0]
    r1 = xc[1] - wall[ic, 1]
    r2 = xc[2] - wall[ic, 2]
    sa = r0 * a0 + r1 * a1 + r2 * a2
    r0 -= sa * a0
    r1 -= sa * a1
    r2 -= sa * a2
    dirn[3] = math.sqrt(r0 * r0 + r1 * r1 + r2 * r2)
    if dirn[3] > 0.0:
        dirn[0] = r0 / dirn[3]
        dirn[1] = r1 / dirn[3]
        dirn[2] = r2 / dirn[3]
    spin = wW[0] * a0 + wW[1] * a1 + wW[2] * a2
    cst[i, CS_SPIN] += spin * dt
    clr = wall[ic, W_RAD] - r_contact
    if dirn[3] > 0.25 * clr:
        if abs(a2) < 0.9:
            u0 = -a2 * a0
            u1 = -a2 * a1
            u2 = 1.0 - a2 * a2
        else:
            u0 = 1.0 - a0 * a0
            u1 = -a0 * a1
            u2 = -a0 * a2
        un = math.sqrt(u0 * u0 + u1 * u1 + u2 * u2)
        u0 /= un
        u1 /= un
        u2 /= un
        w0 = a1 * u2 - a2 * u1
        w1 = a2 * u0 - a0 * u2
        w2 = a0 * u1 - a1 * u0
        th = math.atan2(dirn[0] * w0 + dirn[1] * w1 + dirn[2] * w2,
                        dirn[0] * u0 + dirn[1] * u1 + dirn[2] * u2)
        if cst[i, CS_THOK] == 1.0:
            dth = th - cst[i, CS_TH]
            if dth > math.pi:
                dth -= 2.0 * math.pi
            elif dth < -math.pi:
                dth += 2.0 * math.pi
            cst[i, CS_ORB] += dth
            cst[i, CS_ORBABS] += abs(dth)
        cst[i, CS_TH] = th
        cst[i, CS_THOK] = 1.0
    else:
        cst[i, CS_THOK] = 0.0


@njit(cache=True)
def count_bounce(wob, s_ax, sc):
    """Bit bounce: count the bit leaving the rock (WOB reaching 0) once per lift-off.

    Re-armed once the bit is back on bottom by more than a micron
    (``s_ax`` > 1e-6 m, the bit face's penetration into the rock target).
    """
    if wob <= 0.0:
        if sc[C_OFFB] == 0.0:
            sc[C_BOUNCE] += 1.0
            sc[C_OFFB] = 1.0
    elif s_ax > 1e-6:
        sc[C_OFFB] = 0.0


def classify_whirl(orbit_rad: float, orbit_abs_rad: float, spin_rad: float) -> str:
    """Whirl class of one segment from its orbit and spin angles over the window.

    ``none``: the centre orbits less than one turn in total (|orbit| and the
    summed |d orbit| both < 2 pi); ``chaotic``: the orbit reverses so much that
    the net angle is less than half the summed |d angle|; otherwise ``forward``
    when the orbit turns the same way as the spin, ``backward`` when opposite.
    """
    if orbit_abs_rad < 2.0 * math.pi:
        return "none"
    if abs(orbit_rad) < 0.5 * orbit_abs_rad:
        return "chaotic"
    if spin_rad == 0.0:
        return "chaotic"
    return "forward" if orbit_rad * spin_rad > 0.0 else "backward"


class RunningStats:
    """Streaming mean / min / max of named channels, resumable from a checkpoint."""

    def __init__(self) -> None:
        self.n = 0
        self.s: dict[str, float] = {}
        self.lo: dict[str, float] = {}
        self.hi: dict[str, float] = {}

    def add(self, name: str, x: np.ndarray) -> None:
        """Fold the samples ``x`` of channel ``name`` in (count ``n`` is kept by the caller)."""
        if x.size == 0:
            return
        self.s[name] = self.s.get(name, 0.0) + float(x.sum())
        self.lo[name] = min(self.lo.get(name, math.inf), float(x.min()))
        self.hi[name] = max(self.hi.get(name, -math.inf), float(x.max()))

    def as_dict(self, n: int) -> dict[str, dict[str, float]]:
        return {k: {"mean": self.s[k] / max(n, 1), "min": self.lo[k], "max": self.hi[k]}
                for k in self.s}

    def state(self) -> dict[str, Any]:
        return {"n": self.n, "s": self.s, "lo": self.lo, "hi": self.hi}

    def load(self, d: dict[str, Any]) -> None:
        self.n, self.s, self.lo, self.hi = d["n"], d["s"], d["lo"], d["hi"]


def events_summary(seg: np.ndarray, bp: np.ndarray, sc: np.ndarray, cst: np.ndarray,
                   wstats: RunningStats) -> dict[str, Any]:
    """Events of a run for summary.json from the final state (active rows of ``cst``),
    the segment parameters, and the window statistics ``wstats`` (``bit_rpm``,
    ``surface_torque_Nm`` and its square)."""
    n = int(sc[C_NACT])
    cst = cst[:n]
    h = seg[:n, S_H]
    s_mid = np.cumsum(np.r_[0.0, 2.0 * h[:-1]]) + h
    per_seg = [classify_whirl(float(c[CS_ORB]), float(c[CS_ORBABS]), float(c[CS_SPIN]))
               for c in cst]
    whirling = [c for c in per_seg if c != "none"]
    if whirling:
        vals, counts = np.unique(whirling, return_counts=True)
        dominant = str(vals[int(np.argmax(counts))])
    else:
        dominant = "none"
    onset = [{"segment": i, "time_s": float(c[CS_ONT]), "bit_md_m": float(c[CS_ONMD]),
              "md_m": float(c[CS_ONMD] - s_mid[i])}
             for i, c in enumerate(cst) if c[CS_ONT] >= 0.0]
    ws = wstats.as_dict(wstats.n)
    sev = None
    rms = None
    peak = None
    if "bit_rpm" in ws:
        b = ws["bit_rpm"]
        sev = (b["max"] - b["min"]) / b["mean"] if abs(b["mean"]) > 1e-9 else None
        t = ws["surface_torque_Nm"]
        rms = math.sqrt(max(ws["surface_torque_Nm_sq"]["mean"], 0.0))
        peak = max(abs(t["max"]), abs(t["min"]))
    return {
        "window_start_s": float(bp[B_TWIN]),
        "stick_slip_severity": sev,
        "whirl_class": dominant,
        "whirl_per_segment": per_seg,
        "orbit_angle_rad": [float(c[CS_ORB]) for c in cst],
        "spin_angle_rad": [float(c[CS_SPIN]) for c in cst],
        "bit_bounce_count": int(sc[C_BOUNCE]),
        "max_contact_force_N": float(cst[:, CS_FMAX].max()) if n else 0.0,
        "max_contact_force_per_segment_N": [float(c[CS_FMAX]) for c in cst],
        "contact_time_s_per_segment": [float(c[CS_TCON]) for c in cst],
        "rms_surface_torque_Nm": rms,
        "peak_surface_torque_Nm": peak,
        "contact_onset": onset,
        "segments_in_contact_ever": len(onset),
    }
