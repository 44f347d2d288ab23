"""Case design, the parallel resumable sweep engine and dataset assembly.

- :mod:`~drillfatigue.sweep.design`: Sobol / Latin-hypercube case tables with stable ids.
- :mod:`~drillfatigue.sweep.runner`: :func:`run_sweep` on a process pool or Dask.
- :mod:`~drillfatigue.sweep.cases`: the per-case functions (simulate, fatigue).
- :mod:`~drillfatigue.sweep.dataset`: ``damage.parquet``, dataset card, history export.
"""

from __future__ import annotations

from drillfatigue.sweep.design import design_cases, read_cases, write_cases
from drillfatigue.sweep.runner import (Case, SweepFailedError, SweepReport, cases_from_frame,
                                       run_sweep)

__all__ = [
    "Case",
    "SweepFailedError",
    "SweepReport",
    "cases_from_frame",
    "design_cases",
    "read_cases",
    "run_sweep",
    "write_cases",
]
