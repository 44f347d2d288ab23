"""``case1``, ``case2``, ``case3``, ``plan`` and ``report`` sections: the paper's case studies.

Each section configures one study of :mod:`drillfatigue.studies` (docs/model.md#case-studies).
Defaults are REDUCED versions that run in a few minutes on two cores; the
paper-scale values are given in each field's description and collected in
``params.yaml`` (comment block above ``case1``) and ``data/report/README.md``.

Reductions (documented, all switchable back to the paper's settings):

* case 2: instead of one continuous 800 s window (bit 480 -> 880 m at
  0.5 m/s), ``n_samples`` short windows of ``sample_s`` seconds at bit depths
  spread evenly over 480 -> 880 m; the damage of each short window is scaled to
  the share of the 800 s it stands for (quasi-stationary sampling of the
  drilling window). Coarser string (``dp_segments``, ``dc_segments``).
* case 3: a short rest (``trip_s``), a short ramp (``ramp_s``) and a short
  window (``window_s``) instead of 800 s / 40 s / 60 s; drill pipe in
  ``string.dp_segments`` equal segments instead of cut at its joints.
* case 1: a shorter run (``duration_s``).
"""

from __future__ import annotations

from typing import Literal

from pydantic import Field, model_validator

from drillfatigue.config.base import StrictModel
from drillfatigue.config.well import TortuosityConfig
from drillfatigue.limits import FEATURE_BOUNDS

_MD_MAX = 20000.0


class StringSpec(StrictModel):
    """The case-2/3 string: drill collars at the bit, drill pipe above (docs/model.md#bodies sizes)."""

    dc_length_m: float = Field(180.0, gt=0.0, le=2000.0, description="collar length, m")
    dc_segments: int = Field(9, ge=1, le=1000, description="collar segments (paper: 20)")
    dp_segments: int = Field(20, ge=1, le=5000, description="drill-pipe segments (paper: 100)")


class Case1Config(StrictModel):
    """Whirl of a 5 m pipe in a horizontal hole (paper case 1).

    Four runs: ``models`` x (``mu_low``, ``mu_high``), on the named case
    ``data/cases/case1_whirl.yaml`` (its measured behaviour: mu 0.7 whirls
    backward, 0.08 climbs and slides back). ``duration_s`` paper-scale: not
    stated in the paper; 20 s here.
    """

    models: tuple[Literal["karnopp", "tanh_exp", "tanh", "coulomb", "benson_hallquist",
                          "velocity_trig"], ...] = Field(("karnopp", "tanh_exp"), min_length=1)
    mu_low: float = Field(0.08, ge=0.0, le=1.5, description="low dynamic friction coefficient")
    mu_high: float = Field(0.7, ge=0.0, le=1.5, description="high dynamic friction coefficient")
    static_over_dynamic: float = Field(1.15, ge=1.0, le=3.0, description="mu_static / mu_dynamic")
    pipe_length_m: float = Field(5.0, gt=0.0, le=100.0)
    n_segments: int = Field(5, ge=2, le=200)
    top_torque_Nm: float = Field(200.0, gt=0.0, le=1e6, description="constant top torque")
    duration_s: float = Field(2.0, gt=0.0, le=1e4, description="paper-scale: 20")
    kinematics_rate_hz: float = Field(200.0, gt=0.0, le=1e5)

    @model_validator(mode="after")
    def _check(self) -> Case1Config:
        if self.mu_low >= self.mu_high:
            raise ValueError(f"mu_low must be < mu_high, got {self.mu_low} >= {self.mu_high} "
                             "(allowed: 0 <= mu_low < mu_high <= 1.5)")
        return self


