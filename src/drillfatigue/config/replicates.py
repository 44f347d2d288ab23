"""``replicates`` section of params.yaml: the noise floor of the simulated damage.

The ``replicates`` stage re-simulates the first ``n_cases`` designed cases
``n_replicates - 1`` more times, each with ``variable`` scaled by
``1 + k * rel_step`` (k = 1, 2, ...), a change below what a rig's setting
resolves (the default 1e-2 of 120 rpm is 1.2 rpm). The spread of log10
damage rate across these replicates is what no estimator can predict from
the operating conditions: drill-string dynamics with contact and friction
settles into different states (stick-slip, whirl, bit bounce) for inputs
that close, so it bounds the accuracy any surrogate can reach on the same
data (:mod:`drillfatigue.sweep.replicates`). A step of 1e-4 keeps the runs
on one trajectory for most cases and measures only how reproducible that
trajectory is (docs/surrogate.md#what-limits-it).
"""

from __future__ import annotations

from pydantic import Field, field_validator, model_validator

from drillfatigue.config.base import StrictModel
from drillfatigue.config.sweep import check_path


class ReplicatesConfig(StrictModel):
    """Settings of the ``replicates`` section (noise-floor study).

    Attributes
    ----------
    n_cases : int
        Designed cases replicated (the first ones of the design, whose
        scrambled-Sobol points cover the whole space), 0 to skip the study.
    n_replicates : int
        Runs per case including the design run itself (>= 2).
    variable : str
        Dotted case path of the numeric field perturbed (default
        ``operation.rpm``).
    rel_step : float
        Relative perturbation step, dimensionless: replicate k runs with the
        field times ``1 + k * rel_step``.
    symmetric : bool
        Alternate the sign instead: replicates 1, 2, 3, 4, ... run at
        ``1 + rel_step``, ``1 - rel_step``, ``1 + 2 rel_step``, ``1 - 2
        rel_step``, ..., so the runs centre on the design value (their mean
        estimates the rate at it, not at a shifted value).
    out_dir : str
        Folder of the replicate runs, their fatigue and ``spread.json``.
    """

    n_cases: int = Field(8, ge=0, le=100_000)
    n_replicates: int = Field(4, ge=2, le=100)
    variable: str = "operation.rpm"
    rel_step: float = Field(1e-2, gt=0.0, le=0.1)
    symmetric: bool = False
    out_dir: str = Field("data/replicates", min_length=1)

    @field_validator("variable")
    @classmethod
    def _path(cls, v: str) -> str:
        return check_path(v)

    @model_validator(mode="after")
    def _positive(self) -> ReplicatesConfig:
        # the lowest symmetric replicate scales the field by 1 - m rel_step
        m = (self.n_replicates - 1) // 2
        if self.symmetric and m * self.rel_step >= 1.0:
            raise ValueError(f"symmetric replicates down to 1 - {m} x {self.rel_step} would not "
                             f"keep the field's sign (rel_step < {1.0 / m:.3g} for "
                             f"{self.n_replicates} replicates)")
        return self
