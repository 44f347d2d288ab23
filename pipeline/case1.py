"""DVC stage ``case1``: the founding paper's case study 1 (see drillfatigue.studies.case1).

Reads the ``case1`` section of params.yaml, writes ``data/case1/`` (tables, figures,
runs) and ``metrics/case1.json``.

Usage: ``python pipeline/case1.py [--params params.yaml] [--out data/case1]
[--metrics metrics/case1.json]``
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
    return stage_main("case1", argv)


if __name__ == "__main__":
    sys.exit(main())