class Case2Config(StrictModel):
    """Three profiles, same start and end (paper case 2).

    Reduced default: one continuous 40 s drilling window per profile with the
    rig boundaries (autodriller on WOB). Paper scale: ``sample_s: 810,
    settle_s: 10, string.dc_segments: 20, string.dp_segments: 100`` (one
    continuous 800 s window after the start-up).

    ``tortuosity``: as ``case3.tortuosity``: every profile runs again in its plan
    with this tortuosity, and the lives and order of the tortuous holes are
    reported beside the plans'. ``null``: the plans only.
    """

    profiles: tuple[str, ...] = Field(("profile_1", "profile_2", "profile_3"), min_length=1)
    bit_md_start_m: float = Field(480.0, gt=0.0, le=_MD_MAX)
    bit_md_end_m: float = Field(880.0, gt=0.0, le=_MD_MAX)
    rpm: float = Field(150.0, gt=0.0, le=400.0)
    rop_m_per_s: float = Field(0.5, gt=0.0, le=1.0)
    lobe_amplitude_m: float = Field(0.001, ge=0.0, le=0.05,
                                    description="lobed axial bit motion (docs/model.md#bit: ~1 mm)")
    n_samples: int = Field(1, ge=1, le=1000, description="drilling windows along the 800 s")
    sample_s: float = Field(40.0, gt=0.0, le=1e5,
                            description="simulated length of each window; paper scale 810")
    settle_s: float = Field(2.0, ge=0.0, le=1e4,
                            description="start of the recorded part of each window (ramp, "
                                        "transient); paper-scale 0")
    rpm_ramp_s: float = Field(1.0, ge=0.0, le=1e4, description="paper-scale: 5")
    relax_s: float = Field(0.5, ge=0.0, le=1e3, description="damped settling before t = 0")
    safety_factor: float = Field(0.5, gt=0.0, le=0.95,
                                 description="solver.safety_factor (fraction of the stable step)")
    implicit_bit_torque: bool = Field(
        True, description="solver.implicit_bit_torque: the bit law's damping of the bit's spin "
                          "taken linearly implicit, so a safety factor of 0.85 keeps the "
                          "bit's spin as accurate as 0.5 (docs/performance.md); the plan "
                          "stage's confirmation windows keep the explicit bit torque")
    target_s_from_bit_m: float = Field(40.0, gt=0.0, le=5000.0,
                                       description="joint whose loads are reported")
    string: StringSpec = Field(default_factory=StringSpec)
    loads_rate_hz: float = Field(100.0, gt=0.0, le=1e5)
    criterion: Literal["matake", "findley", "fatemi_socie", "uniaxial"] = "matake"
    boundaries: Literal["rig", "rig_rop", "prescribed_rop"] = Field(
        "rig", description="rig: the autodriller holds wob_set_N and the bit law gives the ROP "
                           "(docs/rig.md); rig_rop: the autodriller drills at rop_m_per_s (its "
                           "ROP limit) unless the WOB reaches wob_set_N first, as the sweep "
                           "drills, and the bit cuts what the bit law lets it; prescribed_rop: the "
                           "bit guided at rop_m_per_s "
                           "(validation of the founding paper's set-up)")
    wob_set_N: float = Field(100e3, gt=0.0, le=FEATURE_BOUNDS["wob_set_N"].hi,
                             description="autodriller WOB set-point (rig)")
    autodriller_measurement: Literal["wob", "hook_load"] = Field(
        "wob", description="what the autodriller measures (rig)")
    block_initial_travel_m: float = Field(
        5.0, ge=0.0, le=60.0, description="block position at t = 0 below the top of its "
                                           "travel (rig): room to pick up while the "
                                           "autodriller settles")
    metrics_skip_s: float = Field(10.0, ge=0.0, le=1e4,
                                  description="start-up left out of the drilling metrics (rig)")
    tortuosity: TortuosityConfig | None = Field(
        default_factory=lambda: TortuosityConfig(model="sine", amplitude_deg=0.5,
                                                 period_m=30.0),
        description="well.tortuosity of a second run of every profile (the plan with "
                    "micro-doglegs, as case3.tortuosity); null: the plans only")

    @model_validator(mode="after")
    def _check(self) -> Case2Config:
        if self.bit_md_end_m <= self.bit_md_start_m:
            raise ValueError("bit_md_end_m must exceed bit_md_start_m "
                             f"(allowed: > {self.bit_md_start_m})")
        if self.settle_s >= self.sample_s:
            raise ValueError(f"settle_s ({self.settle_s}) must be < sample_s ({self.sample_s}) "
                             "(allowed: 0 <= settle_s < sample_s)")
        if self.target_s_from_bit_m >= self.bit_md_start_m:
            raise ValueError("target_s_from_bit_m must lie on the string "
                             f"(allowed: < bit_md_start_m = {self.bit_md_start_m})")
        return self

    @property
    def window_s(self) -> float:
        """The drilling window the paper's life is counted in, s (800 s by default): the
        paper's drilled length at its ROP; with ``boundaries: rig`` the bit drills what
        the autodriller's weight lets it, and the life stays counted in this window."""
        return (self.bit_md_end_m - self.bit_md_start_m) / self.rop_m_per_s


