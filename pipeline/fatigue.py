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
from drillfatigue.sweep.stages import fatigue_stage, write_report  # noqa: E402


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--params", default="params.yaml")
    parser.add_argument("--cases", default=None, help="default: sweep.cases_path")
    parser.add_argument("--runs", default=None, help="default: sweep.sweep_dir")
    parser.add_argument("--out", default=None, help="default: sweep.fatigue_dir")
    parser.add_argument("--scheduler", default=None, help="override sweep.scheduler")
    parser.add_argument("--n-workers", type=int, default=None, help="override sweep.n_workers")
    parser.add_argument("--no-progress", action="store_true")
    parser.add_argument("--metrics", default=None, help="also write the sweep report here (JSON)")
    args = parser.parse_args(argv)
    try:
        params = load_params(args.params)
        report = fatigue_stage(params, cases_path=args.cases, sweep_dir=args.runs,
                               fatigue_dir=args.out, scheduler=args.scheduler,
                               n_workers=args.n_workers, progress=not args.no_progress)
    except InputError as exc:
        print(f"error: {exc.one_line()}", file=sys.stderr)
        return 2
    except SweepFailedError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 1
    if args.metrics:
        write_report(report, args.metrics)
    print(f"fatigue: {report.n_done} done, {report.n_skipped} already done, "
          f"{report.n_failed} failed, {report.wall_s:.1f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
