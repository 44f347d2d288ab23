"""docs/dataset.md runs as written, on a small stand-in of the research dataset.

The page's Python and shell blocks run in order in one scratch folder whose
``data/research/dataset`` holds the fixture ``tests/data/research_dataset``
(a slice of a real pipeline output with the dataset's columns), so the
documented snippets load, write a prediction file and score it as a
researcher's clone would once the dataset is there.
"""

from __future__ import annotations

import shutil
import subprocess
import sys
from pathlib import Path

import pytest
from testkit.doc_blocks import ROOT, SHELL, blocks, scratch

DOC = ROOT / "docs" / "dataset.md"
FIXTURE = ROOT / "tests" / "data" / "research_dataset"


def test_the_page_has_each_loader_and_the_score_command() -> None:
    code = "\n".join(b.code for b in blocks(DOC))
    for needle in ("load_split(", "load_datasets(", "load_torch_splits(",
                   "drillfatigue benchmark score", "drillfatigue benchmark leaderboard"):
        assert needle in code, needle


@pytest.mark.slow
@pytest.mark.timeout(600)
def test_every_documented_snippet_runs(tmp_path: Path) -> None:
    pytest.importorskip("datasets")
    env = scratch(tmp_path)
    data = tmp_path / "data" / "research" / "dataset"
    data.mkdir(parents=True)
    for split in ("train", "heldout"):
        shutil.copy(FIXTURE / f"{split}.parquet", data / f"{split}.parquet")
    n_python = n_shell = 0
    for i, b in enumerate(blocks(DOC)):
        if b.mark == "skip":
            assert b.why.startswith("(") and len(b.why) > 4, f"block {i}: skip says why"
            continue
        if b.lang == "python":
            cmd = [sys.executable, "-c", b.code]
            n_python += 1
        elif b.lang in SHELL:
            cmd = ["bash", "-euo", "pipefail", "-c", b.code]
            n_shell += 1
        else:
            continue
        out = subprocess.run(cmd, cwd=tmp_path, env=env, capture_output=True, text=True,
                             timeout=300)
        assert out.returncode == 0, f"block {i} failed:\n{b.code}\n{out.stdout[-1500:]}\n" \
                                    f"{out.stderr[-3000:]}"
    assert n_python >= 4 and n_shell >= 1
    assert (tmp_path / "score.json").is_file()
