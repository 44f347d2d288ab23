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

import argparse
import sys

from drillfatigue.numba_cache import scope_numba_cache

# Before any kernel module is imported: numba binds a kernel's cache folder
# when the kernel is decorated, so a later call would leave the kernels
# imported above it in the unscoped in-tree cache (stale across modules).
scope_numba_cache()

from drillfatigue.config import load_params  # noqa: E402
from drillfatigue.errors import InputError  # noqa: E402
from drillfatigue.sweep.stages import dataset_stage  # noqa: E402


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--params", default="params.yaml")
    parser.add_argument("--cases", default=None, help="default: sweep.cases_path")
    parser.add_argument("--runs", default=None, help="default: sweep.sweep_dir")
    parser.add_argument("--fatigue", default=None, help="default: sweep.fatigue_dir")
    parser.add_argument("--out", default=None, help="default: sweep.dataset_dir")
    args = parser.parse_args(argv)
    try:
        metrics = dataset_stage(load_params(args.params), cases_path=args.cases,
                                sweep_dir=args.runs, fatigue_dir=args.fatigue,
                                dataset_dir=args.out)
    except InputError as exc:
        print(f"error: {exc.one_line()}", file=sys.stderr)
        return 2
    print(f"dataset: {metrics['n_rows']} rows from {metrics['n_cases_in_dataset']} cases")
    return 0


if __name__ == "__main__":
    sys.exit(main())
