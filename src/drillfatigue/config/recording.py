"""``recording`` section of params.yaml: what the simulator writes and how often."""

from __future__ import annotations

from pydantic import Field

from drillfatigue.config.base import StrictModel


class RecordingConfig(StrictModel):
    """Settings of the ``recording`` section. Units: SI unless the field name says otherwise."""

    loads_rate_hz: float = Field(200.0, gt=0.0, le=1e5)
    channels_rate_hz: float = Field(200.0, gt=0.0, le=1e5)
    kinematics_rate_hz: float = Field(10.0, gt=0.0, le=1e5)
    joints: list[int] | None = Field(None, description="joint indices from the bit; None = all")
    start_s: float = Field(0.0, ge=0.0, le=1e6, description="record from this simulated time")
    events_start_s: float | None = Field(
        None, ge=0.0, le=1e6,
        description="start of the event window (stick-slip, whirl, torque figures); "
                    "default: the end of the rpm ramp")
    detect_buckling: bool | None = Field(
        None, description="run the buckling detector on every kinematics sample and write its "
                          "sections to summary.json (docs/rig.md#buckling); default: on for a "
                          "case with a rig section in a hole with a wall")
