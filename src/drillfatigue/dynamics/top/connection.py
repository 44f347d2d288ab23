"""Connection event sequence: what the rig does when the block reaches the floor.

A connection adds a stand to the string. The sequence (docs/rig.md),
each phase with its duration:

``PH_PICKUP``
    the block lifts the bit off bottom by ``pickup_m`` (still rotating);
``PH_STOP``
    rotation ramps down to 0 (top-drive set-point ramp);
``PH_SLIPS``
    slips set: the string hangs in the rotary table, the block is unloaded;
``PH_STAND``
    the stand is made up; the block goes back up by a stand length. With the
    slips set this moves nothing in the string: the string below the rotary
    grows by the stand while the block travel shrinks by it, so the
    extensible top segment keeps its length;
``PH_SLIPS_OUT``
    the block takes the weight, slips pulled;
``PH_RAMP``
    rotation restarts and ramps back to the set speed;
``PH_TAG``
    the block lowers the bit back to bottom by ``pickup_m``;
then ``PH_DRILL`` (the block mode of the operation) resumes.

:func:`connection_schedule` builds the phase table from a start time and the
durations; :func:`connection_controls` (numba) turns it into what the
boundaries room needs at a time ``t``: the phase, the factor on the rpm
set-point, the block velocity command, whether the slips carry the string,
and the block travel correction at the end of ``PH_STAND``.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
from numba import njit

if TYPE_CHECKING:
    from drillfatigue.config.rig import ConnectionConfig

PH_DRILL = 0
PH_PICKUP = 1
PH_STOP = 2
PH_SLIPS = 3
PH_STAND = 4
PH_SLIPS_OUT = 5
PH_RAMP = 6
PH_TAG = 7
PHASE_NAMES = ("drill", "pickup", "stop", "slips", "stand", "slips_out", "ramp", "tag")
#: Timed phases of a connection (pickup .. tag): their durations and start times are packed.
N_PHASES = PH_TAG

#: controls vector written by :func:`connection_controls`
CC_PHASE = 0  # phase code
CC_RPM_FACTOR = 1  # factor 0..1 on the rpm set-point
CC_BLOCK_V = 2  # block velocity command, m/s (> 0 lowering); NaN: the block mode decides
CC_SLIPS = 3  # 1: the slips carry the string (the block is unloaded)
CC_TRAVEL_SHIFT = 4  # block travel to remove once, at the end of PH_STAND, m (a stand length)
N_CC = 5


@dataclass(frozen=True)
class ConnectionSchedule:
    """Phase table of one connection.

    ``t_start_s`` (shape (8,)): start time of each phase ``PH_PICKUP`` ..
    ``PH_TAG`` and of the return to ``PH_DRILL`` (the last entry); ``params``
    (shape (3,)): ``[pickup_m, stand_length_m, 0]``, as the kernel takes them.
    """

    t_start_s: np.ndarray
    params: np.ndarray

    @property
    def duration_s(self) -> float:
        """Total duration, s."""
        return float(self.t_start_s[-1] - self.t_start_s[0])

    def phases(self) -> list[tuple[str, float, float]]:
        """``(name, start_s, end_s)`` of each phase."""
        t = self.t_start_s
        return [(PHASE_NAMES[k + 1], float(t[k]), float(t[k + 1])) for k in range(7)]


def connection_schedule(t0_s: float, cfg: ConnectionConfig) -> ConnectionSchedule:
    """Phase table of a connection starting at ``t0_s`` (when the block reached the floor)."""
    d = [cfg.pickup_s, cfg.rotation_stop_s, cfg.slips_s, cfg.stand_s, cfg.slips_out_s, cfg.ramp_s,
         cfg.tag_s]
    t = float(t0_s) + np.concatenate([[0.0], np.cumsum(d)])
    return ConnectionSchedule(t_start_s=t, params=np.array([cfg.pickup_m, cfg.stand_length_m, 0.0]))


@njit(cache=True)
def connection_controls(t, t_start, params, out):
    """Controls of a connection at time ``t``.

    Parameters
    ----------
    t : float
        Time, s.
    t_start : ndarray, shape (8,)
        ``ConnectionSchedule.t_start_s``.
    params : ndarray, shape (3,)
        ``ConnectionSchedule.params``.
    out : ndarray, shape (N_CC,)
        Written (see the ``CC_`` indices). The rpm factor ramps linearly
        1 -> 0 over ``PH_STOP`` and 0 -> 1 over ``PH_RAMP``; the block moves
        up by ``pickup_m`` over ``PH_PICKUP`` and down by it over ``PH_TAG``
        at constant speed, is held otherwise; ``CC_TRAVEL_SHIFT`` is the stand
        length from the end of ``PH_STAND`` on (the caller applies it once).

    Returns
    -------
    int
        The phase code (``PH_DRILL`` before and after the connection).
    """
    for k in range(N_CC):
        out[k] = 0.0
    out[CC_RPM_FACTOR] = 1.0
    out[CC_BLOCK_V] = np.nan
    if t < t_start[0] or t >= t_start[7]:
        out[CC_PHASE] = PH_DRILL
        if t >= t_start[7]:
            out[CC_TRAVEL_SHIFT] = params[1]
        return PH_DRILL
    k = 0
    while k < 6 and t >= t_start[k + 1]:
        k += 1
    ph = k + 1
    dur = t_start[k + 1] - t_start[k]
    frac = (t - t_start[k]) / dur if dur > 0.0 else 1.0
    pick = params[0]
    out[CC_PHASE] = ph
    out[CC_BLOCK_V] = 0.0
    if ph == PH_PICKUP:
        out[CC_BLOCK_V] = -pick / dur if dur > 0.0 else 0.0
    elif ph == PH_STOP:
        out[CC_RPM_FACTOR] = 1.0 - frac
    elif ph == PH_SLIPS or ph == PH_STAND:
        out[CC_RPM_FACTOR] = 0.0
        out[CC_SLIPS] = 1.0
    elif ph == PH_SLIPS_OUT:
        out[CC_RPM_FACTOR] = 0.0
    elif ph == PH_RAMP:
        out[CC_RPM_FACTOR] = frac
    elif ph == PH_TAG:
        out[CC_BLOCK_V] = pick / dur if dur > 0.0 else 0.0
    if ph > PH_STAND:
        out[CC_TRAVEL_SHIFT] = params[1]
    return ph


def plan_connections(window_s: float, block_travel_m: float, initial_travel_m: float,
                     stand_length_m: float, rop_m_per_s: float, cfg: ConnectionConfig) -> list[float]:
    """Start times of the connections in a window at a steady ROP (a planning estimate).

    The block lowers from ``initial_travel_m`` to ``block_travel_m`` at the ROP,
    a connection follows, after which the next stand is drilled down from
    ``block_travel_m - stand_length_m``. In a run the connections start when
    the block actually reaches the floor; this gives the expected count and
    times (e.g. to size a window or check the durations).
    """
    if rop_m_per_s <= 0.0:
        return []
    t = (block_travel_m - initial_travel_m) / rop_m_per_s
    starts = []
    while t < window_s:
        starts.append(t)
        t += cfg.duration_s + stand_length_m / rop_m_per_s
    return starts
