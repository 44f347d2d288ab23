"""Validated configuration: one strict model per ``params.yaml`` section.

``load_params(path)`` validates a whole ``params.yaml``; ``load_case(path)``
validates a standalone case file (the simulation sections only). Both raise
:class:`drillfatigue.errors.InputError` with a dotted field path on bad input.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

from pydantic import Field, model_validator

from drillfatigue.config.base import StrictModel, read_yaml, validate
from drillfatigue.config.bit import BitConfig
from drillfatigue.config.contact import ContactConfig
from drillfatigue.config.fatigue import FatigueConfig
from drillfatigue.config.friction import FrictionConfig
from drillfatigue.config.heldout import HeldoutConfig
from drillfatigue.config.operation import OperationConfig
from drillfatigue.config.recording import RecordingConfig
from drillfatigue.config.replicates import ReplicatesConfig
from drillfatigue.config.rig import RigConfig
from drillfatigue.config.solver import SolverConfig
from drillfatigue.config.string import StringConfig
from drillfatigue.config.studies import (
    Case1Config,
    Case2Config,
    Case3Config,
    PlanConfig,
    ReportConfig,
)
from drillfatigue.config.surrogate import SurrogateConfig
from drillfatigue.config.sweep import SweepConfig
from drillfatigue.config.well import WellConfig
from drillfatigue.errors import InputError

__all__ = [
    "BitConfig",
    "CaseConfig",
    "ContactConfig",
    "FatigueConfig",
    "FrictionConfig",
    "HeldoutConfig",
    "OperationConfig",
    "Params",
    "RecordingConfig",
    "ReplicatesConfig",
    "RigConfig",
    "SolverConfig",
    "StringConfig",
    "SurrogateConfig",
    "SweepConfig",
    "WellConfig",
    "load_case",
    "load_params",
    "load_params_requiring",
    "note_default_section",
    "validate",
]


class CaseConfig(StrictModel):
    """One simulation: well, string, operation and the physics/solver options."""

    well: WellConfig = Field(default_factory=WellConfig)
    string: StringConfig = Field(default_factory=StringConfig)
    operation: OperationConfig = Field(default_factory=OperationConfig)
    friction: FrictionConfig = Field(default_factory=FrictionConfig)
    contact: ContactConfig = Field(default_factory=ContactConfig)
    bit: BitConfig = Field(default_factory=BitConfig)
    solver: SolverConfig = Field(default_factory=SolverConfig)
    recording: RecordingConfig = Field(default_factory=RecordingConfig)
    fatigue: FatigueConfig = Field(default_factory=FatigueConfig)
    rig: RigConfig | None = Field(
        None, description="the rig's block, top drive and rock face drive the string "
                          "(docs/rig.md); absent: the operation section's top and bit conditions")

    @model_validator(mode="after")
    def _check_rig_inputs(self) -> CaseConfig:
        """With a ``rig`` section the block holds the string, the top drive turns it and the
        bit law gives the ROP: an ``operation`` input those replace is an error."""
        rig = self.rig
        op = self.operation
        if op.wob_N is not None:
            raise ValueError("operation.wob_N: the WOB set-point is the autodriller's (allowed: "
                             "rig.autodriller.wob_set_N with rig.block_mode autodriller; "
                             "operation.wob_N only as a sweep variable with sweep.boundaries rig, "
                             "which moves it there)")
        if rig is None:
            return self
        # given with a value other than its default (a written-out case.yaml lists
        # every field at its default: that is no input for the mode to ignore)
        given = {k for k in op.model_fields_set
                 if getattr(op, k) != type(op).model_fields[k].default}
        replaced = {
            "trip_speed_m_per_s": (op.trip_speed_m_per_s != 0.0, "the block moves the string",
                                   "0; rig.block_mode trip with rig.trip_speed_m_per_s"),
            "rop_m_per_s": (op.rop_m_per_s != 0.0, "the bit law gives the ROP",
                            "0; rig.block_mode rop for a block speed"),
            "hook_load_N": ("hook_load_N" in given, "the hook load is measured on the block",
                            "no hook_load_N with a rig section"),
            "top_axial": (op.top_axial == "hook_load", "the block holds the top of the string",
                          "neutral_point or fixed (the initial state) with a rig section"),
            "top_mode": (op.top_mode != "rpm", "the top drive turns the string",
                         "rpm; rig.top_drive for the drive's controller"),
            "tob_Nm": (op.tob_Nm != 0.0, "the bit law gives the torque on bit",
                       "0; the bit section"),
            "lobe_count": ("lobe_count" in given, "the lobed face is the rock's",
                           "rig.rock.lobe_count"),
            "lobe_amplitude_m": ("lobe_amplitude_m" in given, "the lobed face is the rock's",
                                 "rig.rock.lobe_amplitude_m"),
        }
        for name, (bad, why, allowed) in replaced.items():
            if bad:
                raise ValueError(f"operation.{name}: not used with the rig section ({why}) "
                                 f"(allowed: {allowed})")
        if op.bit_on_bottom and self.bit.model not in ("yigit_christoforou", "detournay"):
            raise ValueError(f"bit.model: {self.bit.model} prescribes the ROP or the torque; with "
                             "the rig section the bit cuts what the bit law lets it (allowed: "
                             "yigit_christoforou or detournay, or no rig section for "
                             "prescribed-ROP runs)")
        if rig.block_mode == "autodriller":
            if not op.bit_on_bottom:
                raise ValueError("rig.block_mode: the autodriller holds a weight on bit and needs "
                                 "the bit on bottom (allowed: operation.bit_on_bottom true, or "
                                 "block_mode held, rop or trip)")
            if op.neutral_point_s_from_bit_m is not None or op.top_axial != "neutral_point":
                raise ValueError("operation.top_axial: the autodriller starts at its WOB set-point "
                                 "(allowed: top_axial neutral_point without "
                                 "neutral_point_s_from_bit_m with block_mode autodriller)")
        if rig.block_mode == "rop" and op.bit_on_bottom and (
                op.neutral_point_s_from_bit_m is not None or op.top_axial != "neutral_point"):
            raise ValueError("operation.top_axial: a block lowering at its ROP set-point starts in "
                             "steady drilling, at the bit law's WOB for the set-point (allowed: "
                             "top_axial neutral_point without neutral_point_s_from_bit_m with "
                             "block_mode rop on bottom)")
        return self

    @model_validator(mode="after")
    def _check_recording_window(self) -> CaseConfig:
        """A record that starts at or after the end of the run holds nothing: the run would
        complete without loads and ``fatigue`` fail on the missing file."""
        start, end = self.recording.start_s, self.operation.duration_s
        if start >= end:
            raise ValueError(f"recording.start_s: {start:g} s is at or beyond the end of the "
                             f"run (operation.duration_s = {end:g} s): nothing would be "
                             "recorded (allowed: 0 <= start_s < operation.duration_s)")
        return self

    @model_validator(mode="after")
    def _check_hole_clears_string(self) -> CaseConfig:
        """Every component's contact radius must be smaller than the smallest hole radius."""
        r_hole = 0.5 * min(h.diameter_m for h in self.well.hole)
        for i, comp in enumerate(self.string.components):
            r_c = comp.outer_contact_radius_m
            if r_c >= r_hole:
                raise ValueError(
                    f"string.components[{i}]: contact radius {r_c:.4f} m does not fit the "
                    f"hole (smallest hole radius {r_hole:.4f} m) "
                    f"(allowed: contact radius < {r_hole:.4f} m)"
                )
        return self


