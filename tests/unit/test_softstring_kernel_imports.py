"""The soft-string and contact kernel modules import only numpy, numba, math (STYLE.md habit 1).

``typing``/``dataclasses``/``__future__`` are allowed, and imports guarded by
``if TYPE_CHECKING`` (type hints of the config classes) are not executed.
The check reads the module source, since numba itself imports yaml.
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

import drillfatigue.dynamics as dyn

ALLOWED = {"numpy", "numba", "math", "__future__", "typing", "dataclasses"}
KERNEL_MODULES = {"drillfatigue.dynamics.friction", "drillfatigue.dynamics.contact",
                  "drillfatigue.dynamics.bitrock"}


@pytest.mark.parametrize("module", ["contact", "friction", "bitrock", "softstring"])
def test_top_level_imports(module):
    tree = ast.parse((Path(dyn.__file__).parent / f"{module}.py").read_text())
    names = []
    for node in tree.body:  # top level only; TYPE_CHECKING blocks are `if` nodes, skipped
        if isinstance(node, ast.Import):
            names += [a.name.split(".")[0] for a in node.names]
        elif isinstance(node, ast.ImportFrom):
            mod = node.module or ""
            if mod in KERNEL_MODULES:  # kernels may call other kernels
                continue
            names.append(mod.split(".")[0])
    assert set(names) <= ALLOWED, set(names) - ALLOWED
