"""A torch ``Dataset`` of one split of the research dataset.

Each item is one row (a case, joint and location): the numeric inputs as a
float32 tensor, the categorical inputs as integer codes, the target as log10
of the damage rate per hour (floored at the censoring floor), a censoring flag
(the simulated life is beyond the horizon: the answer there is "longer than
the horizon", docs/surrogate.md) and the case id, so that a sampler or a
cross-validation can keep a case's rows together.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd
import torch
from torch.utils.data import Dataset

from drillfatigue.benchmark.splits import DATASET_DIR, GROUP_COLUMN, KEY_COLUMNS, SPLITS, load_splits
from drillfatigue.errors import InputError
from drillfatigue.surrogate.data import log10_target
from drillfatigue.sweep.dataset import column_roles

#: Defaults of the surrogate's configuration (``params.yaml`` ``surrogate``).
RATE_FLOOR_PER_H = 1e-12
HORIZON_H = 1e5


def input_columns(frame: pd.DataFrame) -> tuple[list[str], list[str]]:
    """The numeric and the categorical input columns of a split (the card's
    ``input`` role, :func:`drillfatigue.sweep.dataset.column_roles`; the split
    name and the row's keys are not inputs, the location's name is)."""
    roles = column_roles(list(frame.columns), [])
    inputs = [c for c in frame.columns if roles[c] == "input" and c != "split"
              and (c not in KEY_COLUMNS or c == "location")]
    numeric = [c for c in inputs if pd.api.types.is_numeric_dtype(frame[c].dtype)]
    return numeric, [c for c in inputs if c not in numeric]


class DamageDataset(Dataset[dict[str, Any]]):
    """Rows of one split as tensors.

    Parameters
    ----------
    frame : DataFrame
        A split (:func:`drillfatigue.benchmark.splits.load_split`).
    criterion : str
        Target criterion: the column ``damage_rate_per_h_<criterion>``.
    numeric, categorical : sequence of str, optional
        Input columns; by default every input column of the card
        (:func:`input_columns`).
    categories : mapping, optional
        Levels per categorical column (code = position); by default the sorted
        levels of ``frame``. Pass the training split's levels
        (``train_set.categories``) to the held-out split's dataset so the codes
        agree; a level not among them is an InputError.
    rate_floor_per_h, horizon_h : float
        Censoring floor of the rate (1/h) and the life horizon (h).

    Items are dicts: ``x`` (float32, shape (n_numeric,)), ``x_cat`` (int64,
    shape (n_categorical,)), ``y`` (float32 scalar, log10 damage rate per
    hour), ``censored`` (bool scalar: y < -log10(horizon_h)) and ``case_id``
    (str).
    """

    def __init__(self, frame: pd.DataFrame, criterion: str = "matake",
                 numeric: Sequence[str] | None = None, categorical: Sequence[str] | None = None,
                 categories: Mapping[str, Sequence[str]] | None = None,
                 rate_floor_per_h: float = RATE_FLOOR_PER_H, horizon_h: float = HORIZON_H
                 ) -> None:
        target = f"damage_rate_per_h_{criterion}"
        if target not in frame.columns:
            raise InputError("criterion", f"no column {target!r} in the split",
                             ", ".join(c[len("damage_rate_per_h_"):] for c in frame.columns
                                       if c.startswith("damage_rate_per_h_")))
        num_default, cat_default = input_columns(frame)
        self.numeric = list(num_default if numeric is None else numeric)
        self.categorical = list(cat_default if categorical is None else categorical)
        for col in self.numeric + self.categorical:
            if col not in frame.columns:
                raise InputError(col, "column missing from the split", "the card's inputs")
        self.categories = {c: list(categories[c]) if categories is not None else
                           sorted(map(str, pd.unique(frame[c].astype(str))))
                           for c in self.categorical}
        codes = np.zeros((len(frame), len(self.categorical)), dtype=np.int64)
        for j, col in enumerate(self.categorical):
            lookup = {v: i for i, v in enumerate(self.categories[col])}
            values = frame[col].astype(str).to_numpy()
            unseen = sorted(set(values) - set(lookup))
            if unseen:
                raise InputError(col, f"level(s) {unseen} not in the categories",
                                 ", ".join(self.categories[col]))
            codes[:, j] = [lookup[v] for v in values]
        y = log10_target(frame[target].to_numpy(), rate_floor_per_h)
        self.x = torch.tensor(frame[self.numeric].to_numpy(dtype=np.float64),
                                 dtype=torch.float32)
        self.x_cat = torch.as_tensor(codes)
        self.y = torch.tensor(y, dtype=torch.float32)
        self.censored = torch.as_tensor(y < -math.log10(horizon_h))
        self.case_ids = frame[GROUP_COLUMN].astype(str).tolist()

    def __len__(self) -> int:
        return len(self.case_ids)

    def __getitem__(self, i: int) -> dict[str, Any]:
        return {"x": self.x[i], "x_cat": self.x_cat[i], "y": self.y[i],
                "censored": self.censored[i], "case_id": self.case_ids[i]}


def load_torch_splits(dataset_dir: str | Path = DATASET_DIR, criterion: str = "matake",
                      **kwargs: Any) -> dict[str, DamageDataset]:
    """Every split as a :class:`DamageDataset`, the categorical codes shared.

    The levels of each categorical input are those of all splits together
    (the design's levels: knowing that a held-out case has another BHA leaks
    no target). ``kwargs`` go to :class:`DamageDataset`.
    """
    frames = load_splits(dataset_dir)
    first = DamageDataset(frames[SPLITS[0]], criterion, **kwargs)
    categories = {c: sorted(set().union(*(map(str, pd.unique(f[c].astype(str)))
                                          for f in frames.values())))
                  for c in first.categorical}
    kwargs = kwargs | {"numeric": first.numeric, "categorical": first.categorical,
                       "categories": categories}
    return {s: DamageDataset(f, criterion, **kwargs) for s, f in frames.items()}
