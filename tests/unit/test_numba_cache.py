"""The numba cache folder is keyed by the kernels' source (no stale cross-module cache),
and importing the package changes nothing outside it."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import drillfatigue
from drillfatigue.numba_cache import KERNEL_CONSTANT_MODULES, kernel_digest, scope_numba_cache


def _tree(root: Path, force_body: str) -> None:
    (root / "dynamics").mkdir(parents=True)
    (root / "dynamics" / "integrator.py").write_text("import numba\nfrom .forces import f\n")
    (root / "dynamics" / "forces.py").write_text(f"import numba\n{force_body}\n")
    (root / "cli.py").write_text("print('no kernels here')\n")


def test_editing_a_called_kernel_changes_the_cache_key(tmp_path: Path) -> None:
    _tree(tmp_path / "a", "def f(x): return x")
    _tree(tmp_path / "b", "def f(x): return 2 * x")
    assert kernel_digest(tmp_path / "a") != kernel_digest(tmp_path / "b")


def test_modules_without_numba_do_not_change_it(tmp_path: Path) -> None:
    _tree(tmp_path / "a", "def f(x): return x")
    key = kernel_digest(tmp_path / "a")
    (tmp_path / "a" / "cli.py").write_text("print('edited')\n")
    assert kernel_digest(tmp_path / "a") == key


def test_the_process_cache_folder_ends_with_the_package_key() -> None:
    # tests/conftest.py scoped the cache before any kernel was imported
    key = kernel_digest(Path(drillfatigue.__file__).parent)
    assert Path(os.environ["NUMBA_CACHE_DIR"]).name == key
    import numba.core.config

    assert Path(numba.core.config.CACHE_DIR).name == key


def test_scoping_is_idempotent(tmp_path: Path) -> None:
    before = os.environ["NUMBA_CACHE_DIR"]
    try:
        first = scope_numba_cache(tmp_path)
        assert first.parent == tmp_path
        assert scope_numba_cache(first) == first
    finally:
        scope_numba_cache(before)
    assert os.environ["NUMBA_CACHE_DIR"] == before


# Third-party libraries are imported before the snapshot (torch, for one,
# sets OpenMP variables on import): only the package's own effects count.
_PROBE = """
import json, os, sys
import matplotlib, numba, numpy, pandas, scipy, sklearn, torch, pydantic, typer, rich, fatpack
env0 = dict(os.environ)
import numba.core.config as nc
cache0 = nc.CACHE_DIR
backend0 = matplotlib.get_backend()
import drillfatigue, drillfatigue.dynamics, drillfatigue.fatigue, drillfatigue.surrogate
import drillfatigue.sweep, drillfatigue.studies, drillfatigue.well, drillfatigue.cli
print(json.dumps({
    "env_changed": sorted(k for k in set(env0) | set(os.environ) if env0.get(k) != os.environ.get(k)),
    "cache_changed": nc.CACHE_DIR != cache0,
    "backend": [backend0, matplotlib.get_backend()],
    "pyplot_imported": "matplotlib.pyplot" in sys.modules,
}))
"""


def test_importing_the_package_changes_nothing_outside_it(tmp_path: Path) -> None:
    env = {k: v for k, v in os.environ.items() if k != "NUMBA_CACHE_DIR"}
    env["MPLBACKEND"] = "svg"  # a user's chosen backend must survive the import
    src = str(Path(drillfatigue.__file__).resolve().parents[1])
    env["PYTHONPATH"] = os.pathsep.join([src, env.get("PYTHONPATH", "")])
    out = subprocess.run([sys.executable, "-c", _PROBE], env=env, cwd=tmp_path,
                         capture_output=True, text=True, timeout=240, check=True)
    found = json.loads(out.stdout.strip().splitlines()[-1])
    assert found["env_changed"] == []
    assert found["cache_changed"] is False
    assert found["backend"] == ["svg", "svg"]
    assert found["pyplot_imported"] is False


def test_a_library_figure_leaves_the_backend_alone(tmp_path: Path) -> None:
    """Drawing and saving a library figure keeps the process's backend (no ``matplotlib.use``)."""
    code = (
        "import matplotlib, sys\n"
        "from drillfatigue.plotting import subplots\n"
        "fig, ax = subplots(figsize=(2, 2)); ax.plot([0, 1], [1, 0])\n"
        f"fig.savefig({str(tmp_path / 'f.png')!r})\n"
        "print(matplotlib.get_backend(), 'matplotlib.pyplot' in sys.modules)\n"
    )
    env = dict(os.environ, MPLBACKEND="svg")
    src = str(Path(drillfatigue.__file__).resolve().parents[1])
    env["PYTHONPATH"] = os.pathsep.join([src, env.get("PYTHONPATH", "")])
    out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True,
                         timeout=120, check=True)
    assert out.stdout.split() == ["svg", "False"]
    assert (tmp_path / "f.png").stat().st_size > 0


