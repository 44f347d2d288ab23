"""What the law registries share (:mod:`drillfatigue.dynamics.contact.friction.registry`,
:mod:`drillfatigue.dynamics.bit.laws.registry`): the blocks of the parameter vector, the
opening of a dispatch module, and a package's names loaded on first use.

A registry lists its law modules; a law's position is its id and its ``PARAMS`` its
block in the parameter vector. numba compiles and caches functions from files only, so
a registry's dispatch on the law id is a module written from it
(:mod:`drillfatigue.dynamics.registries`).
"""

from __future__ import annotations

import importlib
import textwrap
from collections.abc import Callable, Mapping, Sequence
from types import ModuleType
from typing import Any


def block_offsets(laws: Sequence[ModuleType], start: int) -> tuple[tuple[int, ...], int]:
    """Each law's block start in the parameter vector (the first at ``start``, each
    after the one before) and the vector's length."""
    out, at = [], start
    for law in laws:
        out.append(at)
        at += len(law.PARAMS)
    return tuple(out), at


def dispatch_prelude(what: str, registry: str, laws: Sequence[ModuleType]) -> tuple[str, list[str]]:
    """The opening of a dispatch module for ``laws`` (its docstring, the imports of the
    law modules, ``N_LAWS`` and an id constant per law) and the modules' short names."""
    package = laws[0].__name__.rsplit(".", 1)[0]
    names = [law.__name__.rsplit(".", 1)[1] for law in laws]
    imports = textwrap.fill(", ".join(sorted(names)) + ",", 96, initial_indent="    ",
                            subsequent_indent="    ")
    ids = "".join(f"{law.NAME.upper()} = {i}\n" for i, law in enumerate(laws))
    head = (f'"""Dispatch of the {what} kernels on the law id (written by\n'
            f":mod:`{registry}` from its ``LAWS``; do not edit:\n"
            'run ``python -m drillfatigue.dynamics.registries``)."""\n\n'
            "from numba import njit\n\n"
            f"from {package} import (\n{imports}\n)\n\n"
            "#: Number of registered laws (ids 0 .. N_LAWS - 1).\n"
            f"N_LAWS = {len(laws)}\n#: Law ids by name.\n{ids}")
    return head, names


def lazy_exports(package: str, exports: Mapping[str, str]) -> Callable[[str], Any]:
    """A module ``__getattr__`` that loads each public name of ``package`` from the module
    ``exports`` maps it to on first use (so that a registry can be imported, and its
    dispatch written, before the dispatch module exists)."""

    def __getattr__(name: str) -> Any:
        if name in exports:
            return getattr(importlib.import_module(exports[name]), name)
        raise AttributeError(f"module {package!r} has no attribute {name!r}")

    return __getattr__
