"""DVC stage ``case3``: the founding paper's case study 3 (see drillfatigue.studies.case3).

Reads the ``case3`` section of params.yaml, writes ``data/case3/`` (tables, figures,
runs) and ``metrics/case3.json``.

Usage: ``python pipeline/case3.py [--params params.yaml] [--out data/case3]
[--metrics metrics/case3.json]``
"""

from __future__ import annotations

import sys

from drillfatigue.numba_cache import scope_numba_cache

# Before any kernel module is imported: numba binds a kernel's cache folder
# when the kernel is decorated, so a later call would leave the kernels
# imported above it in the unscoped in-tree cache (stale across modules).
scope_numba_cache()

from drillfatigue.studies.stages import stage_main  # noqa: E402


def main(argv: list[str] | None = None) -> int:
    return stage_main("case3", argv)


if __name__ == "__main__":
    sys.exit(main())
