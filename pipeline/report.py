"""DVC stage ``report``: ``data/report/README.md`` from the case-study outputs.

Reads ``data/case1``, ``data/case2``, ``data/case3`` (and ``data/plan`` when it
exists) and the measured paper-scale timings ``pipeline/paper_scale_timings.json``;
writes ``data/report/`` (README.md and the figures).

Usage: ``python pipeline/report.py [--params params.yaml] [--out data/report]``
"""

from __future__ import annotations

import sys
from argparse import Namespace
from functools import partial
from pathlib import Path

from drillfatigue.numba_cache import scope_numba_cache

# Before any kernel module is imported: numba binds a kernel's cache folder
# when the kernel is decorated, so a later call would leave the kernels
# imported above it in the unscoped in-tree cache (stale across modules).
scope_numba_cache()

from drillfatigue.config.studies import ReportConfig  # noqa: E402
from drillfatigue.stage import Option, stage_main  # noqa: E402
from drillfatigue.studies.report import write_report  # noqa: E402
from drillfatigue.studies.stages import load_section  # noqa: E402


OPTIONS = (Option("--case1", default="data/case1"), Option("--case2", default="data/case2"),
           Option("--case3", default="data/case3"), Option("--plan", default="data/plan"),
           Option("--timings", default="pipeline/paper_scale_timings.json"),
           Option("--out", help="default: report.out_dir"))


def report(cfg: ReportConfig, args: Namespace) -> None:
    out = Path(args.out or cfg.out_dir)
    plan = Path(args.plan) if Path(args.plan).is_dir() else None
    write_report(Path(args.case1), Path(args.case2), Path(args.case3), out, plan_dir=plan,
                 timings_path=Path(args.timings))


def main(argv: list[str] | None = None) -> int:
    return stage_main(__doc__, report, OPTIONS, argv, load=partial(load_section, name="report"))


if __name__ == "__main__":
    sys.exit(main())
