"""The hand-written maps of the package stay equal to its tree.

Three maps name modules: the import-linter kernel contract (pyproject.toml), the
map of ``docs/dynamics.md``, and each subpackage's docstring. A module added,
moved or removed without its map fails here.
"""

from __future__ import annotations

import ast
import re
import tomllib
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
PKG = ROOT / "src" / "drillfatigue"
#: Packages whose modules docs/dynamics.md maps (paths relative to the package root).
MAPPED = ("dynamics", "softstring")
MAX_MODULES_PER_FOLDER = 8


def _modules(root: Path) -> list[Path]:
    return sorted(p for p in root.rglob("*.py") if p.name != "__init__.py"
                  and "__pycache__" not in p.parts)


def _dotted(path: Path) -> str:
    return ".".join(path.relative_to(PKG.parent).with_suffix("").parts)


def _defines_kernel(path: Path) -> bool:
    tree = ast.parse(path.read_text(encoding="utf-8"))
    for node in ast.walk(tree):
        if isinstance(node, ast.FunctionDef):
            for dec in node.decorator_list:
                target = dec.func if isinstance(dec, ast.Call) else dec
                name = target.attr if isinstance(target, ast.Attribute) else getattr(target, "id", "")
                if name in {"njit", "jit", "vectorize", "guvectorize"}:
                    return True
    return False


def _kernel_contract() -> dict:
    cfg = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))
    for contract in cfg["tool"]["importlinter"]["contracts"]:
        if contract["name"].startswith("kernels import only"):
            return contract
    raise AssertionError("no kernel contract in pyproject.toml")


def test_the_kernel_contract_checks_every_kernel_module() -> None:
    kernels = {_dotted(p) for p in _modules(PKG) if _defines_kernel(p)}
    assert len(kernels) > 15  # the walk found the kernels
    listed = set(_kernel_contract()["source_modules"])
    # a listed package covers its modules (import-linter checks a package's descendants)
    unchecked = {k for k in kernels
                 if not any(k == m or k.startswith(m + ".") for m in listed)}
    assert unchecked == set(), "kernel modules the contract does not check"
    for name in listed - kernels:  # a package, or a module of constants the kernels share
        path = PKG.parent / name.replace(".", "/")
        assert path.with_suffix(".py").is_file() or (path / "__init__.py").is_file(), (
            f"{name} in the kernel contract does not exist")


def test_the_contracts_name_existing_modules() -> None:
    for name in _kernel_contract()["forbidden_modules"]:
        if not name.startswith("drillfatigue"):
            continue
        path = PKG.parent / name.replace(".", "/")
        assert path.with_suffix(".py").is_file() or path.is_dir(), name


def _doc_map() -> set[str]:
    text = (ROOT / "docs" / "dynamics.md").read_text(encoding="utf-8")
    return set(re.findall(r"^\| `([\w/]+\.py)`", text, flags=re.M))


def test_docs_dynamics_maps_every_module() -> None:
    in_tree = set()
    for pkg in MAPPED:
        base = PKG / "dynamics"
        for path in _modules(PKG / pkg):
            rel = path.relative_to(base) if pkg == "dynamics" else path.relative_to(PKG)
            in_tree.add(rel.as_posix())
    in_tree.discard("registries.py")  # named in the text below the table
    mapped = _doc_map()
    assert in_tree - mapped == set(), "modules docs/dynamics.md does not map"
    assert mapped - in_tree == set(), "docs/dynamics.md maps modules that do not exist"


@pytest.mark.parametrize("pkg", ["dynamics", "softstring"])
def test_each_folder_stays_small_and_its_docstring_names_its_modules(pkg: str) -> None:
    for init in sorted((PKG / pkg).rglob("__init__.py")):
        folder = init.parent
        mods = sorted(p.stem for p in folder.glob("*.py") if p.name != "__init__.py")
        assert len(mods) <= MAX_MODULES_PER_FOLDER, folder
        doc = ast.get_docstring(ast.parse(init.read_text(encoding="utf-8"))) or ""
        sub = sorted(d.name for d in folder.iterdir() if (d / "__init__.py").is_file())
        for name in mods + sub:
            assert f"{_dotted(folder / name)}`" in doc or f".{name}`" in doc, (
                f"{init.relative_to(ROOT)} does not name {name}")


def test_unit_tests_mirror_the_source_and_helpers_live_in_testkit() -> None:
    tests = ROOT / "tests"
    unit = tests / "unit"
    n_files = 0
    for path in sorted(unit.rglob("*.py")):
        if "__pycache__" in path.parts:
            continue
        rel = path.relative_to(unit)
        package = PKG.joinpath(*rel.parts[:-1])
        assert (package / "__init__.py").is_file(), (
            f"tests/unit/{rel}: no package src/drillfatigue/{'/'.join(rel.parts[:-1])}")
        assert path.name == "__init__.py" or path.name.startswith("test_"), (
            f"tests/unit/{rel}: a helper outside tests/testkit")
        n_files += path.name.startswith("test_")
    assert n_files > 80  # the walk saw the unit tests
    # no helper module beside the test folders: shared code is testkit's
    loose = [p.name for p in tests.glob("*.py") if p.name != "conftest.py"]
    assert loose == [], f"helpers outside tests/testkit: {loose}"