def test_a_module_that_only_mentions_numba_does_not_change_it(tmp_path: Path) -> None:
    _tree(tmp_path / "a", "def f(x): return x")
    key = kernel_digest(tmp_path / "a")
    (tmp_path / "a" / "cache.py").write_text('"""Scopes numba\'s cache."""\n')
    assert kernel_digest(tmp_path / "a") == key
    (tmp_path / "a" / "cache.py").write_text("from numba import njit\n")
    assert kernel_digest(tmp_path / "a") != key


def test_a_module_of_kernel_constants_changes_it(tmp_path: Path) -> None:
    # kernels read the status codes as compile-time constants: a renumbered
    # code must not reuse kernels compiled with the old number
    _tree(tmp_path / "a", "def f(x): return x")
    (tmp_path / "a" / "status.py").write_text("OK = 0\n")
    key = kernel_digest(tmp_path / "a")
    (tmp_path / "a" / "status.py").write_text("OK = 1\n")
    assert kernel_digest(tmp_path / "a") != key


def test_the_listed_constant_modules_exist() -> None:
    # a renamed or moved module would silently fall out of the key
    root = Path(drillfatigue.__file__).parent
    assert all((root / name).is_file() for name in KERNEL_CONSTANT_MODULES)


_BOUND_OUTSIDE_SCOPE = """
import os, runpy, sys
runpy.run_path(sys.argv[1], run_name="imported")  # the stage's imports, not its main()
from numba.core.caching import FunctionCache
from numba.core.registry import CPUDispatcher
scoped = sys.argv[2]
n, outside = 0, []
for name, mod in list(sys.modules.items()):
    if name.startswith("drillfatigue"):
        for obj in vars(mod).values():
            if isinstance(obj, CPUDispatcher) and isinstance(obj._cache, FunctionCache):
                n += 1
                if not obj._cache._cache_path.startswith(scoped):
                    outside.append(f"{name}.{obj.__name__}: {obj._cache._cache_path}")
print(n, outside)
"""


def test_every_stage_script_binds_its_kernels_to_the_scoped_cache(tmp_path: Path) -> None:
    """A stage script that imports kernel modules before it scopes the cache leaves those
    kernels in numba's in-tree cache (``__pycache__``), which does not notice an edited
    kernel they call in another module: a long-lived checkout then runs stale physics.
    Every script under pipeline/ that loads kernels must bind all of them under the
    scoped folder (measured before the fix: 153-154 kernels outside it per script)."""
    repo = Path(__file__).resolve().parents[2]
    env = {k: v for k, v in os.environ.items() if k != "NUMBA_CACHE_DIR"}
    env["NUMBA_CACHE_DIR"] = str(tmp_path / "base")
    scoped = str(tmp_path / "base" / kernel_digest(Path(drillfatigue.__file__).parent))
    loaded = 0
    for script in sorted((repo / "pipeline").glob("*.py")):
        out = subprocess.run([sys.executable, "-c", _BOUND_OUTSIDE_SCOPE, str(script), scoped],
                             capture_output=True, text=True, env=env, cwd=repo, check=True)
        n, outside = out.stdout.strip().split(" ", 1)
        assert outside == "[]", f"{script.name}: {outside}"
        loaded += int(n) > 0
    assert loaded >= 10  # the simulation, fatigue and study stages load kernels
