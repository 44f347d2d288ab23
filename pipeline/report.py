"""DVC stage ``report``: ``data/report/README.md`` from the case-study outputs.

Reads ``data/case1``, ``data/case2``, ``data/case3`` (and ``data/plan`` when it
exists) and the measured paper-scale timings ``pipeline/paper_scale_timings.json``;
writes ``data/report/`` (README.md and the figures).

Usage: ``python pipeline/report.py [--params params.yaml] [--out data/report]``
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from drillfatigue.numba_cache import scope_numba_cache

# Before any kernel module is imported: numba binds a kernel's cache folder
# when the kernel is decorated, so a later call would leave the kernels
# imported above it in the unscoped in-tree cache (stale across modules).
scope_numba_cache()

from drillfatigue.errors import InputError  # noqa: E402
from drillfatigue.studies.report import write_report  # noqa: E402
from drillfatigue.studies.stages import load_section  # noqa: E402


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--params", default="params.yaml")
    parser.add_argument("--case1", default="data/case1")
    parser.add_argument("--case2", default="data/case2")
    parser.add_argument("--case3", default="data/case3")
    parser.add_argument("--plan", default="data/plan")
    parser.add_argument("--timings", default="pipeline/paper_scale_timings.json")
    parser.add_argument("--out", default=None, help="default: report.out_dir")
    args = parser.parse_args(argv)
    try:
        cfg = load_section(args.params, "report")
        out = Path(args.out or cfg.out_dir)
        plan = Path(args.plan) if Path(args.plan).is_dir() else None
        write_report(Path(args.case1), Path(args.case2), Path(args.case3), out, plan_dir=plan,
                     timings_path=Path(args.timings))
    except InputError as exc:
        print(f"error: {exc.one_line()}", file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main())
