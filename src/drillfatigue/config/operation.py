"""``operation`` section of params.yaml: what the rig does (docs/model.md#top-boundary, docs/model.md#bit).

Top: rotary speed profile (ramp then hold, or a table) and an axial condition,
either a given hook load, a hook load solved so that the neutral point sits at a
chosen distance from the bit (default: the top of the collars), or the top held
at a fixed position (off-bottom checks, natural frequencies). Bit: on bottom
(guided along the well path at the ROP, with lobed axial motion
s0 sin(n phi_bit) and a given torque on bit) or off bottom (free).
"""

from __future__ import annotations

from typing import Literal

from pydantic import Field, model_validator

from drillfatigue.config.base import StrictModel
from drillfatigue.limits import FEATURE_BOUNDS


class OperationConfig(StrictModel):
    """Settings of the ``operation`` section. Units: SI unless the field name says otherwise."""

    duration_s: float = Field(10.0, gt=0.0, le=1e6)
    bit_md_m: float = Field(1000.0, gt=0.0, le=20000.0,
                            description="measured depth of the bit at t = 0")
    top_md_m: float = Field(0.0, ge=0.0, le=20000.0,
                            description="MD of the top of the string (the rig floor) at t = 0")
    # rotary speed at the top
    rpm: float = Field(120.0, ge=-400.0, le=400.0, description="held top-drive speed")
    rpm_ramp_s: float = Field(5.0, ge=0.0, le=1e5, description="linear ramp 0 -> rpm")
    rpm_table: list[tuple[float, float]] | None = Field(
        None, description="[[time_s, rpm], ...] piecewise linear; overrides rpm/ramp")
    # axial condition at the top
    top_axial: Literal["hook_load", "neutral_point", "fixed"] = "neutral_point"
    hook_load_N: float = Field(0.0, ge=0.0, le=1e8)
    neutral_point_s_from_bit_m: float | None = Field(
        None, gt=0.0, le=20000.0, description="default: the top of the collars")
    trip_speed_m_per_s: float = Field(0.0, ge=-10.0, le=10.0,
                                      description="string length change rate off bottom: "
                                                  "> 0 tripping in, < 0 tripping out")
    top_mode: Literal["rpm", "torque"] = Field(
        "rpm", description="rpm: the top drive imposes the speed profile; torque: a constant "
                           "torque top_torque_Nm (ramped over rpm_ramp_s) drives a free top")
    top_torque_Nm: float = Field(0.0, ge=-1e6, le=1e6, description="applied top torque, torque mode")
    top_lateral: Literal["held", "free"] = Field(
        "held", description="held: stiff lateral/tilt springs at the top; free: none")
    # bit
    bit_on_bottom: bool = True
    rop_m_per_s: float = Field(0.0, ge=0.0, le=1.0)
    wob_N: float | None = Field(
        None, gt=0.0, le=FEATURE_BOUNDS["wob_N"].hi,
        description="weight-on-bit set-point, N: the driller's control. It "
        "is the autodriller's rig.autodriller.wob_set_N; the sweep's rig boundaries move it "
        "there (a simulated case gives it in the rig section)")
    tob_Nm: float = Field(0.0, ge=-1e6, le=1e6, description="given torque on bit (bit_on_bottom)")
    lobe_count: int = Field(3, ge=0, le=20)
    lobe_amplitude_m: float = Field(0.0, ge=0.0, le=0.05)
    # mud
    mud_density_kg_per_m3: float = Field(1200.0, ge=0.0, le=3000.0)
    mud_damping_lateral_N_s_per_m2: float = Field(
        50.0, ge=0.0, le=1e6, description="lateral viscous drag per unit length")
    mud_damping_axial_N_s_per_m2: float = Field(5.0, ge=0.0, le=1e6)
    # Aarsnes & Shor's field fit (k_t = 50 on their paper's 500-cell grid of 5 7/8 in
    # pipe, J. Petrol. Sci. Eng. 163 (2018)) is 0.032 per m (docs/rig.md)
    mud_damping_torsional_N_m_s_per_m: float = Field(
        0.03, ge=0.0, le=1e4, description="torsional viscous drag per unit length, N m s/rad per m")

    @model_validator(mode="after")
    def _check(self) -> OperationConfig:
        if self.top_md_m >= self.bit_md_m:
            raise ValueError(f"top_md_m must be < bit_md_m, got {self.top_md_m} >= {self.bit_md_m} "
                             "(allowed: 0 <= top_md_m < bit_md_m)")
        if self.rpm_table is not None:
            times = [t for t, _ in self.rpm_table]
            if len(times) < 1 or any(b <= a for a, b in zip(times, times[1:], strict=False)):
                raise ValueError("rpm_table times must increase strictly "
                                 "(allowed: [[t0, rpm0], [t1, rpm1], ...] with t0 < t1 < ...)")
            if any(abs(r) > 400.0 for _, r in self.rpm_table):
                raise ValueError("rpm_table speeds must be within +-400 (allowed: -400 <= rpm <= 400)")
        if self.top_axial == "neutral_point" and not self.bit_on_bottom:
            raise ValueError("an off-bottom string has no neutral point to place "
                             "(allowed: top_axial fixed or hook_load when bit_on_bottom is false)")
        if self.trip_speed_m_per_s != 0.0 and (self.bit_on_bottom or self.top_axial != "fixed"):
            raise ValueError("tripping needs the bit off bottom and the top fixed "
                             "(allowed: trip_speed_m_per_s != 0 with bit_on_bottom false and "
                             "top_axial fixed)")
        return self
