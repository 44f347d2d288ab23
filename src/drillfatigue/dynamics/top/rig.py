"""Rig boundaries at the top of the string: the travelling block and the top drive.

Kernels (``@njit(cache=True)``, float64 vectors, SI, status codes) that the
simulator calls once per step, and the closed forms that set and check their
gains. The configuration lives in :mod:`drillfatigue.config.rig`; the user
documentation is ``docs/rig.md``.

Block
-----
The top of the string hangs from the block; its position ``x`` (m, block
travel measured downward from the top of its travel, 0 .. ``travel``) and
velocity ``v`` (m/s, > 0 lowering) are the state. The hook load is what the
string pulls on the hook, measured by the simulator and passed in, not
imposed. Each step the mode gives a velocity command, the block follows it
within the acceleration limit and the speed limit, and stops at the ends of
its travel (status ``BLOCK_AT_FLOOR``: a connection is due, or
``BLOCK_AT_CROWN``). Modes:

``BLOCK_HELD``
    command 0 (slips set, or the driller holds the brake).
``BLOCK_VELOCITY``
    command = the set velocity: an ROP set-point (> 0), or tripping in (> 0)
    and out (< 0) at a block speed; reaming and back-reaming are the same
    with the top drive turning.
``BLOCK_AUTODRILLER_WOB``, ``BLOCK_AUTODRILLER_HOOK``
    a PI controller on the weight-on-bit error ``e = WOB_set - WOB_meas``
    in velocity form, ``v_cmd = Kp e + Ki integral(e)``, sampled every
    ``Ts`` (zero-order hold). The driller's autodriller sees only the surface
    hook load: WOB_meas = ``H_off - H`` with ``H_off`` the off-bottom
    (rotating) hook load taken before tagging bottom (``_HOOK`` mode); the
    ``_WOB`` mode takes a downhole WOB measurement. The measurement passes a
    first-order filter of time constant ``BP_TFILT`` (0: none) before the
    controller samples it. The command is limited to
    ``[-v_max, rop_limit]`` and the integral stops growing while the command
    is limited in the direction of the error, or while the block stands at
    an end of its travel and the command pushes beyond it
    (conditional-integration anti-windup).

Top drive
---------
State: the quill speed ``omega`` (rad/s), angle ``phi`` (rad), the PI
integral and the drive torque (N m), all on the string side of the gearbox
(the motor's inertia ``J_m`` appears as ``n^2 J_m``, its torque as ``n T_m``).

``TOP_DRIVE_STIFF``
    the speed is imposed (the set-point and its rate); the drive torque is
    what holding it takes, ``T = T_string + J domega_set/dt``.
``TOP_DRIVE_PI``
    ``J domega/dt = T - T_string``, ``T = clip(Kp (omega_set - omega) + Ki
    integral, -T_max, T_max)`` with conditional-integration anti-windup; the
    surface torque is ``T``. Stepped semi-implicitly (speed first, then angle
    with the new speed).

"Soft-torque" tuning (Kyllingstad & Nessjoen, "A new stick-slip prevention system", SPE/IADC
119660, 2009): ``Kp``
equal to the characteristic torsional impedance of the drill pipe,
``Z = J_p sqrt(G rho)``, so that torsional waves arriving at the top are
absorbed rather than reflected, and ``Ki = J omega_ss^2``, which cancels the
top drive's inertia at the stick-slip frequency ``omega_ss`` (estimated by
:func:`torsional_first_mode_rad_s`).

Autodriller stability
---------------------
Quasi-static plant: the block lowers the top at ``v``, the string (axial
stiffness ``k`` from block to rock, in series with the rock contact) turns a
length mismatch into WOB, and the bit drills it off at ``ROP = c WOB`` (the
linearised bit law, ``c = dROP/dWOB``); what the controller measures is
delayed by ``tau`` (axial waves run ``L / c_a`` down and, for the hook-load
measurement, back up; plus half the control period for the zero-order hold
and any telemetry delay). So ``dWOB/dt = k (v(t - tau) - c WOB)`` and the
open loop from set-point error to measured WOB is

    L(s) = k (Kp s + Ki) exp(-s tau) / (s (s + k c)).

``|L(i w)|`` falls monotonically with ``w`` (its square is
``k^2 (Ki^2 + Kp^2 u) / (u (u + k^2 c^2))`` with ``u = w^2``), so it crosses
1 once, at

    w_c^2 = [k^2 (Kp^2 - c^2) + sqrt(k^4 (Kp^2 - c^2)^2 + 4 k^2 Ki^2)] / 2,

and the loop is stable (Nyquist) iff the phase there is above -pi:

    phase margin = atan(Kp w_c / Ki) + atan(k c / w_c) - w_c tau > 0.

Without delay the margin is positive for any positive gains: this closed
loop is the second-order system ``WOB'' + k (Kp + c) WOB' + k Ki WOB = k Ki
WOB_set`` (natural frequency ``sqrt(k Ki)``, damping ratio ``k (Kp + c) /
(2 sqrt(k Ki))``) used by the step-response reference. With the delay, too
high a proportional gain makes the loop oscillate and grow.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

# --- block --------------------------------------------------------------------------------
BLOCK_HELD = 0
BLOCK_VELOCITY = 1
BLOCK_AUTODRILLER_WOB = 2
BLOCK_AUTODRILLER_HOOK = 3

#: block parameter vector (float64, length ``N_BLOCK_P``)
BP_VMAX = 0  # block speed limit, m/s
BP_AMAX = 1  # block acceleration limit, m/s^2
BP_TRAVEL = 2  # block travel, m (x in [0, travel])
BP_VSET = 3  # velocity set-point of BLOCK_VELOCITY, m/s (> 0 lowering)
BP_WOBSET = 4  # WOB set-point, N
BP_KP = 5  # autodriller proportional gain, (m/s) / N
BP_KI = 6  # autodriller integral gain, (m/s^2) / N
BP_TS = 7  # autodriller control period, s (0: every step)
BP_HOFF = 8  # off-bottom hook load (the autodriller's zero of WOB), N
BP_ROPLIM = 9  # autodriller's largest lowering command (ROP limit), m/s
BP_TFILT = 10  # time constant of the first-order filter on the measured WOB / hook load, s (0: none)
N_BLOCK_P = 11

#: block state vector (float64, length ``N_BLOCK_S``)
BS_X = 0  # block travel below the top of its travel, m
BS_V = 1  # block velocity, m/s (> 0 lowering)
BS_I = 2  # integral of the WOB error, N s
BS_VCMD = 3  # held velocity command, m/s
BS_TNEXT = 4  # time of the next controller sample, s
BS_T = 5  # time, s
BS_WOBMEAS = 6  # WOB the controller used at its last sample, N
BS_MEAS = 7  # filtered measurement (WOB or hook load of the mode), N
N_BLOCK_S = 8

BLOCK_OK = 0
BLOCK_AT_FLOOR = 1
BLOCK_AT_CROWN = 2
BLOCK_BAD_MODE = -1
BLOCK_NONFINITE = -2


@njit(cache=True)
def block_command(mode, p, s, wob_N, hook_N, dt):
    """Velocity command of the block's mode at the current state (m/s); updates the PI state.

    Parameters
    ----------
    mode : int
        ``BLOCK_HELD``, ``BLOCK_VELOCITY``, ``BLOCK_AUTODRILLER_WOB`` or ``BLOCK_AUTODRILLER_HOOK``.
    p : ndarray, shape (N_BLOCK_P,)
    s : ndarray, shape (N_BLOCK_S,)
        Read and written: the PI integral, the held command and the next sample time.
    wob_N, hook_N : float
        Measured WOB (N) and hook load (N) now.
    dt : float
        Step, s: the integration interval when the controller samples every
        step (``BP_TS = 0``).

    Returns
    -------
    float
        The velocity command, m/s; NaN for an unknown mode.
    """
    if mode == BLOCK_HELD:
        return 0.0
    if mode == BLOCK_VELOCITY:
        return p[BP_VSET]
    if mode != BLOCK_AUTODRILLER_WOB and mode != BLOCK_AUTODRILLER_HOOK:
        return math.nan
    ts = p[BP_TS]
    if ts > 0.0 and s[BS_T] + 0.5 * dt < s[BS_TNEXT]:
        return s[BS_VCMD]
    w = wob_N if mode == BLOCK_AUTODRILLER_WOB else p[BP_HOFF] - hook_N
    e = p[BP_WOBSET] - w
    lo = -p[BP_VMAX]
    hi = min(p[BP_ROPLIM], p[BP_VMAX])
    # the integral advances over the hold period that follows this sample
    dt_i = ts if ts > 0.0 else dt
    i_new = s[BS_I] + e * dt_i
    v = p[BP_KP] * e + p[BP_KI] * i_new
    if (v > hi and e > 0.0) or (v < lo and e < 0.0):
        i_new = s[BS_I]  # conditional integration: no wind-up against the limit
        v = p[BP_KP] * e + p[BP_KI] * i_new
    v = min(max(v, lo), hi)
    s[BS_I] = i_new
    s[BS_VCMD] = v
    s[BS_WOBMEAS] = w
    s[BS_TNEXT] = s[BS_T] + ts
    return v


@njit(cache=True)
def block_step(mode, p, s, wob_N, hook_N, dt):
    """Advance the block by one step ``dt``: command, rate and speed limits, travel ends.

    Parameters
    ----------
    mode : int
    p : ndarray, shape (N_BLOCK_P,)
    s : ndarray, shape (N_BLOCK_S,)
        Block state, advanced in place (position, velocity, controller, time).
    wob_N, hook_N : float
        Measured WOB and hook load at the start of the step, N.
    dt : float
        Step, s. With ``BP_TS = 0`` the autodriller samples every step and
        integrates its error over ``dt``.

    Returns
    -------
    int
        ``BLOCK_OK``, ``BLOCK_AT_FLOOR`` (the block reached the bottom of its
        travel: stopped, a connection is due), ``BLOCK_AT_CROWN`` (stopped at
        the top), ``BLOCK_BAD_MODE`` or ``BLOCK_NONFINITE``.
    """
    i_prev = s[BS_I]
    tf = p[BP_TFILT]
    if tf > 0.0 and (mode == BLOCK_AUTODRILLER_WOB or mode == BLOCK_AUTODRILLER_HOOK):
        # the load cell / downhole sensor and the display are filtered (first order,
        # exact for a measurement held over the step)
        raw = wob_N if mode == BLOCK_AUTODRILLER_WOB else hook_N
        s[BS_MEAS] += (1.0 - math.exp(-dt / tf)) * (raw - s[BS_MEAS])
        wob_N = s[BS_MEAS]
        hook_N = s[BS_MEAS]
    vc = block_command(mode, p, s, wob_N, hook_N, dt)
    if math.isnan(vc):
        return BLOCK_BAD_MODE
    vmax = p[BP_VMAX]
    vc = min(max(vc, -vmax), vmax)
    dv_max = p[BP_AMAX] * dt
    v0 = s[BS_V]
    v1 = v0 + min(max(vc - v0, -dv_max), dv_max)
    x1 = s[BS_X] + 0.5 * (v0 + v1) * dt
    status = BLOCK_OK
    if x1 >= p[BP_TRAVEL]:
        x1 = p[BP_TRAVEL]
        v1 = 0.0
        status = BLOCK_AT_FLOOR
    elif x1 <= 0.0:
        x1 = 0.0
        v1 = 0.0
        status = BLOCK_AT_CROWN
    if (status == BLOCK_AT_FLOOR and vc > 0.0) or (status == BLOCK_AT_CROWN and vc < 0.0):
        # conditional integration at the ends of the travel too: an autodriller whose
        # block cannot follow does not wind up
        s[BS_I] = i_prev
    s[BS_X] = x1
    s[BS_V] = v1
    s[BS_T] += dt
    if not (math.isfinite(x1) and math.isfinite(v1)):
        return BLOCK_NONFINITE
    return status


# --- top drive ----------------------------------------------------------------------------
TOP_DRIVE_STIFF = 0
TOP_DRIVE_PI = 1

#: top-drive parameter vector (string side of the gearbox)
TP_J = 0  # inertia n^2 J_motor + J_gear/quill, kg m^2
TP_KP = 1  # N m s/rad
TP_KI = 2  # N m/rad
TP_TMAX = 3  # torque limit, N m
N_TD_P = 4

#: top-drive state vector
TS_OMEGA = 0  # quill speed, rad/s
TS_PHI = 1  # quill angle, rad
TS_I = 2  # integral of the speed error, rad
TS_T = 3  # drive torque applied to the quill, N m
N_TD_S = 4

TD_OK = 0
TD_AT_LIMIT = 1
TD_BAD_MODE = -1
TD_NONFINITE = -2


@njit(cache=True)
def top_drive_step(mode, p, s, omega_set, omega_set_rate, torque_string, dt):
    """Advance the top drive by one step.

    Parameters
    ----------
    mode : int
        ``TOP_DRIVE_STIFF`` or ``TOP_DRIVE_PI``.
    p : ndarray, shape (N_TD_P,)
    s : ndarray, shape (N_TD_S,)
        Advanced in place.
    omega_set, omega_set_rate : float
        Speed set-point (rad/s) and its time derivative (rad/s^2) at the start of the step.
    torque_string : float
        Torque the string exerts back on the quill (its top torsional load), N m.
    dt : float
        Step, s.

    Returns
    -------
    int
        ``TD_OK``, ``TD_AT_LIMIT`` (the PI output was limited), ``TD_BAD_MODE``
        or ``TD_NONFINITE``.
    """
    if mode == TOP_DRIVE_STIFF:
        s[TS_T] = torque_string + p[TP_J] * omega_set_rate
        w1 = omega_set + omega_set_rate * dt
        s[TS_PHI] += 0.5 * (omega_set + w1) * dt
        s[TS_OMEGA] = w1
        return TD_OK
    if mode != TOP_DRIVE_PI:
        return TD_BAD_MODE
    e = omega_set - s[TS_OMEGA]
    tmax = p[TP_TMAX]
    i_new = s[TS_I] + e * dt
    t = p[TP_KP] * e + p[TP_KI] * i_new
    status = TD_OK
    if (t > tmax and e > 0.0) or (t < -tmax and e < 0.0):
        i_new = s[TS_I]
        t = p[TP_KP] * e + p[TP_KI] * i_new
    if t > tmax:
        t = tmax
        status = TD_AT_LIMIT
    elif t < -tmax:
        t = -tmax
        status = TD_AT_LIMIT
    s[TS_I] = i_new
    s[TS_T] = t
    s[TS_OMEGA] += dt * (t - torque_string) / p[TP_J]
    s[TS_PHI] += s[TS_OMEGA] * dt
    if not math.isfinite(s[TS_OMEGA]):
        return TD_NONFINITE
    return status


# --- Python helpers: gains, modes, stability ----------------------------------------------


def autodriller_loop(kp: float, ki: float, k_axial_N_per_m: float, c_rop: float,
                     delay_s: float) -> tuple[float, float]:
    """Gain crossover and phase margin of the autodriller loop (module docstring).

    Parameters
    ----------
    kp : float
        Proportional gain, (m/s)/N.
    ki : float
        Integral gain, (m/s^2)/N.
    k_axial_N_per_m : float
        Axial stiffness from the block to the rock (string in series with the rock contact), N/m.
    c_rop : float
        ``dROP/dWOB`` of the bit law at the operating point, m/(N s); 0 if unknown
        (conservative: it adds phase).
    delay_s : float
        Loop delay, s.

    Returns
    -------
    omega_c : float
        Gain crossover, rad/s.
    phase_margin_rad : float
        > 0: stable.
    """
    k = k_axial_N_per_m
    a = k * k * (kp * kp - c_rop * c_rop)
    u = 0.5 * (a + math.sqrt(a * a + 4.0 * k * k * ki * ki))
    wc = math.sqrt(u)
    if wc == 0.0:
        return 0.0, math.pi
    pm = math.atan2(kp * wc, ki) + math.atan2(k * c_rop, wc) - wc * delay_s
    return wc, pm


def autodriller_delay_s(length_m: float, wave_speed_m_per_s: float, measurement: str,
                        control_period_s: float, telemetry_delay_s: float = 0.0) -> float:
    """Loop delay: axial wave transit (down; and up for the hook load), half the period, telemetry."""
    n_way = 2.0 if measurement == "hook_load" else 1.0
    extra = telemetry_delay_s if measurement == "wob" else 0.0
    return n_way * length_m / wave_speed_m_per_s + 0.5 * control_period_s + extra


def second_order_step(t_s: np.ndarray, k_axial_N_per_m: float, kp: float, ki: float, c_rop: float,
                      step_N: float) -> np.ndarray:
    """WOB change after a set-point step of the delay-free autodriller loop, N (closed form).

    ``WOB'' + 2 zeta wn WOB' + wn^2 WOB = wn^2 step`` with ``wn^2 = k Ki`` and
    ``2 zeta wn = k (Kp + c)``, but the set-point also enters through ``Kp``
    (a zero at ``-Ki/Kp``): ``WOB(s) / step = k (Kp s + Ki) / (s^2 + k (Kp + c) s + k Ki)``.
    Evaluated by its partial fractions (under-, critically or over-damped).
    """
    t = np.asarray(t_s, float)
    k = k_axial_N_per_m
    a1 = k * (kp + c_rop)
    a0 = k * ki
    b1 = k * kp
    b0 = k * ki
    disc = a1 * a1 - 4.0 * a0
    if a0 == 0.0:
        raise ValueError("second_order_step needs ki > 0")
    # y(t) = step * [b0/a0 + response of (b1 s + b0 - (b0/a0) (s + a1)) / (s^2 + a1 s + a0)]
    y_inf = b0 / a0
    # homogeneous part with y(0) = 0, y'(0) = b1 (the zero gives an initial slope)
    if abs(disc) < 1e-12 * a1 * a1:
        r = -0.5 * a1
        c1 = -y_inf
        c2 = b1 - r * c1
        y = y_inf + (c1 + c2 * t) * np.exp(r * t)
    elif disc < 0.0:
        sig = -0.5 * a1
        wd = 0.5 * math.sqrt(-disc)
        c1 = -y_inf
        c2 = (b1 - sig * c1) / wd
        y = y_inf + np.exp(sig * t) * (c1 * np.cos(wd * t) + c2 * np.sin(wd * t))
    else:
        r1 = 0.5 * (-a1 + math.sqrt(disc))
        r2 = 0.5 * (-a1 - math.sqrt(disc))
        # c1 + c2 = -y_inf, r1 c1 + r2 c2 = b1
        c1 = (b1 + r2 * y_inf) / (r1 - r2)
        c2 = -y_inf - c1
        y = y_inf + c1 * np.exp(r1 * t) + c2 * np.exp(r2 * t)
    return step_N * y


def torsional_impedance_Nms_per_rad(gj_Nm2: float, polar_inertia_per_length_kg_m: float) -> float:
    """Characteristic torsional impedance of a pipe, ``sqrt(GJ rho J_p)``, N m s/rad."""
    return math.sqrt(gj_Nm2 * polar_inertia_per_length_kg_m)


def torsional_first_mode_rad_s(length_m: float, wave_speed_m_per_s: float, pipe_inertia_kg_m2: float,
                               end_inertia_kg_m2: float) -> float:
    """First torsional mode of a pipe clamped at the top with an end inertia (the BHA), rad/s.

    Root of ``x tan(x) = J_pipe / J_end`` with ``x = omega L / c`` in ``(0, pi/2)``
    (a uniform shaft, fixed at one end, with a lumped inertia at the other);
    ``J_end -> 0`` gives the quarter wave ``pi c / (2 L)``.
    """
    if end_inertia_kg_m2 <= 0.0:
        return 0.5 * math.pi * wave_speed_m_per_s / length_m
    r = pipe_inertia_kg_m2 / end_inertia_kg_m2
    lo, hi = 0.0, 0.5 * math.pi
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if mid * math.tan(mid) < r:
            lo = mid
        else:
            hi = mid
    return 0.5 * (lo + hi) * wave_speed_m_per_s / length_m


def soft_torque_gains(impedance_Nms_per_rad: float, inertia_kg_m2: float,
                      omega_stick_slip_rad_s: float) -> tuple[float, float]:
    """Soft-torque PI gains ``(Kp, Ki) = (Z, J omega_ss^2)`` (Kyllingstad & Nessjoen 2009)."""
    return impedance_Nms_per_rad, inertia_kg_m2 * omega_stick_slip_rad_s**2


BLOCK_MODE_IDS: dict[str, int] = {"held": BLOCK_HELD, "rop": BLOCK_VELOCITY, "trip": BLOCK_VELOCITY,
                                  "autodriller_wob": BLOCK_AUTODRILLER_WOB,
                                  "autodriller_hook_load": BLOCK_AUTODRILLER_HOOK}
TOP_DRIVE_MODE_IDS: dict[str, int] = {"stiff": TOP_DRIVE_STIFF, "pi": TOP_DRIVE_PI,
                                      "soft_torque": TOP_DRIVE_PI}


def new_block_state(x0_m: float = 0.0, v0_m_per_s: float = 0.0) -> np.ndarray:
    """A block state vector at travel ``x0`` and velocity ``v0``, controller at rest."""
    s = np.zeros(N_BLOCK_S)
    s[BS_X] = x0_m
    s[BS_V] = v0_m_per_s
    return s


def new_top_drive_state(omega0_rad_s: float = 0.0) -> np.ndarray:
    """A top-drive state vector turning at ``omega0``, controller at rest."""
    s = np.zeros(N_TD_S)
    s[TS_OMEGA] = omega0_rad_s
    return s


def drilling_window_metrics(
    time_s: np.ndarray,
    wob_N: np.ndarray,
    rop_m_per_s: np.ndarray,
    surface_torque_Nm: np.ndarray,
    block_travel_m: np.ndarray,
    travel_m: float,
    wob_set_N: float,
    string_top_above_rotary_m: np.ndarray | None = None,
    t_skip_s: float = 10.0,
) -> dict[str, float | bool]:
    """What a drilling window did at the rig boundaries, for ``summary.json`` and case-2 metrics.

    Time averages weight each sample by the interval to the next one (sample
    and hold) and use only ``t >= time_s[0] + t_skip_s`` (the start-up).

    Returns
    -------
    dict
        ``on_bottom_fraction`` (share of time with WOB > 0), ``mean_wob_N``,
        ``wob_error_rel`` (mean WOB / set-point - 1), ``mean_rop_m_per_s``,
        ``mean_surface_torque_Nm``, ``block_min_m``, ``block_max_m``,
        ``block_within_travel`` (0 <= travel <= ``travel_m`` throughout) and,
        with ``string_top_above_rotary_m``, its maximum
        ``string_top_max_above_rotary_m`` and ``string_top_below_rotary``
        (never above).
    """
    t = np.asarray(time_s, float)
    if t.ndim != 1 or t.size < 2 or not np.all(np.diff(t) > 0):
        raise ValueError("time_s must be 1-D, increasing, with at least 2 samples")
    sel = t >= t[0] + t_skip_s
    if sel.sum() < 2:
        raise ValueError(f"no window left after t_skip_s = {t_skip_s} s")
    dt = np.diff(t[sel])
    w = np.concatenate([dt, dt[-1:]])
    w = w / w.sum()

    def avg(x: np.ndarray) -> float:
        return float(np.sum(np.asarray(x, float)[sel] * w))

    wob = np.asarray(wob_N, float)
    blk = np.asarray(block_travel_m, float)
    out: dict[str, float | bool] = {
        "on_bottom_fraction": float(np.sum((wob[sel] > 0.0) * w)),
        "mean_wob_N": avg(wob),
        "wob_error_rel": avg(wob) / wob_set_N - 1.0,
        "mean_rop_m_per_s": avg(rop_m_per_s),
        "mean_surface_torque_Nm": avg(surface_torque_Nm),
        "block_min_m": float(blk.min()),
        "block_max_m": float(blk.max()),
        "block_within_travel": bool(blk.min() >= 0.0 and blk.max() <= travel_m),
    }
    if string_top_above_rotary_m is not None:
        top = np.asarray(string_top_above_rotary_m, float)
        out["string_top_max_above_rotary_m"] = float(top.max())
        out["string_top_below_rotary"] = bool(top.max() <= 0.0)
    return out
