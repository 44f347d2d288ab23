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
from drillfatigue.sweep.stages import design_stage  # noqa: E402


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--params", default="params.yaml")
    parser.add_argument("--out", default=None, help="case table (default: sweep.cases_path)")
    parser.add_argument("--progress", action="store_true",
                        help="progress bars of the adaptive design's simulations")
    args = parser.parse_args(argv)
    try:
        frame = design_stage(load_params(args.params), args.out, progress=args.progress)
    except InputError as exc:
        print(f"error: {exc.one_line()}", file=sys.stderr)
        return 2
    except SweepFailedError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 1
    print(f"design: {len(frame)} cases")
    return 0


if __name__ == "__main__":
    sys.exit(main())
