"""Every shell command in docs/*.md and data/examples/*.md runs as written.

The machinery and the markers are :mod:`testkit.doc_blocks`; README.md's
blocks are run by tests/pipeline/test_readme.py.
"""

from __future__ import annotations

from pathlib import Path

import pytest
from testkit.doc_blocks import ROOT, SHELL, blocks, documents, run_document

DOCS = documents()


def test_the_documents_with_commands_are_found() -> None:
    with_commands = {p.relative_to(ROOT).as_posix() for p in DOCS
                     if any(b.lang in SHELL for b in blocks(p))}
    assert {"docs/field-data.md", "docs/service.md", "docs/getting-started.md",
            "data/examples/README.md"} <= with_commands


@pytest.mark.slow
@pytest.mark.timeout(1200)  # a first run of the kernels on a fresh cache compiles them
@pytest.mark.parametrize("doc", DOCS, ids=[p.relative_to(ROOT).as_posix() for p in DOCS])
def test_every_documented_command_runs(doc: Path, tmp_path: Path) -> None:
    run_document(doc, tmp_path)
