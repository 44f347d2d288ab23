"""DVC stage ``case2``: the founding paper's case study 2 (see drillfatigue.studies.case2).

Reads the ``case2`` section of params.yaml, writes ``data/case2/`` (tables, figures,
runs) and ``metrics/case2.json``.

Usage: ``python pipeline/case2.py [--params params.yaml] [--out data/case2]
[--metrics metrics/case2.json]``
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
    return stage_main("case2", argv)


if __name__ == "__main__":
    sys.exit(main())
