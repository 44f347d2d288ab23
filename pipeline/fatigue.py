"""DVC stage ``fatigue``: evaluate fatigue damage of every simulated case, in parallel.

A separate stage (not folded into ``simulate``) so that changing the
``fatigue`` section (S-N curves, SCFs, criteria) re-evaluates damage without
re-simulating. Reads ``data/design/cases.parquet``, ``data/sweep/``, the
``fatigue`` section and ``sweep.fatigue_criteria``/``sweep.api_rp7g``; writes
``data/fatigue/<case_id>/damage.parquet`` (every criterion plus the API RP7G
rows), ``data/fatigue/failures.parquet`` and ``data/fatigue/sweep.json``.
Resumable like ``simulate``: a case is re-evaluated only when its run or the
fatigue settings changed.

Usage: ``python pipeline/fatigue.py [--params params.yaml] [--cases PATH] [--runs DIR]
[--out DIR] [--scheduler S] [--n-workers N] [--no-progress] [--metrics JSON]``
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
from drillfatigue.sweep.stages import fatigue_stage, write_report  # noqa: E402


OPTIONS = (Option("--cases", help="default: sweep.cases_path"),
           Option("--runs", help="default: sweep.sweep_dir"),
           Option("--out", help="default: sweep.fatigue_dir"), *SWEEP_OPTIONS)


def fatigue(params: Params, args: Namespace) -> str:
    report = fatigue_stage(params, cases_path=args.cases, sweep_dir=args.runs,
                           fatigue_dir=args.out, scheduler=args.scheduler,
                           n_workers=args.n_workers, progress=not args.no_progress)
    if args.metrics:
        write_report(report, args.metrics)
    return (f"fatigue: {report.n_done} done, {report.n_skipped} already done, "
            f"{report.n_failed} failed, {report.wall_s:.1f} s")


def main(argv: list[str] | None = None) -> int:
    return stage_main(__doc__, fatigue, OPTIONS, argv)


if __name__ == "__main__":
    sys.exit(main())
