"""DVC stage ``simulate``: run every designed case in parallel, resumably.

Reads ``data/design/cases.parquet`` and the ``sweep`` section (scheduler,
workers, retries, failure threshold); writes ``data/sweep/<case_id>/`` per
finished case (loads, joints, channels, summary, DONE marker),
``data/sweep/failures.parquet`` and ``data/sweep/sweep.json``. A rerun after
a kill finishes only the missing cases (declare the output ``persist: true``
so DVC keeps it). Exit code 1 when more than ``sweep.failure_threshold`` of
the cases fail, 2 on bad input.

Usage: ``python pipeline/simulate.py [--params params.yaml] [--cases PATH] [--out DIR]
[--scheduler S] [--n-workers N] [--no-progress] [--metrics JSON]``
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
from drillfatigue.stage import SWEEP_OPTIONS, Option, stage_main  # noqa: E402
from drillfatigue.sweep.stages import simulate_stage, write_report  # noqa: E402


OPTIONS = (Option("--cases", help="default: sweep.cases_path"),
           Option("--out", help="default: sweep.sweep_dir"), *SWEEP_OPTIONS)


def simulate(params: Params, args: Namespace) -> str:
    report = simulate_stage(params, cases_path=args.cases, sweep_dir=args.out,
                            scheduler=args.scheduler, n_workers=args.n_workers,
                            progress=not args.no_progress)
    if args.metrics:
        write_report(report, args.metrics)
    return (f"simulate: {report.n_done} done, {report.n_skipped} already done, "
            f"{report.n_failed} failed, {report.wall_s:.1f} s")


def main(argv: list[str] | None = None) -> int:
    return stage_main(__doc__, simulate, OPTIONS, argv)


if __name__ == "__main__":
    sys.exit(main())
