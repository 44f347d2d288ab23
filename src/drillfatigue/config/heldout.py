"""``heldout`` section of params.yaml: a test design of its own seed, apart from training.

The ``heldout`` stage samples ``n_cases`` cases over the same ranges, base
case, boundaries and window rule as the ``sweep`` section, with its own
``seed``; cases that the training design also holds are left out, so no
case is shared. They are simulated, evaluated and assembled into a dataset
by the same code as the training sweep (:func:`drillfatigue.sweep.stages.heldout_stage`),
under their own folders. The evaluate stage reads ``<dataset_dir>/damage.parquet``.
"""

from __future__ import annotations

from pydantic import Field

from drillfatigue.config.base import StrictModel


class HeldoutConfig(StrictModel):
    """Settings of the ``heldout`` section.

    Attributes
    ----------
    n_cases : int
        Requested cases (a Sobol design rounds up to a power of two), 0 ... 1,000,000.
    seed : int
        Seed of the held-out design; a seed other than ``sweep.seed``.
    cases_path, sweep_dir, fatigue_dir, dataset_dir : str
        Where the held-out design, runs, fatigue results and dataset go.
    draws : int
        Runs per held-out case for the ``heldout_draws`` stage, the design
        run included (1: none more): the others at rpm x (1 +- k
        ``draw_rel_step``), alternating in sign, so the mean of a case's
        runs estimates the damage rate of its operating condition at a
        rig's rpm resolution (docs/surrogate.md#what-limits-it).
    draw_rel_step : float
        Relative rpm step of the draws, dimensionless.
    draws_dir : str
        Folder of the draws' runs, fatigue and ``spread.parquet``.
    """

    n_cases: int = Field(16, ge=1, le=1_000_000)
    seed: int = Field(20250101, ge=0, le=2**63 - 1)
    cases_path: str = Field("data/heldout/design/cases.parquet", min_length=1)
    sweep_dir: str = Field("data/heldout/sweep", min_length=1)
    fatigue_dir: str = Field("data/heldout/fatigue", min_length=1)
    dataset_dir: str = Field("data/heldout/dataset", min_length=1)
    draws: int = Field(1, ge=1, le=21)
    draw_rel_step: float = Field(1e-2, gt=0.0, le=0.1)
    draws_dir: str = Field("data/heldout/draws", min_length=1)
