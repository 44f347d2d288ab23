"""Rig set-up from the configuration: checks before any step, and the kernels' parameters.

The ``rig`` section (:mod:`drillfatigue.config.rig`) says what the rig does;
this module checks what needs the string and the window besides (autodriller
loop stability, a connection longer than the window: :func:`check_rig_setup`,
a one-line :class:`~drillfatigue.errors.InputError` before any step) and packs
the parameter vectors of the block and top-drive kernels
(:mod:`drillfatigue.dynamics.top.rig`). See docs/rig.md.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

import numpy as np
from scipy.linalg import eigh_tridiagonal

from drillfatigue.config.rig import RigConfig
from drillfatigue.dynamics.top import rig as R
from drillfatigue.dynamics.top.rig import autodriller_delay_s, autodriller_loop
from drillfatigue.dynamics.bit.rockface import steady_wob_for_rop_N
from drillfatigue.errors import InputError
from drillfatigue.limits import FEATURE_BOUNDS
from drillfatigue.string import build_segments
from drillfatigue.units import rad_per_s_from_rpm

if TYPE_CHECKING:
    from drillfatigue.config import CaseConfig

# --- checks that need the string and the window -------------------------------------------

#: Phase margin below which an autodriller loop is refused, rad (it would ring for
#: tens of periods and a small model error would make it unstable).
MIN_PHASE_MARGIN_RAD = math.radians(10.0)


def string_axial_properties(case: CaseConfig, string_length_m: float | None = None) -> dict[str, float]:
    """Axial stiffness (N/m), axial wave speed (m/s) and length (m) of a case's string.

    The stiffness is the series sum of its components' ``EA / L`` between the
    top and the bit (the top component extended or cut to the span
    ``operation.bit_md_m - operation.top_md_m``, as the soft-string driver does).
    """
    if string_length_m is not None:
        case = case.model_copy(update={"operation": case.operation.model_copy(
            update={"top_md_m": case.operation.bit_md_m - string_length_m})})
    seg, lengths = _string_span(case)
    span = float(lengths.sum())
    ea = seg.ea_N[: lengths.size]
    rho_lin = seg.mass_per_length_kg_per_m[: lengths.size]
    compliance = float((lengths / ea).sum())
    # wave transit time: sum of L / c per component, c = sqrt(EA / (rho A)) with the component's
    # mass per length (tool joints included)
    transit = float((lengths * (rho_lin / ea) ** 0.5).sum())
    return {"k_axial_N_per_m": 1.0 / compliance, "wave_speed_m_per_s": span / transit,
            "length_m": span}


def check_rig_setup(rig: RigConfig, case: CaseConfig, c_rop_m_per_N_s: float = 0.0) -> dict[str, float]:
    """Checks of a rig set-up against its string and window, before any step is taken.

    Raises :class:`InputError` (one line) for an autodriller whose loop is
    unstable or has less than ``MIN_PHASE_MARGIN_RAD`` of phase margin on
    this string (criterion of :mod:`drillfatigue.dynamics.top.rig`), an ROP set-point
    the bit law cannot reach (:func:`rop_start_wob_N`), a connection
    longer than the simulated window, and a trip or ROP set-point above the
    block speed limit (also refused by :class:`RigConfig` itself).

    Parameters
    ----------
    rig : RigConfig
    case : CaseConfig
        The string and ``operation.duration_s`` (the window).
    c_rop_m_per_N_s : float
        ``dROP/dWOB`` of the bit law at the set-point (0: conservative).

    Returns
    -------
    dict
        ``omega_c_rad_s``, ``phase_margin_rad``, ``delay_s`` of the autodriller loop;
        ``rop_start_wob_N`` (the bit law's steady WOB at the set-point,
        :func:`rop_start_wob_N`) of a ``block_mode: rop`` run on bottom; empty
        otherwise. For ``summary.json``.
    """

    window = case.operation.duration_s
    if rig.connection.enabled and rig.connection.duration_s > window:
        raise InputError("rig.connection", f"one connection takes {rig.connection.duration_s:.0f} s, "
                         f"longer than the window operation.duration_s = {window:.0f} s",
                         "connection duration <= operation.duration_s")
    if rig.block_mode == "rop" and case.operation.bit_on_bottom:
        # the run starts in steady drilling at the set-point: the law must reach it
        return {"rop_start_wob_N": rop_start_wob_N(rig, case)}
    if rig.block_mode != "autodriller":
        return {}
    ad = rig.effective_autodriller
    props = string_axial_properties(case)
    # a first-order filter lags like a delay of its time constant at the loop's frequencies
    delay = autodriller_delay_s(props["length_m"], props["wave_speed_m_per_s"], ad.measurement,
                                ad.control_period_s, ad.telemetry_delay_s) + ad.measurement_filter_s
    wc, pm = autodriller_loop(ad.kp_m_per_s_per_N, ad.ki_m_per_s2_per_N, props["k_axial_N_per_m"],
                              c_rop_m_per_N_s, delay)
    if pm < MIN_PHASE_MARGIN_RAD:
        # the margin is lost both at small kp (integral action dominates: phase near -pi) and at
        # large kp (the delay): report the interval of kp with enough margin at this ki
        kp0 = ad.kp_m_per_s_per_N if ad.kp_m_per_s_per_N > 0 else 1e-7
        grid = [kp0 * 10.0 ** (e / 40.0) for e in range(-160, 161)]
        ok = [kp for kp in grid if autodriller_loop(kp, ad.ki_m_per_s2_per_N, props["k_axial_N_per_m"],
                                                    c_rop_m_per_N_s, delay)[1] >= MIN_PHASE_MARGIN_RAD]
        allowed = (f"{min(ok):.3g} <= kp_m_per_s_per_N <= {max(ok):.3g} with ki_m_per_s2_per_N = "
                   f"{ad.ki_m_per_s2_per_N:g}" if ok else "a smaller ki_m_per_s2_per_N")
        state = "unstable" if pm <= 0.0 else "nearly unstable"
        raise InputError("rig.autodriller.kp_m_per_s_per_N",
                         f"the autodriller loop is {state} on this string (phase margin "
                         f"{math.degrees(pm):.1f} deg at {wc:.2f} rad/s, needs "
                         f"{math.degrees(MIN_PHASE_MARGIN_RAD):.0f} deg; string stiffness "
                         f"{props['k_axial_N_per_m']:.3g} N/m, loop delay {delay:.2f} s)", allowed)
    return {"omega_c_rad_s": wc, "phase_margin_rad": pm, "delay_s": delay}


def drilling_rpm(case: CaseConfig) -> float:
    """The speed the run drills at after its start-up: the last entry of
    ``operation.rpm_table``, else ``operation.rpm``."""
    op = case.operation
    return float(op.rpm_table[-1][1]) if op.rpm_table is not None else float(op.rpm)


def rop_start_wob_N(rig: RigConfig, case: CaseConfig) -> float:
    """Initial WOB of a ``block_mode: rop`` run on bottom: the bit law's steady WOB for
    ``rig.rop_set_m_per_s`` at the drilling speed (:func:`drilling_rpm`), N.

    The block lowers at the set-point and, in steady drilling, the bit cuts as fast
    as the block lowers; the law is inverted by
    :func:`drillfatigue.dynamics.bit.rockface.steady_wob_for_rop_N` up to the largest WOB
    of :data:`drillfatigue.limits.FEATURE_BOUNDS` (1000 kN). A set-point the law
    cannot give below that WOB, or below its threshold, is an :class:`InputError`
    naming ``rig.rop_set_m_per_s`` and the reachable range, raised before any step.
    """
    rop = float(rig.rop_set_m_per_s)  # type: ignore[arg-type]
    rpm = drilling_rpm(case)
    wob_max = FEATURE_BOUNDS["wob_N"].hi
    wob, lo, hi = steady_wob_for_rop_N(case.bit, rop, rpm, wob_max)
    if math.isfinite(wob):
        return wob
    if hi <= 0.0:
        raise InputError("rig.rop_set_m_per_s",
                         f"the bit law ({case.bit.model}) cuts nothing at {rpm:g} rpm (below its "
                         "bit-speed threshold), so no WOB gives an ROP of "
                         f"{rop:.4g} m/s", "a drilling speed above the bit law's threshold")
    raise InputError("rig.rop_set_m_per_s",
                     f"{rop:.4g} m/s is not reachable by the bit law ({case.bit.model}) at "
                     f"{rpm:g} rpm with a WOB up to {wob_max:.0f} N",
                     # with a fade-in band the law's ROP rises continuously from 0
                     f"{'0 <' if lo < 1e-9 * hi else f'{lo:.4g} <='} rop_set_m_per_s <= {hi:.4g}")


# --- packing for the kernels -------------------------------------------------------------


def _string_span(case: CaseConfig) -> tuple[Any, np.ndarray]:
    """Segments (bit first) and their lengths extended/cut to the span top -> bit."""

    op = case.operation
    seg = build_segments(case.string, op.mud_density_kg_per_m3)
    span = op.bit_md_m - op.top_md_m
    lengths = seg.length_m.copy()
    top_end = lengths.cumsum()
    if top_end[-1] < span:
        lengths[-1] += span - top_end[-1]
    else:
        k = int((top_end < span).sum())
        lengths = lengths[: k + 1]
        lengths[-1] -= top_end[k] - span
    return seg, lengths


def string_torsional_properties(case: CaseConfig) -> dict[str, float]:
    """Torsional impedance of the top component and the string's first torsional mode.

    ``impedance_Nms_per_rad``: ``sqrt(GJ rho J_p)`` of the top segment's
    component (tool joints included in its inertia). ``first_mode_rad_s``:
    the lowest eigenfrequency of the segments as a torsional chain (inertia
    per segment, ``GJ / L`` between neighbours), clamped at the top (a stiff
    top drive) and free at the bit: the stick-slip frequency the soft-torque
    rule tunes for.
    """
    seg, lengths = _string_span(case)
    n = lengths.size
    ia_per_m = seg.inertia_axial_kg_m2[:n] / seg.length_m[:n]
    j = ia_per_m * lengths  # inertia of each (possibly extended) segment, bit first
    gj = seg.gj_Nm2[:n]
    # springs between segment centres, and from the top segment's centre to the quill
    k_between = 1.0 / (0.5 * lengths[:-1] / gj[:-1] + 0.5 * lengths[1:] / gj[1:])
    k_top = gj[-1] / (0.5 * lengths[-1])
    diag = np.zeros(n)
    diag[:-1] += k_between
    diag[1:] += k_between
    diag[-1] += k_top
    # symmetric form J^-1/2 K J^-1/2 of the tridiagonal chain
    d = diag / j
    e = -k_between / np.sqrt(j[:-1] * j[1:])
    w2 = eigh_tridiagonal(d, e, select="i", select_range=(0, 0), eigvals_only=True)[0]
    return {"impedance_Nms_per_rad": math.sqrt(float(gj[-1] * ia_per_m[-1])),
            "first_mode_rad_s": math.sqrt(max(float(w2), 0.0)), "length_m": float(lengths.sum())}


def block_params(rig: RigConfig, hook_off_N: float = 0.0) -> tuple[int, np.ndarray]:
    """Block mode id and parameter vector for :func:`drillfatigue.dynamics.top.rig.block_step`.

    ``hook_off_N`` is the autodriller's zero (the rotating off-bottom hook load,
    measured or from the soft-string model); used by ``measurement: hook_load``.
    """

    p = np.zeros(R.N_BLOCK_P)
    p[R.BP_VMAX] = rig.block.max_speed_m_per_s
    p[R.BP_AMAX] = rig.block.max_accel_m_per_s2
    p[R.BP_TRAVEL] = rig.block.travel_m
    if rig.block_mode == "autodriller":
        ad = rig.effective_autodriller
        mode = R.BLOCK_AUTODRILLER_HOOK if ad.measurement == "hook_load" else R.BLOCK_AUTODRILLER_WOB
        p[R.BP_WOBSET] = ad.wob_set_N
        p[R.BP_KP] = ad.kp_m_per_s_per_N
        p[R.BP_KI] = ad.ki_m_per_s2_per_N
        p[R.BP_TS] = ad.control_period_s
        p[R.BP_HOFF] = hook_off_N
        p[R.BP_ROPLIM] = ad.rop_limit_m_per_s
        p[R.BP_TFILT] = ad.measurement_filter_s
    elif rig.block_mode == "held":
        mode = R.BLOCK_HELD
    else:
        mode = R.BLOCK_VELOCITY
        v = rig.rop_set_m_per_s if rig.block_mode == "rop" else rig.trip_speed_m_per_s
        p[R.BP_VSET] = float(v)  # type: ignore[arg-type]
    return mode, p


def top_drive_params(rig: RigConfig, case: CaseConfig) -> tuple[int, np.ndarray, dict[str, float]]:
    """Top-drive mode id, parameter vector and the gains used (for ``summary.json``).

    ``soft_torque`` gains come from the string: ``Kp`` = impedance of the top
    component, ``Ki = J omega_ss^2`` with ``omega_ss = 2 pi / stick_slip_period_s``
    or the string's first torsional mode (:func:`string_torsional_properties`).
    """

    td = rig.top_drive
    p = np.zeros(R.N_TD_P)
    p[R.TP_J] = td.inertia_kg_m2
    p[R.TP_TMAX] = td.torque_limit_Nm
    info: dict[str, float] = {"inertia_kg_m2": td.inertia_kg_m2}
    if td.tuning == "stiff":
        return R.TOP_DRIVE_STIFF, p, info
    if td.tuning == "pi":
        kp, ki = float(td.kp_Nm_s_per_rad), float(td.ki_Nm_per_rad)  # type: ignore[arg-type]
    else:
        props = string_torsional_properties(case)
        w_ss = (2.0 * math.pi / td.stick_slip_period_s if td.stick_slip_period_s is not None
                else props["first_mode_rad_s"])
        kp, ki = R.soft_torque_gains(props["impedance_Nms_per_rad"], td.inertia_kg_m2, w_ss)
        info["stick_slip_omega_rad_s"] = w_ss
    p[R.TP_KP] = kp
    p[R.TP_KI] = ki
    info.update(kp_Nm_s_per_rad=kp, ki_Nm_per_rad=ki)
    return R.TOP_DRIVE_PI, p, info


def rod_input_impedance(omega_rad_s: float, sections: list[tuple[float, float, float]]) -> complex:
    """Axial driving-point impedance (N s/m) at the bottom of a stack of uniform rods.

    ``sections``: ``(length_m, EA_N, mass_per_length_kg_per_m)`` from the bit up;
    the last one continues upward without end (no reflection from the top: the
    string above is long and damped). Each section of impedance ``Z_s =
    sqrt(EA m')`` and wave number ``k = omega sqrt(m'/EA)`` carries the impedance
    ``Z`` at its top to ``Z_s (Z + i Z_s tan kL) / (Z_s + i Z tan kL)`` at its
    bottom (the transmission-line rule for longitudinal waves in a rod).
    """
    ea, m = sections[-1][1], sections[-1][2]
    z: complex = complex(math.sqrt(ea * m))
    for length, ea, m in reversed(sections[:-1]):
        zs = math.sqrt(ea * m)
        t = math.tan(omega_rad_s * math.sqrt(m / ea) * length)
        z = zs * (z + 1j * zs * t) / (zs + 1j * z * t)
    return z


def lobe_force_amplitude_N(rpm: float, lobe_count: int, amplitude_m: float,
                           contact_stiffness_N_per_m: float,
                           sections: list[tuple[float, float, float]]) -> float:
    """Amplitude of the contact force a fixed lobed face drives into a string (linear, undamped).

    The face moves the bit face as ``A sin(n Omega t)``; the rock spring ``k``
    in series with the string's driving-point impedance ``Z``
    (:func:`rod_input_impedance`) carries ``|F| = A / |1/k + 1/(i w Z)|`` at
    ``w = n Omega``. The bit stays on a face it is pressed on with a mean WOB
    above ``|F|`` and leaves it below (bit bounce). Undamped: near a resonance
    of the string it overestimates, away from one it is the linear answer.
    """
    w = rad_per_s_from_rpm(lobe_count * abs(rpm))
    if w == 0.0 or amplitude_m == 0.0:
        return 0.0
    z = rod_input_impedance(w, sections)
    return float(amplitude_m / abs(1.0 / contact_stiffness_N_per_m + 1.0 / (1j * w * z)))
