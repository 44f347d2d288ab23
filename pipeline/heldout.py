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

import argparse
import sys

from drillfatigue.numba_cache import scope_numba_cache

# Before any kernel module is imported: numba binds a kernel's cache folder
# when the kernel is decorated, so a later call would leave the kernels
# imported above it in the unscoped in-tree cache (stale across modules).
scope_numba_cache()

from drillfatigue.config import load_params  # noqa: E402
from drillfatigue.errors import InputError  # noqa: E402
from drillfatigue.sweep.runner import SweepFailedError  # noqa: E402
from drillfatigue.sweep.stages import heldout_stage  # noqa: E402


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--params", default="params.yaml")
    parser.add_argument("--no-progress", action="store_true")
    args = parser.parse_args(argv)
    try:
        metrics = heldout_stage(load_params(args.params), progress=not args.no_progress)
    except InputError as exc:
        print(f"error: {exc.one_line()}", file=sys.stderr)
        return 2
    except SweepFailedError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 1
    print(f"heldout: {metrics['n_rows']} rows from {metrics['n_cases_in_dataset']} cases "
          f"({metrics['n_cases_shared_with_training_dropped']} shared with training left out)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
