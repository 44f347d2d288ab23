"""Shared test set-up: numba's cache keyed by the kernels' source; test helpers importable;
the slow test files first.

The helper modules in ``tests/testkit/`` (synthetic sweep cases with fault
injection, synthetic fatigue run folders, a tiny surrogate, a throwaway
PostgreSQL server ...) are test fixtures, not part of the installed package;
``pythonpath`` in ``pyproject.toml`` puts ``tests/`` on ``sys.path`` so test
modules and sweep worker processes import them as ``testkit.<module>``.
"""

from __future__ import annotations

import pytest

from drillfatigue.numba_cache import scope_numba_cache

# Before any test module imports a kernel: numba binds the cache folder when
# a function is decorated.
scope_numba_cache()


def pytest_collection_modifyitems(items: list[pytest.Item]) -> None:
    """Files holding a ``slow`` test run first, the rest after, each in collection order.

    ``make test`` hands whole files to its workers in this order (``--dist loadfile``):
    long files started last would leave one worker running alone at the end.
    """
    slow_files = {item.path for item in items if item.get_closest_marker("slow")}
    items.sort(key=lambda item: item.path not in slow_files)