class Case3Config(StrictModel):
    """Horizontal section of profile 1 (paper case 3).

    ``mode: rig`` (default, the paper's sequence with the bit on bottom): the
    string in the hole with the bit on bottom at ``bit_md_end_m`` (the trip's end
    state: a run cannot switch the block from tripping to the autodriller), at rest
    for ``trip_s``, the rpm ramped to ``rpm`` over ``ramp_s``, then the recorded
    window of ``window_s``; the rig boundaries of case 2 (autodriller on WOB, bit
    law ROP, lobed rock face). String ``bha``: the ``paper_bha`` preset (collars
    with a near-bit and a string stabilizer) with drill pipe up to the bit depth,
    cut at its joints (``dp_joints_per_segment``) or into ``string.dp_segments``
    equal segments; ``bare_collars``: ``string``'s collars and drill pipe. Bending
    between supports: ``contact_points``, ``span_bending``, ``lateral_mud_mass``
    (docs/bending.md), on.

    Paper scale: ``ramp_s: 40, window_s: 60`` (the trip of 800 s is the
    string's placement; ``trip_s`` is the rest before the ramp).

    ``tortuosity``: a ``well.tortuosity`` block (docs/wells.md#tortuosity); the case
    then runs twice, in the well section's hole (the plan) and in the same hole with
    this tortuosity, and reports both beside the paper's lives. Default: a sine of
    0.5 deg over 30 m in the inclination plane from the surface, the "2 deg/30 m"
    tortuosity torque-and-drag practice adds to a plan (4 A / P; peak 3.1 deg/30 m;
    docs/case3.md#tortuosity). ``null``: the plan only.
    """

    profile: str = "profile_1"
    mode: Literal["rig", "on_bottom", "tripping"] = Field(
        "rig", description="rig: bit on bottom, autodriller on WOB, bit-law ROP, lobed rock "
                           "face (docs/case3.md); on_bottom: prescribed ROP; tripping: off "
                           "bottom, the string slides in during the whole run")
    rop_m_per_s: float = Field(0.01, ge=0.0, le=1.0, description="on_bottom mode")
    bit_md_end_m: float = Field(900.0, gt=0.0, le=_MD_MAX,
                                description="bit MD at the end of the run (tripping, "
                                            "on_bottom) or at its start (rig)")
    trip_speed_m_per_s: float = Field(0.1, gt=0.0, le=2.0)
    trip_s: float = Field(1.0, ge=0.0, le=1e5,
                          description="tripping: the trip (paper 800); rig, on_bottom: at rest "
                                      "before the ramp (the trip is the string's placement)")
    ramp_s: float = Field(2.0, gt=0.0, le=1e4, description="ramp 0 -> rpm; paper 40")
    window_s: float = Field(10.0, gt=0.0, le=1e5, description="recorded window; paper 60")
    rpm: float = Field(50.0, gt=0.0, le=400.0)
    s_from_bit_m: tuple[float, ...] = Field((8.0, 40.0, 80.0), min_length=1)
    bha: Literal["paper_bha", "bare_collars"] = Field(
        "paper_bha", description="paper_bha: the preset's stabilized BHA (180 m); "
                                 "bare_collars: string.dc_length_m of collars")
    string: StringSpec = Field(default_factory=lambda: StringSpec(dc_segments=20, dp_segments=20))
    dp_joints_per_segment: int | None = Field(
        1, ge=1, le=10, description="paper_bha: drill pipe cut at its joints, this many per "
                                    "segment; null: string.dp_segments equal segments (with "
                                    "contact_points: string only in a straight hole: a long "
                                    "rigid segment's tool joints lie outside a build's wall)")
    contact_points: Literal["ends", "ends_and_middle", "string"] = Field(
        "string", description="contact.points: string = tool joints, stabilizers, collar "
                              "points by the chord rule")
    span_bending: bool = Field(True, description="contact.span_bending: bending of the "
                                                 "pipe's weight between its supports")
    lateral_mud_mass: bool = Field(True, description="string.lateral_mud_mass")
    wob_set_N: float = Field(100e3, gt=0.0, le=FEATURE_BOUNDS["wob_set_N"].hi,
                             description="autodriller set-point (rig)")
    autodriller_measurement: Literal["wob", "hook_load"] = "wob"
    block_initial_travel_m: float = Field(5.0, ge=0.0, le=60.0, description="rig")
    lobe_amplitude_m: float = Field(0.001, ge=0.0, le=0.05,
                                    description="lobed rock face (rig) or bit motion")
    loads_rate_hz: float = Field(100.0, gt=0.0, le=1e5)
    criterion: Literal["matake", "findley", "fatemi_socie", "uniaxial"] = "matake"
    tortuosity: TortuosityConfig | None = Field(
        default_factory=lambda: TortuosityConfig(model="sine", amplitude_deg=0.5,
                                                 period_m=30.0),
        description="well.tortuosity of the second run (the plan with micro-doglegs); "
                    "null: the plan only")

    @property
    def duration_s(self) -> float:
        """Simulated time: trip, ramp, window."""
        return self.trip_s + self.ramp_s + self.window_s

    @property
    def advance_m_per_s(self) -> float:
        """Bit advance rate the start depth is set back by, m/s: the ROP on bottom, the
        trip speed off bottom; 0 with the rig (the bit starts at ``bit_md_end_m`` and
        drills what the bit law gives, a few decimetres in a minute)."""
        if self.mode == "rig":
            return 0.0
        return self.rop_m_per_s if self.mode == "on_bottom" else self.trip_speed_m_per_s


class PlanConfig(StrictModel):
    """Defaults of ``drillfatigue plan rank`` (its options override them)."""

    surrogate_dir: str = Field("data/surrogate/model", min_length=1)
    confirm_top_k: int = Field(0, ge=0, le=50, description="simulator confirmation of the top k")
    out_dir: str = Field("data/plan", min_length=1)


class ReportConfig(StrictModel):
    """Report stage: where the study outputs are and where the README goes."""

    out_dir: str = Field("data/report", min_length=1)
    figure_dpi: int = Field(110, ge=50, le=600)


__all__ = ["Case1Config", "Case2Config", "Case3Config", "PlanConfig", "ReportConfig",
           "StringSpec"]
