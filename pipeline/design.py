"""DVC stage ``design``: sample the operating cases of the sweep.

Reads the case sections (the base case) and the ``sweep`` section of
``params.yaml``; writes ``data/design/cases.parquet`` (case id, one column per
design variable, full case JSON), ``data/design/coverage.csv`` (DVC plot of
the design) and ``data/design/design.json`` (metrics). Bad variables or
bounds fail here, before any simulation, with a one-line error.

With ``sweep.method: adaptive`` the stage also simulates and evaluates the
cases it chooses (the simulate and fatigue stages' code, fatigue and window
settings), into ``sweep.adaptive.cache_dir`` (``data/design/adaptive``):
resumable, a rerun reads finished cases back. Exit code 1 when more than
``sweep.failure_threshold`` of a round's cases fail.

Usage: ``python pipeline/design.py [--params params.yaml] [--out data/design/cases.parquet]
[--progress]``
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
from drillfatigue.sweep.stages import design_stage  # noqa: E402


OPTIONS = (Option("--out", help="case table (default: sweep.cases_path)"),
           Option("--progress", switch=True,
                  help="progress bars of the adaptive design's simulations"))


def design(params: Params, args: Namespace) -> str:
    frame = design_stage(params, args.out, progress=args.progress)
    return f"design: {len(frame)} cases"


def main(argv: list[str] | None = None) -> int:
    return stage_main(__doc__, design, OPTIONS, argv)


if __name__ == "__main__":
    sys.exit(main())
