"""Torch surrogate of the simulator: operating conditions -> fatigue damage rate.

Public API: :class:`Surrogate` (``Surrogate.load(path).predict(frame)``),
:func:`fit_surrogate`, :class:`DeepEnsembleRegressor` (its training settings
:class:`TrainingSettings`), :class:`SplitConformal`,
:class:`DomainChecker`, :func:`make_synthetic_dataset`. Operating-log replay
(the digital twin) is in :mod:`drillfatigue.surrogate.twin`; the user-facing
query vocabulary (units) in :mod:`drillfatigue.io.names`.
"""

from __future__ import annotations

from drillfatigue.surrogate.conformal import SplitConformal, conformal_quantile
from drillfatigue.surrogate.data import make_synthetic_dataset, split_by_case
from drillfatigue.surrogate.facade import PREDICTION_COLUMNS, Surrogate, fit_surrogate
from drillfatigue.surrogate.model import DeepEnsembleRegressor, TrainingSettings
from drillfatigue.surrogate.ood import DomainChecker

__all__ = [
    "PREDICTION_COLUMNS",
    "DeepEnsembleRegressor",
    "DomainChecker",
    "SplitConformal",
    "Surrogate",
    "TrainingSettings",
    "conformal_quantile",
    "fit_surrogate",
    "make_synthetic_dataset",
    "split_by_case",
]
