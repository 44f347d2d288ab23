"""``solver`` section of params.yaml: integration and numerical stiffness.

The integrator is explicit velocity Verlet with a fixed step set by the
stiffest element (see :mod:`drillfatigue.dynamics.step.integrator`).
"""

from __future__ import annotations

from pydantic import Field

from drillfatigue.config.base import StrictModel


class SolverConfig(StrictModel):
    """Settings of the ``solver`` section. Units: SI unless the field name says otherwise."""

    dt_s: float | None = Field(None, gt=0.0, le=0.01,
                               description="fixed step; default: safety x stable step")
    safety_factor: float = Field(0.5, gt=0.0, le=0.95,
                                 description="fraction of the stable step 2/omega_max")
    joint_damping_ratio: float = Field(0.02, ge=0.0, le=1.0,
                                       description="zeta of every joint spring, c = 2 zeta sqrt(k m)")
    boundary_damping_ratio: float = Field(0.3, ge=0.0, le=2.0,
                                          description="zeta of the top/bit boundary springs")
    top_axial_stiffness_N_per_m: float | None = Field(None, gt=0.0, le=1e13)
    top_torsional_stiffness_N_m_per_rad: float | None = Field(None, gt=0.0, le=1e12)
    parasitic_stiffness_scale: float = Field(1.0, gt=0.0, le=100.0,
                                             description="top lateral/tilt springs vs the joint springs")
    chunk_steps: int = Field(2000, ge=1, le=10_000_000, description="steps per kernel call")
    checkpoint_every_s: float = Field(0.0, ge=0.0, le=1e6, description="0 = no checkpoints")
    max_segments: int | None = Field(None, ge=1, le=100_000,
                                     description="cap on the rows allocated for drilling growth")
    relax_s: float = Field(0.0, ge=0.0, le=1e4,
                           description="damped pre-run settling the string in the hole before t = 0")
    energy_blowup_factor: float = Field(1e3, gt=1.0, le=1e12,
                                        description="divergence when energy exceeds this x its scale")
    growth_work_trapezoid: bool = Field(
        True, description="book the work of the string's growth (drilling, tripping) with the "
                          "trapezoid of the axial force below the top over the step, as the "
                          "integrator's kicks see it (docs/rig.md#in-the-simulator); false: the "
                          "force at the end of the step only, an O(dt) error in the energy "
                          "balance (always on with a rig section)")
    implicit_bit_torque: bool = Field(
        False, description="take the bit law's own damping of the bit's spin (its slope "
                           "dTOB/domega near zero speed) linearly implicit, so the step is not "
                           "limited by 2 I_bit / (dTOB/domega), which the stable-step estimate "
                           "does not count (docs/performance.md#the-bit-torque-and-the-step)")
