"""Write the dispatch modules of the law registries (friction and bit laws).

numba compiles and caches functions from source files only, so a registry's
dispatch on the law id is a module written from the registry::

    python -m drillfatigue.dynamics.registries          # write what is out of date
    python -m drillfatigue.dynamics.registries --check  # exit 1 if anything is

``tests/unit/dynamics/test_registries.py`` runs the check.
"""

from __future__ import annotations

import sys
from pathlib import Path

from drillfatigue.dynamics.bit.laws import registry as bit_registry
from drillfatigue.dynamics.contact.friction import registry as friction_registry


def dispatch_files() -> dict[Path, str]:
    """Each dispatch module's path and the source its registry gives."""
    return {registry.DISPATCH: registry.dispatch_source()
            for registry in (friction_registry, bit_registry)}


def main(argv: list[str] | None = None) -> int:
    args = sys.argv[1:] if argv is None else argv
    stale = [path for path, src in dispatch_files().items()
             if not path.is_file() or path.read_text(encoding="utf-8") != src]
    if "--check" in args:
        for path in stale:
            print(f"{path}: out of date (python -m drillfatigue.dynamics.registries)")
        return 1 if stale else 0
    for path in stale:
        path.write_text(dispatch_files()[path], encoding="utf-8")
        print(f"wrote {path}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
