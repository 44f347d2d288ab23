"""Imports sit at the top of modules; a local one says why.

An import inside a function hides a dependency from the reader and from
import-linter, so the package keeps them only where an optional extra (torch,
FastAPI, dask, dvclive), a real import cycle or the command line's start-up
time needs one. Such an import carries a comment naming the reason, with one
of the words ``optional``, ``cycle`` or ``start-up``: on its own line, or on
the line just above its block of imports (one comment may serve a block).
"""

from __future__ import annotations

import ast
import json
import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

PACKAGE = Path(__file__).resolve().parents[2] / "src" / "drillfatigue"
REASON = re.compile(r"#.*\b(optional|cycle|start-up)\b")
FUNCTIONS = (ast.FunctionDef, ast.AsyncFunctionDef, ast.Lambda)
IMPORTS = (ast.Import, ast.ImportFrom)


def local_imports(tree: ast.AST) -> list[ast.stmt]:
    """Import statements anywhere inside a function body of ``tree``."""
    found: list[ast.stmt] = []

    def walk(node: ast.AST, in_function: bool) -> None:
        for child in ast.iter_child_nodes(node):
            if in_function and isinstance(child, IMPORTS):
                found.append(child)
            walk(child, in_function or isinstance(child, FUNCTIONS))

    walk(tree, False)
    return found


def undocumented(source: str) -> list[int]:
    """Line numbers of the local imports in ``source`` that give no reason."""
    tree = ast.parse(source)
    lines = source.splitlines()
    import_lines = {n for node in ast.walk(tree) if isinstance(node, IMPORTS)
                    for n in range(node.lineno, (node.end_lineno or node.lineno) + 1)}
    missing = []
    for node in local_imports(tree):
        own = lines[node.lineno - 1:(node.end_lineno or node.lineno)]
        if any(REASON.search(line) for line in own):
            continue
        # the first line above the block of imports (and blank lines) this one is in
        above = node.lineno - 1
        while above >= 1 and (above in import_lines or not lines[above - 1].strip()):
            above -= 1
        if above < 1 or not REASON.search(lines[above - 1]):
            missing.append(node.lineno)
    return missing


def test_every_local_import_in_the_package_names_its_reason():
    bad = [f"{path.relative_to(PACKAGE.parent)}:{line}"
           for path in sorted(PACKAGE.rglob("*.py"))
           for line in undocumented(path.read_text(encoding="utf-8"))]
    assert not bad, ("imports inside functions without a '# optional ...', '# cycle: ...' or "
                     "'# start-up: ...' comment (move them to the module top, or say why not): "
                     + ", ".join(bad))


@pytest.mark.parametrize("source, expected", [
    # a bare local import, and one under a comment that gives no reason
    ("def f():\n    import json\n    return json\n", [2]),
    ("def f():\n    # json\n    import json\n", [3]),
    ("def f():  # noqa: ANN202\n    import json\n", [2]),
    # a reason on the line, above the line, above its block, on a try line
    ("def f():\n    import torch  # optional extra [surrogate]\n", []),
    ("def f():\n    # cycle: b imports a\n    from b import c\n", []),
    ("def f():\n    # start-up: slow\n    import a\n    import b\n\n    from c import (d,\n"
     "                   e)\n", []),
    ("def f():\n    try:  # optional extra [service]\n        import uvicorn\n"
     "    except ImportError:\n        pass\n", []),
    # the block ends at code: a later import needs its own reason
    ("def f():\n    # optional: x\n    import x\n    x.run()\n    import y\n", [5]),
    # nested functions and methods count; module-level and class-level imports do not
    ("class A:\n    import os\n    def m(self):\n        def g():\n            import re\n", [5]),
    ("import os\nif os:\n    import re\n", []),
])
def test_the_check_flags_exactly_the_undocumented_ones(source, expected):
    assert undocumented(source) == expected


def test_the_help_loads_no_optional_extra_and_no_start_up_module():
    # what the 'optional' and 'start-up' local imports keep out of `drillfatigue --help`
    code = ("import sys\nfrom drillfatigue.cli import main\nmain(['--help'])\n"
            "import json\nprint(json.dumps(sorted(m for m in ('torch', 'sklearn', 'fastapi', "
            "'uvicorn', 'matplotlib', 'dask', 'distributed', 'dvclive', 'drillfatigue.surrogate', "
            "'drillfatigue.studies', 'drillfatigue.sweep') if m in sys.modules)))\n")
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join([str(PACKAGE.parent), env.get("PYTHONPATH", "")])
    out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True,
                         timeout=120, check=True)
    assert json.loads(out.stdout.strip().splitlines()[-1]) == []

