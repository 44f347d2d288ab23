"""DVC stage ``heldout_draws``: each held-out case run again at rpm moved by a fraction of a percent.

Runs every held-out case ``heldout.draws - 1`` more times with rpm x (1 +- k
``heldout.draw_rel_step``), alternating in sign (the held-out run itself is
draw 0), with the sweep's window rule, scheduler and retries
(:func:`drillfatigue.sweep.replicates.heldout_draws_stage`). Writes
``<heldout.draws_dir>/spread.parquet`` (every draw's damage rate per case,
joint and location), ``spread.json`` (the draws' spread) and the runs under
``sweep`` and ``fatigue`` there (resumable). ``evaluate --draws`` scores the
held-out rows against the mean rate of each case's draws. With
``heldout.draws: 1`` it runs nothing and writes empty tables. Exit code 1 when
more than ``sweep.failure_threshold`` of the runs fail, 2 on bad input.

Usage: ``python pipeline/heldout_draws.py [--params params.yaml] [--no-progress]``
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
from drillfatigue.sweep.replicates import heldout_draws_stage  # noqa: E402


def heldout_draws(params: Params, args: Namespace) -> str:
    result = heldout_draws_stage(params, progress=not args.no_progress)
    return (f"heldout draws: {result['n_cases']} cases x {result['n_replicates']} runs, "
            f"sigma {result['sigma_log10']:.3f} decades")


def main(argv: list[str] | None = None) -> int:
    return stage_main(__doc__, heldout_draws, [NO_PROGRESS], argv)


if __name__ == "__main__":
    sys.exit(main())
