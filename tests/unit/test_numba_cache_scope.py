"""The numba cache folder is keyed by the kernels' source (no stale cross-module cache)."""

from __future__ import annotations

import os
from pathlib import Path

import drillfatigue
from drillfatigue import _kernel_digest


def _tree(root: Path, force_body: str) -> None:
    (root / "dynamics").mkdir(parents=True)
    (root / "dynamics" / "integrator.py").write_text("import numba\nfrom .forces import f\n")
    (root / "dynamics" / "forces.py").write_text(f"import numba\n{force_body}\n")
    (root / "cli.py").write_text("print('no kernels here')\n")


def test_editing_a_called_kernel_changes_the_cache_key(tmp_path: Path) -> None:
    _tree(tmp_path / "a", "def f(x): return x")
    _tree(tmp_path / "b", "def f(x): return 2 * x")
    assert _kernel_digest(tmp_path / "a") != _kernel_digest(tmp_path / "b")


def test_modules_without_numba_do_not_change_it(tmp_path: Path) -> None:
    _tree(tmp_path / "a", "def f(x): return x")
    key = _kernel_digest(tmp_path / "a")
    (tmp_path / "a" / "cli.py").write_text("print('edited')\n")
    assert _kernel_digest(tmp_path / "a") == key


def test_the_process_cache_folder_ends_with_the_package_key() -> None:
    key = _kernel_digest(Path(drillfatigue.__file__).parent)
    assert Path(os.environ["NUMBA_CACHE_DIR"]).name == key
