"""drillfatigue: drill-string dynamics in deviated wells and fatigue prognosis.

Subpackages: ``well`` (trajectories, wellbore geometry), ``string`` (components
and segmentation), ``dynamics`` (numba rigid-segment simulator), ``fatigue``
(stresses, rainflow, S-N, Miner, critical plane, API RP7G), ``surrogate``
(torch ensemble), ``sweep`` (case design and parallel runs), ``config``
(validated parameter models), ``cli``. SI units throughout the code.
"""

from __future__ import annotations

import hashlib
import os
import sys
from pathlib import Path

__version__ = "0.1.0"


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


def _kernel_digest(root: Path) -> str:
    """16 hex digits of SHA-256 over every module under ``root`` that mentions numba."""
    return source_digest(root, b"numba")[:16]


def _scope_numba_cache() -> None:
    """Point numba's on-disk cache at a folder keyed by the kernels' source.

    numba invalidates a cached function only when its own file changes, not
    when a kernel it calls (in another module) does: a stale cache would
    silently run old physics. So the cache lives in
    ``$NUMBA_CACHE_DIR/<digest>`` (default base ``~/.cache/drillfatigue/numba``),
    the digest covering every package module that uses numba; an edit anywhere
    in the kernels starts a fresh cache. Runs once, before any kernel module
    is imported (the decorators bind their cache folder at import time).
    The make targets set ``NUMBA_CACHE_DIR=.numba_cache``.
    """
    base = Path(os.environ.get("NUMBA_CACHE_DIR") or Path.home() / ".cache" / "drillfatigue" / "numba")
    key = _kernel_digest(Path(__file__).parent)
    if base.name != key:  # not already scoped (worker processes inherit the folder)
        base = base / key
    os.environ["NUMBA_CACHE_DIR"] = str(base)
    numba_config = sys.modules.get("numba.core.config")
    if numba_config is not None:  # numba imported first: its config has read the variable
        numba_config.CACHE_DIR = str(base)


_scope_numba_cache()


def __getattr__(name: str) -> object:
    """Lazy top-level API: ``drillfatigue.simulate``.

    Imported on first use, not at the top: the simulator imports this package
    (a real cycle at import time), and its numba kernels must load only after
    :func:`_scope_numba_cache` has chosen the cache folder.
    """
    if name == "simulate":
        from drillfatigue.dynamics.api import simulate

        return simulate
    if name == "SimulationResult":
        from drillfatigue.dynamics.api import SimulationResult

        return SimulationResult
    raise AttributeError(f"module 'drillfatigue' has no attribute {name!r}")
