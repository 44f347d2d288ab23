"""Every code block of README.md runs, in order, in a scratch copy of the inputs.

Blocks marked ``<!-- readme-test: skip (...) -->`` are the two make targets
(the whole pipeline, and the suite this test is part of). Blocks marked
``needs-model`` get a tiny surrogate trained here in place of the pipeline's
``data/surrogate/model`` (:mod:`testkit.doc_blocks`, which runs the other
documents' commands the same way).
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest
from testkit.doc_blocks import ROOT, blocks, scratch
from testkit.tiny_surrogate import train_tiny_surrogate


def readme_blocks() -> list[tuple[str, str, str]]:
    return [(b.mark, b.lang, b.code) for b in blocks(ROOT / "README.md")]


def test_the_readme_has_the_blocks_this_test_expects() -> None:
    found = readme_blocks()
    assert [lang for _, lang, _ in found].count("python") >= 1
    assert sum(lang == "bash" and mark == "" for mark, lang, _ in found) >= 1
    assert {mark for mark, _, _ in found} <= {"", "skip", "needs-model"}
    assert all("make " in code for mark, _, code in found if mark == "skip")


@pytest.mark.slow
@pytest.mark.timeout(900)  # the first run of the kernels on a fresh cache compiles them
def test_every_readme_code_block_runs(tmp_path: Path) -> None:
    env = scratch(tmp_path)
    model_ready = False
    for i, (mark, lang, code) in enumerate(readme_blocks()):
        if mark == "skip":
            continue
        if mark == "needs-model" and not model_ready:
            train_tiny_surrogate(ROOT / "params.yaml", tmp_path / "data" / "surrogate" / "model")
            model_ready = True
        cmd = ["bash", "-euo", "pipefail", "-c", code] if lang == "bash" else \
            [sys.executable, "-c", code]
        out = subprocess.run(cmd, cwd=tmp_path, env=env, capture_output=True, text=True,
                             timeout=600)
        assert out.returncode == 0, f"README block {i} ({lang}) failed:\n{code}\n{out.stderr[-3000:]}"
    # the figure the README shows is the one the quickstart draws
    assert (tmp_path / "runs/quick_fatigue/damage_along_string.png").stat().st_size > 10_000
    assert (tmp_path / "runs/profile_3.png").is_file() and (tmp_path / "runs/tnd.png").is_file()
