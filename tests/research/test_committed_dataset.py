"""The research dataset assembled from its committed case files loads as docs/dataset.md says.

The DVC stage ``research_dataset`` (``pipeline/research_dataset.py``) assembles the
committed case files into the splits, here into a scratch copy of ``data/research``
as a fresh clone's ``make repro`` does; the bytes are those the committed card's
Croissant metadata hashes. The page's loader snippets (pandas, Hugging Face
``datasets``, torch) run as written on them. The splits are disjoint by case and hold
every case of their designs.
"""

from __future__ import annotations

import hashlib
import json
import shutil
import subprocess
import sys
from pathlib import Path

import pandas as pd
import pytest
from testkit.doc_blocks import ROOT, blocks

RESEARCH = ROOT / "data" / "research"
CARD = RESEARCH / "dataset"
N_TRAIN, N_HELDOUT = 2048, 128


@pytest.fixture(scope="module")
def scratch(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A folder whose ``data/research`` holds the committed case files, designs and card,
    with the splits assembled by the stage script."""
    root = tmp_path_factory.mktemp("clone")
    research = root / "data" / "research"
    for part in ("cases", "design"):
        shutil.copytree(RESEARCH / part, research / part)
    shutil.copy(RESEARCH / ".drillfatigue.json", research / ".drillfatigue.json")
    (research / "dataset").mkdir()
    for name in ("README.md", "croissant.json"):
        shutil.copy(CARD / name, research / "dataset" / name)
    res = subprocess.run([sys.executable, str(ROOT / "pipeline" / "research_dataset.py"),
                          "--params", str(ROOT / "params.yaml"), "--root", str(research)],
                         cwd=root, capture_output=True, text=True, timeout=600)
    assert res.returncode == 0, res.stderr[-3000:]
    return root


def _snippet(needle: str) -> str:
    found = [b.code for b in blocks(ROOT / "docs" / "dataset.md")
             if b.lang == "python" and needle in b.code]
    assert len(found) == 1, needle
    return found[0]


def _run(code: str, cwd: Path) -> str:
    res = subprocess.run([sys.executable, "-c", code], cwd=cwd, capture_output=True, text=True,
                         timeout=600)
    assert res.returncode == 0, res.stderr[-3000:]
    return res.stdout


@pytest.mark.slow
def test_the_splits_hold_every_case_of_their_designs_once(scratch: Path) -> None:
    dataset = scratch / "data" / "research" / "dataset"
    for split, n in (("train", N_TRAIN), ("heldout", N_HELDOUT)):
        design = pd.read_parquet(RESEARCH / "design" / f"{split}.parquet", columns=["case_id"])
        rows = pd.read_parquet(dataset / f"{split}.parquet", columns=["case_id", "joint",
                                                                       "location", "split"])
        assert len(design) == n and set(rows["case_id"]) == set(design["case_id"]), split
        assert (rows["split"] == split).all()
        assert not rows.duplicated(["case_id", "joint", "location"]).any()
    train = set(pd.read_parquet(dataset / "train.parquet", columns=["case_id"])["case_id"])
    held = set(pd.read_parquet(dataset / "heldout.parquet", columns=["case_id"])["case_id"])
    assert not train & held


@pytest.mark.slow
def test_the_committed_card_describes_the_assembled_bytes(scratch: Path) -> None:
    card = (CARD / "README.md").read_text(encoding="utf-8")
    assert card.startswith("---\n") and "drillfatigue dataset research" in card
    meta = json.loads((CARD / "croissant.json").read_text(encoding="utf-8"))
    assert meta["@type"] in ("sc:Dataset", "Dataset")
    for entry in meta["distribution"]:
        data = (scratch / "data" / "research" / "dataset" / entry["contentUrl"]).read_bytes()
        assert hashlib.sha256(data).hexdigest() == entry["sha256"], entry["contentUrl"]


@pytest.mark.slow
def test_the_documented_loaders_load_the_assembled_splits(scratch: Path) -> None:
    out = _run(_snippet("load_split(\"train\")"), scratch)
    assert f"{N_TRAIN} training cases, {N_HELDOUT} held out" in out
    pytest.importorskip("datasets")
    assert "Value" in _run(_snippet("load_datasets("), scratch)
    out = _run(_snippet("load_torch_splits("), scratch)
    assert "torch.Size([256" in out and "torch.bool" in out