class Params(CaseConfig):
    """The whole ``params.yaml``: the case sections plus pipeline sections."""

    sweep: SweepConfig = Field(default_factory=SweepConfig)
    surrogate: SurrogateConfig = Field(default_factory=SurrogateConfig)
    replicates: ReplicatesConfig = Field(default_factory=ReplicatesConfig)
    heldout: HeldoutConfig = Field(default_factory=HeldoutConfig)
    case1: Case1Config = Field(default_factory=Case1Config)
    case2: Case2Config = Field(default_factory=Case2Config)
    case3: Case3Config = Field(default_factory=Case3Config)
    plan: PlanConfig = Field(default_factory=PlanConfig)
    report: ReportConfig = Field(default_factory=ReportConfig)

    @model_validator(mode="after")
    def _check_recording_window(self) -> Params:
        """Not checked on the whole file: the sweep sets each case's duration
        (``sweep.window_s`` at ``sweep.window_path``) and every case is checked as it is
        assembled (:func:`drillfatigue.sweep.design.design_space`), as is the case
        ``simulate params.yaml`` runs (:func:`load_case`)."""
        return self


def load_params(path: str | Path = "params.yaml") -> Params:
    """Load and validate a ``params.yaml``."""
    return validate(Params, read_yaml(path))


def load_params_requiring(path: str | Path, section: str, command: str) -> Params:
    """:func:`load_params` for a command that needs ``section`` to be in the file.

    A params file without that section would silently run on the section's
    defaults (for ``sweep``: a design of cases nobody asked for); that is an
    InputError naming the file and the section.
    """
    data = read_yaml(path)
    if section not in data:
        raise InputError(str(path), f"has no {section!r} section, which {command} needs "
                         f"(without it every {section} setting would be a default)",
                         f"a params file with a {section} section (see params.yaml); "
                         f"write '{section}: {{}}' for the defaults")
    return validate(Params, data)


def note_default_section(path: str | Path, section: str) -> str | None:
    """A one-line note when the params file at ``path`` lacks ``section`` (its defaults
    apply wholesale), else None."""
    if section in read_yaml(path):
        return None
    return f"note: {path} has no {section!r} section; using its defaults"


#: Sections of params.yaml that configure the pipeline, not one simulation.
PIPELINE_SECTIONS = ("sweep", "surrogate", "replicates", "heldout", "case1", "case2", "case3", "plan",
                     "report")


def load_case(path: str | Path) -> CaseConfig:
    """Load and validate a standalone case YAML file.

    A whole ``params.yaml`` is accepted too: it is validated as :class:`Params`
    (so its pipeline sections are checked, not ignored) and its case sections
    form the case.
    """
    data = read_yaml(path)
    if isinstance(data, dict) and any(k in data for k in PIPELINE_SECTIONS):
        params = validate(Params, data)
        return CaseConfig.model_validate(params.model_dump(include=set(CaseConfig.model_fields)))
    return validate(CaseConfig, data)


def case_from_dict(data: dict[str, Any]) -> CaseConfig:
    """Validate a case given as a plain mapping (e.g. one row of a sweep)."""
    return validate(CaseConfig, data)
