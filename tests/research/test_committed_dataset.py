"""The research dataset committed in ``data/research/dataset`` loads as docs/dataset.md says.

The page's loader snippets (pandas, Hugging Face ``datasets``, torch) run as written
from the repository root, on the committed files (not a fixture): a fresh clone loads
the splits. The splits are disjoint by case, hold every case of their designs, and
the card and its Croissant metadata sit beside them.
"""

from __future__ import annotations

import json
import subprocess
import sys

import pandas as pd
import pytest
from testkit.doc_blocks import ROOT, blocks

DATASET = ROOT / "data" / "research" / "dataset"
DESIGN = ROOT / "data" / "research" / "design"
N_TRAIN, N_HELDOUT = 2048, 128


def _snippet(needle: str) -> str:
    found = [b.code for b in blocks(ROOT / "docs" / "dataset.md")
             if b.lang == "python" and needle in b.code]
    assert len(found) == 1, needle
    return found[0]


def _run(code: str) -> str:
    res = subprocess.run([sys.executable, "-c", code], cwd=ROOT, capture_output=True, text=True,
                         timeout=600)
    assert res.returncode == 0, res.stderr[-3000:]
    return res.stdout


def test_the_splits_hold_every_case_of_their_designs_once() -> None:
    for split, n in (("train", N_TRAIN), ("heldout", N_HELDOUT)):
        design = pd.read_parquet(DESIGN / f"{split}.parquet", columns=["case_id"])
        rows = pd.read_parquet(DATASET / f"{split}.parquet", columns=["case_id", "joint",
                                                                       "location", "split"])
        assert len(design) == n and set(rows["case_id"]) == set(design["case_id"]), split
        assert (rows["split"] == split).all()
        assert not rows.duplicated(["case_id", "joint", "location"]).any()
    train = set(pd.read_parquet(DATASET / "train.parquet", columns=["case_id"])["case_id"])
    held = set(pd.read_parquet(DATASET / "heldout.parquet", columns=["case_id"])["case_id"])
    assert not train & held


def test_the_card_and_the_croissant_metadata_are_there() -> None:
    card = (DATASET / "README.md").read_text(encoding="utf-8")
    assert card.startswith("---\n") and "drillfatigue dataset research" in card
    meta = json.loads((DATASET / "croissant.json").read_text(encoding="utf-8"))
    assert meta["@type"] in ("sc:Dataset", "Dataset")


@pytest.mark.slow
def test_the_documented_loaders_load_the_committed_splits() -> None:
    out = _run(_snippet("load_split(\"train\")"))
    assert f"{N_TRAIN} training cases, {N_HELDOUT} held out" in out
    pytest.importorskip("datasets")
    assert "Value" in _run(_snippet("load_datasets("))
    out = _run(_snippet("load_torch_splits("))
    assert "torch.Size([256" in out and "torch.bool" in out
