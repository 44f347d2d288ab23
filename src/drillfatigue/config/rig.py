"""``rig`` section: the travelling block, the autodriller, the top drive, the rock face, connections.

Kernels: :mod:`drillfatigue.dynamics.rig` (block, top drive, rock face) and
:mod:`drillfatigue.dynamics.connection` (connection event sequence). User
documentation with the basis of every default: ``docs/rig.md``.

Every mode uses only some inputs; an input given for a mode that cannot use it
is an error naming the mode (no silent overrides), and
:meth:`RigConfig.effective_inputs` lists what a mode does use (for
``summary.json``). Checks that need the string and the window (autodriller
loop stability, a connection longer than the window) are in
:func:`check_rig_setup`, called before any step is taken.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any, Literal

import numpy as np
from pydantic import Field, model_validator

from drillfatigue.config.base import StrictModel
from drillfatigue.errors import InputError
from drillfatigue.units import HOUR_S

if TYPE_CHECKING:
    from drillfatigue.config import CaseConfig

#: Stand of three range-2 joints (3 x 9.5 m), the usual unit added at a connection, m.
DEFAULT_STAND_LENGTH_M = 28.5


class BlockConfig(StrictModel):
    """The travelling block.

    Attributes
    ----------
    travel_m : float
        Usable block travel, m. Default 30: a stand (28.5 m) plus the quill
        and elevator margin of a rig built for triples.
    max_speed_m_per_s : float
        Block speed limit, m/s. Default 1.5 (drawworks tripping speeds are
        about 0.5-2 m/s).
    max_accel_m_per_s2 : float
        Block acceleration limit, m/s^2. Default 0.5 (a stop from 1.5 m/s in
        3 s; drawworks brakes and VFDs ramp over seconds).
    initial_travel_m : float
        Block position at t = 0, m below the top of its travel. Default 0
        (a fresh stand: the block at the top).
    """

    travel_m: float = Field(30.0, gt=0.0, le=60.0)
    max_speed_m_per_s: float = Field(1.5, gt=0.0, le=5.0)
    max_accel_m_per_s2: float = Field(0.5, gt=0.0, le=20.0)
    initial_travel_m: float = Field(0.0, ge=0.0, le=60.0)

    @model_validator(mode="after")
    def _check(self) -> BlockConfig:
        if self.initial_travel_m > self.travel_m:
            raise ValueError(f"initial_travel_m: {self.initial_travel_m} m is beyond the block travel "
                             f"{self.travel_m} m (allowed: 0 <= initial_travel_m <= travel_m)")
        return self


class AutodrillerConfig(StrictModel):
    """PI autodriller on the weight on bit (velocity form; ``docs/rig.md``).

    Attributes
    ----------
    measurement : {"hook_load", "wob"}
        ``hook_load``: what the driller's autodriller has, WOB = off-bottom
        hook load - hook load (default); ``wob``: a downhole WOB measurement.
    wob_set_N : float
        WOB set-point, N. Default 100 kN (mid range of an 8 1/2 in PDC bit,
        about 10-180 kN).
    kp_m_per_s_per_N, ki_m_per_s2_per_N : float
        PI gains. Defaults 5.7e-7 (m/s)/N and 5.7e-8 (m/s^2)/N: a closed loop
        with natural frequency 0.2 rad/s and damping ratio 1 for a string of
        axial stiffness 7e5 N/m (1000 m of 5 in drill pipe, EA/L); a 10 kN
        error then asks for 5.7 mm/s (20 m/h).
    rop_limit_m_per_s : float
        Largest lowering command, m/s. Default 60 m/h.
    control_period_s : float
        Controller sample period, s; 0 = every step. Default 0.1 (a PLC cycle).
    telemetry_delay_s : float
        Delay of the downhole WOB measurement (``wob`` only), s. Default 0.
    measurement_filter_s : float
        Time constant of the first-order filter on the measurement, s; 0: none.
        Default 0.5 s: load cells and autodriller displays are filtered over about
        a second or less, which keeps the bit's lobe-rate WOB ripple (tens of Hz,
        attenuated to ~1 %) out of the controller; the loop's phase margin on the
        default 1000 m string drops from 65 to 51 deg. Without it a ripple that reaches zero WOB (bit bounce) drives the
        command into its ROP limit at every lift-off, where the anti-windup freezes
        the integral, and the mean WOB settles below the set-point.
    """

    measurement: Literal["hook_load", "wob"] = "hook_load"
    wob_set_N: float = Field(100e3, gt=0.0, le=2e6)
    kp_m_per_s_per_N: float = Field(5.7e-7, ge=0.0, le=1e-3)
    ki_m_per_s2_per_N: float = Field(5.7e-8, gt=0.0, le=1e-3)
    rop_limit_m_per_s: float = Field(60.0 / HOUR_S, gt=0.0, le=1.0)
    control_period_s: float = Field(0.1, ge=0.0, le=10.0)
    telemetry_delay_s: float = Field(0.0, ge=0.0, le=60.0)
    measurement_filter_s: float = Field(0.5, ge=0.0, le=60.0)

    @model_validator(mode="after")
    def _check(self) -> AutodrillerConfig:
        if self.measurement == "hook_load" and self.telemetry_delay_s != 0.0:
            raise ValueError("telemetry_delay_s: not used with measurement hook_load "
                             "(allowed: 0, or measurement wob)")
        return self


class TopDriveConfig(StrictModel):
    """The top drive and its speed controller (string side of the gearbox).

    Attributes
    ----------
    tuning : {"stiff", "pi", "soft_torque"}
        ``stiff``: the speed is imposed, the torque is what it takes
        (default; the simulator's behaviour before the rig boundaries);
        ``pi``: PI speed control with ``kp``/``ki``; ``soft_torque``: PI with
        the gains of the soft-torque rule (``Kp`` = pipe torsional impedance,
        ``Ki`` = ``J omega_ss^2``; Kyllingstad & Nessjoen 2009).
    motor_inertia_kg_m2 : float
        Inertia of the motor rotor(s) on the motor shaft, kg m^2. Default 8
        (two AC motors of a 500 t electric top drive; a stated value, not a
        datasheet).
    gear_ratio : float
        Motor speed / quill speed. Default 10.5.
    quill_inertia_kg_m2 : float
        Gears, quill, saver sub on the string side, kg m^2. Default 50.
    kp_Nm_s_per_rad, ki_Nm_per_rad : float or None
        PI gains (``pi`` only; string side). Used for ``pi``, an error for the
        other tunings.
    torque_limit_Nm : float
        Torque limit at the quill, N m. Default 50 kN m (continuous drilling
        torque of a 500 t top drive, about 37 kft lbf).
    stick_slip_period_s : float or None
        ``soft_torque`` only: the stick-slip period to tune for, s; default
        the first torsional mode of the string
        (:func:`drillfatigue.dynamics.rig.torsional_first_mode_rad_s`).
    """

    tuning: Literal["stiff", "pi", "soft_torque"] = "stiff"
    motor_inertia_kg_m2: float = Field(8.0, gt=0.0, le=1e3)
    gear_ratio: float = Field(10.5, gt=0.0, le=100.0)
    quill_inertia_kg_m2: float = Field(50.0, ge=0.0, le=1e4)
    kp_Nm_s_per_rad: float | None = Field(None, ge=0.0, le=1e8)
    ki_Nm_per_rad: float | None = Field(None, ge=0.0, le=1e9)
    torque_limit_Nm: float = Field(50e3, gt=0.0, le=1e6)
    stick_slip_period_s: float | None = Field(None, gt=0.0, le=600.0)

    @model_validator(mode="after")
    def _check(self) -> TopDriveConfig:
        gains = self.kp_Nm_s_per_rad is not None or self.ki_Nm_per_rad is not None
        if self.tuning == "pi" and (self.kp_Nm_s_per_rad is None or self.ki_Nm_per_rad is None):
            raise ValueError("kp_Nm_s_per_rad: tuning pi needs both kp_Nm_s_per_rad and ki_Nm_per_rad "
                             "(allowed: both given with tuning pi)")
        if self.tuning != "pi" and gains:
            raise ValueError(f"kp_Nm_s_per_rad: the gains are not used by tuning {self.tuning} "
                             "(allowed: gains only with tuning pi)")
        if self.tuning != "soft_torque" and self.stick_slip_period_s is not None:
            raise ValueError(f"stick_slip_period_s: not used by tuning {self.tuning} "
                             "(allowed: only with tuning soft_torque)")
        return self

    @property
    def inertia_kg_m2(self) -> float:
        """Inertia on the string side, ``n^2 J_motor + J_quill``, kg m^2."""
        return self.gear_ratio**2 * self.motor_inertia_kg_m2 + self.quill_inertia_kg_m2


class RockConfig(StrictModel):
    """Rock face under the bit (``docs/rig.md``).

    Attributes
    ----------
    contact_stiffness_N_per_m : float or None
        Penalty stiffness of the rock face, N/m. Default: the axial joint
        stiffness of the bit segment (EA/L), as the simulator's bit guide
        uses, so the rock spring never sets the stable step and its
        compliance is that of one more segment.
    contact_damping_ratio : float
        Fraction of critical damping of the rock dash-pot for the bit
        segment's mass, 0..1. Default 0.2 (as the wall contact, MODEL.md section 5).
    lobe_count : int
        Lobes of the bottom-hole pattern per revolution. Default 3 (tricone
        pattern, MODEL.md section 4).
    lobe_amplitude_m : float
        Amplitude of the lobed face, m. Default 1 mm (MODEL.md section 4).
    """

    contact_stiffness_N_per_m: float | None = Field(None, ge=1e4, le=1e11)
    contact_damping_ratio: float = Field(0.2, ge=0.0, le=1.0)
    lobe_count: int = Field(3, ge=0, le=20)
    lobe_amplitude_m: float = Field(1e-3, ge=0.0, le=0.05)


class ConnectionConfig(StrictModel):
    """The connection sequence when the block reaches the floor (``drillfatigue.dynamics.connection``).

    Durations, s: ``rotation_stop_s`` (rpm ramps to 0 after the bit is picked
    off bottom), ``pickup_s`` (block raised off bottom by ``pickup_m``),
    ``slips_s`` (slips set, string hangs in the rotary), ``stand_s`` (stand
    made up, block back to the top), ``slips_out_s``, ``ramp_s`` (rotation
    restarts and ramps to the set rpm), ``tag_s`` (back to bottom). Defaults:
    a 2-3 minute connection of an offshore rig with a pipe-handling system.
    """

    enabled: bool = False
    stand_length_m: float = Field(DEFAULT_STAND_LENGTH_M, gt=0.0, le=60.0)
    pickup_m: float = Field(1.0, ge=0.0, le=20.0)
    pickup_s: float = Field(10.0, ge=0.0, le=600.0)
    rotation_stop_s: float = Field(10.0, ge=0.0, le=600.0)
    slips_s: float = Field(10.0, ge=0.0, le=600.0)
    stand_s: float = Field(90.0, gt=0.0, le=3600.0)
    slips_out_s: float = Field(10.0, ge=0.0, le=600.0)
    ramp_s: float = Field(20.0, ge=0.0, le=600.0)
    tag_s: float = Field(10.0, ge=0.0, le=600.0)

    @property
    def duration_s(self) -> float:
        """Total duration of one connection, s."""
        return (self.pickup_s + self.rotation_stop_s + self.slips_s + self.stand_s + self.slips_out_s
                + self.ramp_s + self.tag_s)


BlockMode = Literal["autodriller", "rop", "held", "trip"]


class RigConfig(StrictModel):
    """Settings of the ``rig`` section. Units: SI unless the field name says otherwise.

    Attributes
    ----------
    block_mode : {"autodriller", "rop", "held", "trip"}
        What moves the block: the autodriller on WOB (default), an ROP
        set-point, nothing (held), or a trip at a block speed.
    rop_set_m_per_s : float or None
        ``rop`` only: the block lowering speed, m/s (> 0).
    trip_speed_m_per_s : float or None
        ``trip`` only: block speed, > 0 running in, < 0 pulling out, m/s.
    block, autodriller, top_drive, rock, connection
        Sub-sections; ``autodriller`` is an error with a mode other than
        ``autodriller``, ``connection.enabled`` with ``held``.
    """

    block_mode: BlockMode = "autodriller"
    rop_set_m_per_s: float | None = Field(None, gt=0.0, le=5.0)
    trip_speed_m_per_s: float | None = Field(None, ge=-5.0, le=5.0)
    block: BlockConfig = Field(default_factory=BlockConfig)
    autodriller: AutodrillerConfig | None = None
    top_drive: TopDriveConfig = Field(default_factory=TopDriveConfig)
    rock: RockConfig = Field(default_factory=RockConfig)
    connection: ConnectionConfig = Field(default_factory=ConnectionConfig)

    @model_validator(mode="after")
    def _check(self) -> RigConfig:
        m = self.block_mode
        if self.rop_set_m_per_s is not None and m != "rop":
            raise ValueError(f"rop_set_m_per_s: not used by block_mode {m} "
                             "(allowed: only with block_mode rop)")
        if self.trip_speed_m_per_s is not None and m != "trip":
            raise ValueError(f"trip_speed_m_per_s: not used by block_mode {m} "
                             "(allowed: only with block_mode trip)")
        if self.autodriller is not None and m != "autodriller":
            raise ValueError(f"autodriller: not used by block_mode {m} "
                             "(allowed: only with block_mode autodriller)")
        if m == "rop" and self.rop_set_m_per_s is None:
            raise ValueError("rop_set_m_per_s: block_mode rop needs a set-point "
                             "(allowed: 0 < rop_set_m_per_s)")
        if m == "trip" and not self.trip_speed_m_per_s:
            raise ValueError("trip_speed_m_per_s: block_mode trip needs a non-zero block speed "
                             "(allowed: > 0 running in, < 0 pulling out)")
        if m == "held" and self.connection.enabled:
            raise ValueError("connection: a held block never reaches the floor "
                             "(allowed: connection.enabled false with block_mode held)")
        con = self.connection
        if con.enabled and con.stand_length_m + con.pickup_m > self.block.travel_m:
            raise ValueError(f"connection: a stand of {con.stand_length_m} m plus the pick-up "
                             f"{con.pickup_m} m does not fit the block travel {self.block.travel_m} m "
                             "(allowed: stand_length_m + pickup_m <= block.travel_m)")
        vmax = self.block.max_speed_m_per_s
        for name, v in (("rop_set_m_per_s", self.rop_set_m_per_s),
                        ("trip_speed_m_per_s", self.trip_speed_m_per_s)):
            if v is not None and abs(v) > vmax:
                raise ValueError(f"{name}: block speed {abs(v)} m/s is above the block speed limit "
                                 f"{vmax} m/s (allowed: |{name}| <= block.max_speed_m_per_s)")
        ad = self.effective_autodriller
        if m == "autodriller" and ad.rop_limit_m_per_s > vmax:
            raise ValueError(f"autodriller: rop_limit_m_per_s {ad.rop_limit_m_per_s} m/s is above the "
                             f"block speed limit {vmax} m/s (allowed: <= block.max_speed_m_per_s)")
        return self

    @property
    def effective_autodriller(self) -> AutodrillerConfig:
        """The autodriller settings in use (the defaults if the section is absent)."""
        return self.autodriller if self.autodriller is not None else AutodrillerConfig()

    def effective_inputs(self) -> dict[str, Any]:
        """The inputs the chosen modes use, for ``summary.json`` (SI, field names as in the config)."""
        out: dict[str, Any] = {"block_mode": self.block_mode, "block": self.block.model_dump()}
        if self.block_mode == "autodriller":
            out["autodriller"] = self.effective_autodriller.model_dump()
        elif self.block_mode == "rop":
            out["rop_set_m_per_s"] = self.rop_set_m_per_s
        elif self.block_mode == "trip":
            out["trip_speed_m_per_s"] = self.trip_speed_m_per_s
        td = self.top_drive
        out["top_drive"] = {"tuning": td.tuning}
        if td.tuning != "stiff":
            out["top_drive"].update(inertia_kg_m2=td.inertia_kg_m2, gear_ratio=td.gear_ratio,
                                    torque_limit_Nm=td.torque_limit_Nm)
        if td.tuning == "pi":
            out["top_drive"].update(kp_Nm_s_per_rad=td.kp_Nm_s_per_rad, ki_Nm_per_rad=td.ki_Nm_per_rad)
        out["rock"] = self.rock.model_dump()
        if self.connection.enabled:
            out["connection"] = self.connection.model_dump()
        return out


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
    this string (criterion of :mod:`drillfatigue.dynamics.rig`), a connection
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
        ``omega_c_rad_s``, ``phase_margin_rad``, ``delay_s`` of the autodriller loop
        (empty without an autodriller), for ``summary.json``.
    """
    from drillfatigue.dynamics.rig import autodriller_delay_s, autodriller_loop

    window = case.operation.duration_s
    if rig.connection.enabled and rig.connection.duration_s > window:
        raise InputError("rig.connection", f"one connection takes {rig.connection.duration_s:.0f} s, "
                         f"longer than the window operation.duration_s = {window:.0f} s",
                         "connection duration <= operation.duration_s")
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


# --- packing for the kernels -------------------------------------------------------------


def _string_span(case: CaseConfig) -> tuple[Any, np.ndarray]:
    """Segments (bit first) and their lengths extended/cut to the span top -> bit."""
    from drillfatigue.string import build_segments

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
    from scipy.linalg import eigh_tridiagonal

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
    """Block mode id and parameter vector for :func:`drillfatigue.dynamics.rig.block_step`.

    ``hook_off_N`` is the autodriller's zero (the rotating off-bottom hook load,
    measured or from the soft-string model); used by ``measurement: hook_load``.
    """
    from drillfatigue.dynamics import rig as R

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
    from drillfatigue.dynamics import rig as R

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
