"""DVC stage ``heldout``: the held-out test design, simulated, evaluated and assembled apart.

Reads the ``heldout`` section (size, seed, folders), the ``sweep`` section
(ranges, base case, boundaries, window rule, criteria, scheduler) and the
training design ``sweep.cases_path`` (its cases are left out of the test
design); writes ``data/heldout/design/cases.parquet``, ``data/heldout/sweep/``,
``data/heldout/fatigue/`` and ``data/heldout/dataset/`` (``damage.parquet``,
card, metrics) with the same code as the training stages. Resumable: finished
cases are skipped. Exit code 1 when more than ``sweep.failure_threshold`` of
the cases fail, 2 on bad input.

Usage: ``python pipeline/heldout.py [--params params.yaml] [--no-progress]``
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
from drillfatigue.sweep.stages import heldout_stage  # noqa: E402


def heldout(params: Params, args: Namespace) -> str:
    metrics = heldout_stage(params, progress=not args.no_progress)
    return (f"heldout: {metrics['n_rows']} rows from {metrics['n_cases_in_dataset']} cases "
            f"({metrics['n_cases_shared_with_training_dropped']} shared with training left out)")


def main(argv: list[str] | None = None) -> int:
    return stage_main(__doc__, heldout, [NO_PROGRESS], argv)


if __name__ == "__main__":
    sys.exit(main())
