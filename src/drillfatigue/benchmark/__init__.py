"""The research dataset as a benchmark: loaders, card, scoring, baselines, leaderboard.

The research dataset (``data/research/dataset/``) holds one parquet file per
split, ``train.parquet`` and ``heldout.parquet``, one row per case, joint and
location, split by case (docs/dataset.md). This subpackage reads it
(:mod:`~drillfatigue.benchmark.splits`: pandas, Hugging Face ``datasets``, a
torch ``Dataset``), writes its card and Croissant metadata
(:mod:`~drillfatigue.benchmark.card`), scores a model's prediction file on the
held-out split with the project's metrics (:mod:`~drillfatigue.benchmark.score`)
and fits the baselines of the leaderboard
(:mod:`~drillfatigue.benchmark.baselines`, :mod:`~drillfatigue.benchmark.leaderboard`).
"""

from __future__ import annotations

from drillfatigue.benchmark.splits import (DATASET_DIR, DATASET_VERSION, SPLITS, load_datasets,
                                           load_split)

__all__ = ["DATASET_DIR", "DATASET_VERSION", "SPLITS", "load_datasets", "load_split"]
