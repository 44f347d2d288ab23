"""Surrogate of the simulator: operating conditions -> fatigue damage rate.

What ``drillfatigue query``, the digital twin, the service and ``plan rank``
serve is gradient boosting (scikit-learn, ``surrogate.served_model: gbm`` in
``params.yaml``) with a cross-conformal interval by case and a domain check
(:mod:`drillfatigue.surrogate.served_gbm`, :mod:`drillfatigue.surrogate.gbm`);
a torch deep ensemble (:class:`DeepEnsembleRegressor`, split-conformal, with
TorchScript and ONNX exports) is the alternative behind the same interface and
the library's default. docs/surrogate.md says why gradient boosting is served.

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
