"""Loaders of the research dataset: pandas, Hugging Face ``datasets``, torch.

The fixture ``tests/data/research_dataset`` is a slice of a real pipeline
output (6 training cases, 2 held-out cases of their own design).
"""

from __future__ import annotations

import math
import shutil
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from drillfatigue.benchmark import SPLITS, load_datasets, load_split
from drillfatigue.benchmark.splits import check_disjoint, load_splits
from drillfatigue.errors import InputError

DATA = Path(__file__).resolve().parents[2] / "data" / "research_dataset"


def test_load_split_returns_the_split_rows() -> None:
    train = load_split("train", DATA)
    heldout = load_split("heldout", DATA)
    assert (train["split"] == "train").all() and (heldout["split"] == "heldout").all()
    assert train["case_id"].nunique() == 6 and heldout["case_id"].nunique() == 2
    assert not set(train["case_id"]) & set(heldout["case_id"])


def test_unknown_split_and_missing_folder_are_input_errors(tmp_path: Path) -> None:
    with pytest.raises(InputError, match="unknown split 'test'"):
        load_split("test", DATA)
    with pytest.raises(InputError, match="dataset file not found"):
        load_split("train", tmp_path)


def test_a_case_in_both_splits_is_refused(tmp_path: Path) -> None:
    train = load_split("train", DATA)
    heldout = load_split("heldout", DATA)
    leak = pd.concat([heldout, train[train["case_id"] == train["case_id"].iloc[0]]
                      .assign(split="heldout")])
    with pytest.raises(InputError, match="in both train and heldout"):
        check_disjoint({"train": train, "heldout": leak})
    for name in ("train.parquet",):
        shutil.copy(DATA / name, tmp_path / name)
    leak.to_parquet(tmp_path / "heldout.parquet", index=False)
    with pytest.raises(InputError, match="splits by case"):
        load_splits(tmp_path)


def test_a_row_of_another_split_is_refused(tmp_path: Path) -> None:
    shutil.copy(DATA / "heldout.parquet", tmp_path / "heldout.parquet")
    load_split("train", DATA).assign(split="heldout").to_parquet(tmp_path / "train.parquet")
    with pytest.raises(InputError, match="rows whose 'split' is not 'train'"):
        load_split("train", tmp_path)


def test_datasets_dict_has_both_splits_with_typed_features() -> None:
    datasets = pytest.importorskip("datasets")
    dd = load_datasets(DATA)
    assert set(dd) == set(SPLITS)
    train = load_split("train", DATA)
    assert dd["train"].num_rows == len(train)
    assert dd["heldout"].features == dd["train"].features
    feats = dd["train"].features
    assert feats["operation.rpm"] == datasets.Value("float64")
    assert feats["joint"] == datasets.Value("int64")
    assert feats["case_id"] == datasets.Value("string")
    assert dd["train"][0]["case_id"] == train["case_id"].iloc[0]
    assert math.isclose(dd["train"][3]["damage_rate_per_h_matake"],
                        float(train["damage_rate_per_h_matake"].iloc[3]))


def test_torch_dataset_items_and_shared_codes() -> None:
    torch = pytest.importorskip("torch")
    from drillfatigue.benchmark.torch_dataset import DamageDataset, load_torch_splits

    sets = load_torch_splits(DATA)
    tr, ho = sets["train"], sets["heldout"]
    assert tr.categories == ho.categories and tr.numeric == ho.numeric
    assert "joint" not in tr.numeric and "damage_rate_per_h_matake" not in tr.numeric
    assert "stick_slip_severity" not in tr.numeric  # post-run columns are not inputs
    item = tr[0]
    assert item["x"].dtype == torch.float32 and item["x"].shape == (len(tr.numeric),)
    assert item["x_cat"].dtype == torch.int64 and item["x_cat"].shape == (len(tr.categorical),)
    frame = load_split("train", DATA)
    y = np.log10(np.maximum(frame["damage_rate_per_h_matake"].to_numpy(), 1e-12))
    np.testing.assert_allclose(tr.y.numpy(), y.astype(np.float32))
    np.testing.assert_array_equal(tr.censored.numpy(), y < -5.0)
    assert item["case_id"] == frame["case_id"].iloc[0]
    batch = next(iter(torch.utils.data.DataLoader(tr, batch_size=8)))
    assert batch["x"].shape == (8, len(tr.numeric)) and len(batch["case_id"]) == 8
    with pytest.raises(InputError, match="not in the categories"):
        DamageDataset(load_split("heldout", DATA),
                      categories={c: ["nothing"] for c in tr.categorical})
    with pytest.raises(InputError, match="no column 'damage_rate_per_h_findley'"):
        DamageDataset(frame, criterion="findley")
