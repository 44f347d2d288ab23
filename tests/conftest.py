"""Shared test set-up: numba's cache keyed by the kernels' source; test helpers importable;
the slow test files first.

The helper modules in ``tests/testkit/`` (synthetic sweep cases with fault
injection, synthetic fatigue run folders, a tiny surrogate, a throwaway
PostgreSQL server ...) are test fixtures, not part of the installed package;
``pythonpath`` in ``pyproject.toml`` puts ``tests/`` on ``sys.path`` so test
modules and sweep worker processes import them as ``testkit.<module>``.
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

from drillfatigue.numba_cache import scope_numba_cache

# Before any test module imports a kernel: numba binds the cache folder when
# a function is decorated.
scope_numba_cache()


def pytest_configure(config: pytest.Config) -> None:
    """In a parallel run, fill numba's cache first, one process per core
    (:mod:`testkit.warm_numba`): on a fresh clone each worker would compile the same
    kernels side by side. Quick (seconds) when the cache is already filled."""
    if (hasattr(config, "workerinput") or not config.getoption("numprocesses", None)
            or os.environ.get("DRILLFATIGUE_TESTS_WARMED")):  # make test warmed it
        return
    tests = Path(__file__).resolve().parent
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(
        [str(tests), str(tests.parent / "src"), os.environ.get("PYTHONPATH", "")])}
    procs = [subprocess.Popen([sys.executable, "-m", "testkit.warm_numba", part], env=env,
                              cwd=tests.parent, stdout=subprocess.DEVNULL)
             for part in ("sim", "models")]
    for proc in procs:
        proc.wait()  # a part that fails is reported by the tests that meet its code


def pytest_collection_modifyitems(items: list[pytest.Item]) -> None:
    """Files holding a ``slow`` test run first, the rest after, each in collection order.

    ``make test`` hands whole files to its workers in this order (``--dist loadfile``):
    long files started last would leave one worker running alone at the end.
    """
    slow_files = {item.path for item in items if item.get_closest_marker("slow")}
    items.sort(key=lambda item: item.path not in slow_files)
