"""Shared test set-up: numba's cache keyed by the kernels' source; test helpers importable.

The helper modules in ``tests/helpers/`` (synthetic sweep cases with fault
injection, synthetic fatigue run folders) are test fixtures, not part of the
installed package; ``pythonpath`` in ``pyproject.toml`` puts ``tests/`` on
``sys.path`` so test modules and sweep worker processes import them as
``helpers.<module>``.
"""

from __future__ import annotations

from drillfatigue.numba_cache import scope_numba_cache

# Before any test module imports a kernel: numba binds the cache folder when
# a function is decorated.
scope_numba_cache()
