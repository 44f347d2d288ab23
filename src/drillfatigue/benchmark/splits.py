"""Loaders of the research dataset's splits: pandas, Hugging Face ``datasets``.

The dataset folder holds ``train.parquet`` and ``heldout.parquet`` (one row per
case, joint and location; a ``split`` column names the file's split). The
splits are by case: the held-out cases come from a design of their own seed and
no case id appears in both (a case id hashes the case's simulation inputs, so a
shared id would be the same simulation). The torch ``Dataset`` is in
:mod:`drillfatigue.benchmark.torch_dataset`.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import pandas as pd

from drillfatigue.errors import InputError

#: Where the research sweep assembles the dataset (repository-relative).
DATASET_DIR = Path("data/research/dataset")
#: Version of the dataset's schema and splits (semantic versioning: a new column is a
#: minor version, a changed split or target a major one).
DATASET_VERSION = "1.0.0"
#: The splits, in the order they are listed.
SPLITS: tuple[str, ...] = ("train", "heldout")
SPLIT_COLUMN = "split"
GROUP_COLUMN = "case_id"
#: Columns that name one row of a split.
KEY_COLUMNS: tuple[str, ...] = ("case_id", "joint", "location")
#: The design's inputs: what a case's simulation was asked to do.
DESIGN_INPUTS: tuple[str, ...] = (
    "operation.rpm", "operation.wob_N", "bit.rop_c1_m_per_N_sqrt_s", "operation.bit_md_m",
    "operation.lobe_amplitude_m", "operation.mud_density_kg_per_m3", "friction.mu_dynamic",
    "well.profile", "string.bha")


def split_path(split: str, dataset_dir: str | Path = DATASET_DIR) -> Path:
    """The parquet file of ``split`` in ``dataset_dir``.

    Raises
    ------
    InputError
        An unknown split, or a file that is not there.
    """
    if split not in SPLITS:
        raise InputError("split", f"unknown split {split!r}", ", ".join(SPLITS))
    path = Path(dataset_dir) / f"{split}.parquet"
    if not path.is_file():
        raise InputError(str(path), "dataset file not found",
                         "a research dataset folder (docs/dataset.md)")
    return path


def load_split(split: str, dataset_dir: str | Path = DATASET_DIR) -> pd.DataFrame:
    """One split of the research dataset as a DataFrame.

    Parameters
    ----------
    split : {"train", "heldout"}
    dataset_dir : path
        The dataset folder (``data/research/dataset`` by default).

    Returns
    -------
    DataFrame
        One row per case, joint and location; columns as documented in the
        folder's ``README.md``.
    """
    frame = pd.read_parquet(split_path(split, dataset_dir))
    if SPLIT_COLUMN in frame.columns and not (frame[SPLIT_COLUMN] == split).all():
        raise InputError(str(split_path(split, dataset_dir)),
                         f"rows whose {SPLIT_COLUMN!r} is not {split!r}",
                         "each file holds its own split")
    return frame


def load_splits(dataset_dir: str | Path = DATASET_DIR) -> dict[str, pd.DataFrame]:
    """Every split, checked disjoint by case (:func:`check_disjoint`)."""
    frames = {s: load_split(s, dataset_dir) for s in SPLITS}
    check_disjoint(frames)
    return frames


def check_disjoint(frames: Mapping[str, pd.DataFrame]) -> None:
    """Raise InputError when a case id is in more than one split."""
    seen: dict[str, str] = {}
    for split, frame in frames.items():
        for case in pd.unique(frame[GROUP_COLUMN].astype(str)):
            if case in seen:
                raise InputError(GROUP_COLUMN, f"case {case} in both {seen[case]} and {split}",
                                 "splits by case: every case in one split")
            seen[case] = split


def hf_dtype(series: pd.Series) -> str:
    """The Hugging Face ``datasets`` value type of a column (``float64``, ``int64``,
    ``bool`` or ``string``)."""
    kind = series.dtype
    if pd.api.types.is_bool_dtype(kind):
        return "bool"
    if pd.api.types.is_integer_dtype(kind):
        return "int64"
    if pd.api.types.is_float_dtype(kind):
        return "float64"
    return "string"


def load_datasets(dataset_dir: str | Path = DATASET_DIR,
                  splits: Sequence[str] = SPLITS) -> Any:
    """The splits as a Hugging Face ``datasets.DatasetDict``, features typed.

    Built from the parquet files through pandas (no download, no cache
    folder): each column's type is the one :func:`hf_dtype` gives, the same in
    every split.

    Returns
    -------
    datasets.DatasetDict
        ``{"train": Dataset, "heldout": Dataset}``.
    """
    try:
        import datasets  # optional: the Hugging Face datasets package
    except ImportError as exc:  # an optional loader: say what to install
        raise InputError("datasets", "the Hugging Face datasets package is not installed",
                         "pip install datasets") from exc
    frames = {s: load_split(s, dataset_dir) for s in splits}
    check_disjoint(frames)
    first = frames[splits[0]]
    features = datasets.Features({c: datasets.Value(hf_dtype(first[c])) for c in first.columns})
    out = {}
    for split, frame in frames.items():
        if list(frame.columns) != list(first.columns):
            raise InputError(str(split_path(split, dataset_dir)),
                             f"columns differ from the {splits[0]} split's",
                             "one schema for every split")
        out[split] = datasets.Dataset.from_pandas(frame, features=features, preserve_index=False,
                                                  split=datasets.NamedSplit(split))
    return datasets.DatasetDict(out)
