"""DVC stage ``replicates``: the noise floor of the simulated damage.

Re-simulates the first ``replicates.n_cases`` designed cases
``replicates.n_replicates - 1`` more times with ``replicates.variable``
scaled by ``1 + k * replicates.rel_step`` and measures how far log10 damage
rate moves (:mod:`drillfatigue.sweep.replicates`). Writes
``<out_dir>/spread.json`` (pooled sigma in decades, the factor-of-2 and R^2
ceilings of any estimator on this data), ``spread.parquet``, and the replicate
runs under ``<out_dir>/sweep`` and ``<out_dir>/fatigue`` (resumable).
Exit code 1 when more than ``sweep.failure_threshold`` of the replicates
fail, 2 on bad input.

Usage: ``python pipeline/replicates.py [--params params.yaml] [--no-progress]``
"""

from __future__ import annotations

import sys
from argparse import Namespace

from drillfatigue.numba_cache import scope_numba_cache

# Before any kernel module is imported: numba binds a kernel's cache folder
# when the kernel is decorated, so a later call would leave the kernels
# imported above it in the unscoped in-tree cache (stale across modules).
scope_numba_cache()

from drillfatigue.config import Params  # noqa: E402
from drillfatigue.stage import NO_PROGRESS, stage_main  # noqa: E402
from drillfatigue.sweep.replicates import replicates_stage  # noqa: E402


def replicates(params: Params, args: Namespace) -> str:
    result = replicates_stage(params, progress=not args.no_progress)
    return (f"replicates: {result['n_cases']} cases x {result['n_replicates']} runs, "
            f"sigma {result['sigma_log10']:.3f} decades, factor-2 ceiling "
            f"{result['ceiling_factor2_fraction']:.3f}, R2 ceiling {result['ceiling_r2']:.3f}")


def main(argv: list[str] | None = None) -> int:
    return stage_main(__doc__, replicates, [NO_PROGRESS], argv)


if __name__ == "__main__":
    sys.exit(main())
