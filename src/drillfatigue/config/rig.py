"""``rig`` section: the travelling block, the autodriller, the top drive, the rock face, connections.

Kernels: :mod:`drillfatigue.dynamics.top.rig` (block, top drive, rock face) and
:mod:`drillfatigue.dynamics.top.connection` (connection event sequence). User
documentation with the basis of every default: ``docs/rig.md``.

Every mode uses only some inputs; an input given for a mode that cannot use it
is an error naming the mode (no silent overrides), and
:meth:`RigConfig.effective_inputs` lists what a mode does use (for
``summary.json``). Checks that need the string and the window (autodriller
loop stability, a connection longer than the window) are in
:func:`drillfatigue.dynamics.top.setup.check_rig_setup`, called before any
step is taken.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any, Literal

from pydantic import Field, model_validator

from drillfatigue.config.base import StrictModel
from drillfatigue.limits import FEATURE_BOUNDS
from drillfatigue.units import HOUR_S

if TYPE_CHECKING:
    pass

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
        default 1000 m string drops from 65 to 51 deg. Without it a ripple that reaches zero WOB (bit bounce)
        drives the
        command into its ROP limit at every lift-off, where the anti-windup freezes
        the integral, and the mean WOB settles below the set-point.
    """

    measurement: Literal["hook_load", "wob"] = "hook_load"
    wob_set_N: float = Field(100e3, gt=0.0, le=FEATURE_BOUNDS["wob_set_N"].hi)
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
        (:func:`drillfatigue.dynamics.top.rig.torsional_first_mode_rad_s`).
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
        segment's mass, 0..1. Default 0.2 (as the wall contact, docs/model.md#contact).
    lobe_count : int
        Lobes of the bottom-hole pattern per revolution. Default 3 (tricone
        pattern, docs/model.md#bit).
    lobe_amplitude_m : float
        Amplitude of the lobed face, m. Default 1 mm (docs/model.md#bit).
    """

    contact_stiffness_N_per_m: float | None = Field(None, ge=1e4, le=1e11)
    contact_damping_ratio: float = Field(0.2, ge=0.0, le=1.0)
    lobe_count: int = Field(3, ge=0, le=20)
    lobe_amplitude_m: float = Field(1e-3, ge=0.0, le=0.05)


class ConnectionConfig(StrictModel):
    """The connection sequence when the block reaches the floor (``drillfatigue.dynamics.top.connection``).

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
