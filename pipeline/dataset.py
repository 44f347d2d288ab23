"""DVC stage ``dataset``: assemble the damage dataset and its card.

Reads ``data/design/cases.parquet``, ``data/sweep/`` (summary dynamics),
``data/fatigue/`` (damage) and the ``sweep`` section (design description);
writes ``data/dataset/damage.parquet`` (one row per case and component
location), ``data/dataset/README.md`` (dataset card), ``data/dataset/metrics.json``
and ``data/dataset/plots/damage_rate_hist.csv``.

Usage: ``python pipeline/dataset.py [--params params.yaml] [--cases PATH] [--runs DIR]
[--fatigue DIR] [--out DIR]``
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
from drillfatigue.stage import Option, stage_main  # noqa: E402
from drillfatigue.sweep.stages import dataset_stage  # noqa: E402


OPTIONS = (Option("--cases", help="default: sweep.cases_path"),
           Option("--runs", help="default: sweep.sweep_dir"),
           Option("--fatigue", help="default: sweep.fatigue_dir"),
           Option("--out", help="default: sweep.dataset_dir"))


def dataset(params: Params, args: Namespace) -> str:
    metrics = dataset_stage(params, cases_path=args.cases, sweep_dir=args.runs,
                            fatigue_dir=args.fatigue, dataset_dir=args.out)
    return f"dataset: {metrics['n_rows']} rows from {metrics['n_cases_in_dataset']} cases"


def main(argv: list[str] | None = None) -> int:
    return stage_main(__doc__, dataset, OPTIONS, argv)


if __name__ == "__main__":
    sys.exit(main())
