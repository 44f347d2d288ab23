"""Every function of the package fits on a screen or two and takes a handful of arguments:
at most 150 lines and 16 parameters (kernels take named bundles, STYLE.md habit 20)."""

from __future__ import annotations

import ast
from pathlib import Path

import drillfatigue

ROOT = Path(drillfatigue.__file__).resolve().parent
MAX_LINES = 150
MAX_PARAMS = 16

def _n_params(fn: ast.FunctionDef | ast.AsyncFunctionDef) -> int:
    """Every parameter a caller can pass (``self`` included, ``*args`` and ``**kw`` one each)."""
    a = fn.args
    return (len(a.posonlyargs) + len(a.args) + len(a.kwonlyargs)
            + (a.vararg is not None) + (a.kwarg is not None))


def _oversized() -> dict[tuple[str, str], str]:
    """``(module path, function name) -> what is over`` for every function over a limit."""
    found: dict[tuple[str, str], str] = {}
    for path in sorted(ROOT.rglob("*.py")):
        tree = ast.parse(path.read_text(encoding="utf-8"), filename=str(path))
        for node in ast.walk(tree):
            if not isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef):
                continue
            assert node.end_lineno is not None
            lines = node.end_lineno - node.lineno + 1
            params = _n_params(node)
            if lines > MAX_LINES or params > MAX_PARAMS:
                key = (path.relative_to(ROOT).as_posix(), node.name)
                found[key] = f"line {node.lineno}: {lines} lines, {params} parameters"
    return found


def test_no_function_is_over_150_lines_or_16_parameters() -> None:
    over = _oversized()
    assert not over, "split these or give them named bundles:\n" + "\n".join(
        f"{path}:{name} ({what})" for (path, name), what in sorted(over.items()))


def test_the_limits_are_measured_as_stated() -> None:
    code = ("def f(a, /, b, *c, d, **e):\n" + "    x = 1\n" * 149
            + "async def g(self):\n    pass\n")
    tree = ast.parse(code)
    f, g = tree.body
    assert isinstance(f, ast.FunctionDef) and isinstance(g, ast.AsyncFunctionDef)
    assert _n_params(f) == 5 and _n_params(g) == 1
    assert f.end_lineno is not None and f.end_lineno - f.lineno + 1 == 150
