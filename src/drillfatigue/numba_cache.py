"""numba's on-disk cache folder, keyed by the source of the package's kernels.

numba invalidates a cached function only when its own file changes, not when
a kernel it calls in another module does: a stale cache would silently run
old physics. :func:`scope_numba_cache` therefore points numba's cache at
``<base>/<digest>``, the digest covering every package module that imports
numba and the modules of numbers the kernels read as compile-time constants
(:data:`KERNEL_CONSTANT_MODULES`), so an edit anywhere in the kernels starts a
fresh cache.

Importing :mod:`drillfatigue` does not do this (a library must not change its
host process's environment or numba's global settings). It is called
explicitly by the ``drillfatigue`` command, by the pipeline stages, by remote
Dask workers of a sweep and by the test suite. A program that uses the
library and wants the same protection calls it once, before it imports any
kernel module (``drillfatigue.dynamics``, ``drillfatigue.fatigue`` …), since
numba binds a function's cache folder when the function is decorated::

    import drillfatigue.numba_cache

    drillfatigue.numba_cache.scope_numba_cache()
    from drillfatigue.dynamics import simulate  # kernels now cache under the scoped folder
"""

from __future__ import annotations

import functools
import hashlib
import os
import re
import sys
from pathlib import Path

__all__ = ["KERNEL_CONSTANT_MODULES", "default_cache_base", "kernel_digest", "scope_numba_cache",
           "source_digest"]

PACKAGE_ROOT = Path(__file__).resolve().parent


def source_digest(root: Path, only_containing: bytes = b"") -> str:
    """SHA-256 (hex) over the ``.py`` modules under ``root`` (paths and contents).

    ``only_containing``: hash only the modules whose source contains it.
    """
    digest = hashlib.sha256()
    for path in sorted(root.rglob("*.py")):
        text = path.read_bytes()
        if only_containing in text:
            digest.update(path.relative_to(root).as_posix().encode() + b"\0" + text)
    return digest.hexdigest()


_IMPORTS_NUMBA = re.compile(rb"^\s*(?:import numba|from numba[\s.])", re.M)

#: Modules (paths under the package root) without numba whose module-level
#: numbers the kernels read as compile-time constants: numba freezes them into
#: the compiled code, so they key the cache like the kernels themselves.
KERNEL_CONSTANT_MODULES: tuple[str, ...] = ("status.py", "units.py", "dynamics/core/status.py",
                                             "dynamics/core/layout.py")


def kernel_digest(root: Path) -> str:
    """16 hex digits of SHA-256 over every module under ``root`` that imports numba
    or is one of :data:`KERNEL_CONSTANT_MODULES`.

    Only modules that import numba can define or call kernels; a module that
    merely mentions numba (this one) does not invalidate the cache.
    """
    digest = hashlib.sha256()
    for path in sorted(root.rglob("*.py")):
        text = path.read_bytes()
        if (_IMPORTS_NUMBA.search(text)
                or path.relative_to(root).as_posix() in KERNEL_CONSTANT_MODULES):
            digest.update(path.relative_to(root).as_posix().encode() + b"\0" + text)
    return digest.hexdigest()[:16]


@functools.lru_cache(maxsize=1)
def _package_kernel_digest() -> str:
    return kernel_digest(PACKAGE_ROOT)


def default_cache_base() -> Path:
    """``$NUMBA_CACHE_DIR`` if set, else ``~/.cache/drillfatigue/numba``."""
    return Path(os.environ.get("NUMBA_CACHE_DIR") or Path.home() / ".cache" / "drillfatigue" / "numba")


def scope_numba_cache(base: str | Path | None = None) -> Path:
    """Point numba's on-disk cache at ``<base>/<kernel digest>`` and return that folder.

    Sets ``NUMBA_CACHE_DIR`` in this process's environment (worker processes
    started afterwards inherit it) and, when numba is already imported, its
    ``numba.core.config.CACHE_DIR``. Idempotent: a base that already ends in
    the digest is kept as it is. Call it before any kernel module is
    imported; kernels decorated earlier keep the folder they were bound to.

    Parameters
    ----------
    base : str or Path, optional
        Parent folder of the per-digest caches; default :func:`default_cache_base`
        (the make targets set ``NUMBA_CACHE_DIR=.numba_cache``).

    Returns
    -------
    Path
        The scoped cache folder.
    """
    folder = Path(base) if base is not None else default_cache_base()
    key = _package_kernel_digest()
    if folder.name != key:
        folder = folder / key
    os.environ["NUMBA_CACHE_DIR"] = str(folder)
    numba_config = sys.modules.get("numba.core.config")
    if numba_config is not None:  # numba's config read the variable when numba was imported
        numba_config.CACHE_DIR = str(folder)  # type: ignore[attr-defined]
    return folder
