"""Kernel modules stay free of high-level dependencies (STYLE.md habit 1).

Every module that defines a numba ``@njit`` kernel may import numpy, numba,
math and other kernel modules, but never pandas, pyarrow, pydantic, yaml,
torch or the configuration package: kernels work on bare float arrays in SI.
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

SRC = Path(__file__).resolve().parents[2] / "src" / "drillfatigue"
FORBIDDEN = ("pandas", "pyarrow", "pydantic", "yaml", "torch", "drillfatigue.config", "sklearn")


def _kernel_modules() -> list[Path]:
    return sorted(p for p in SRC.rglob("*.py") if "@njit" in p.read_text(encoding="utf-8"))


def _runtime_imports(path: Path) -> list[str]:
    tree = ast.parse(path.read_text(encoding="utf-8"))
    names: list[str] = []
    for node in tree.body:  # module level only; TYPE_CHECKING blocks are skipped below
        if isinstance(node, ast.Import):
            names += [a.name for a in node.names]
        elif isinstance(node, ast.ImportFrom) and node.module:
            names.append(node.module)
    return names


def test_there_are_kernel_modules() -> None:
    # Guards the test below against silently checking nothing.
    assert len(_kernel_modules()) >= 5


@pytest.mark.parametrize("path", _kernel_modules(), ids=lambda p: str(p.relative_to(SRC)))
def test_kernel_module_imports_only_numerics(path: Path) -> None:
    bad = [n for n in _runtime_imports(path) if n.split(".")[0] in FORBIDDEN or
           any(n == f or n.startswith(f + ".") for f in FORBIDDEN)]
    assert not bad, f"{path.name} imports {bad}; kernel modules must stay numpy/numba/math only"
