"""TorchScript export of the surrogate for serving.

The exported module is the :class:`~drillfatigue.surrogate.model.EnsembleModule`
with the feature scaler, the one-hot encoder and the conformal quantile baked
in: ``module(x_num, x_cat) -> (n, 4)`` = log10 damage rate per hour, sigma,
lower and upper interval bound, from raw SI features (float32, columns in the
order of ``metadata.json["preprocessor"]["numeric"]``) and category codes
(int64, levels in ``metadata.json["preprocessor"]["categories"]``). The
out-of-domain test is not part of the export (it needs the reference set);
servers use ``ood_reference.npy`` and ``metadata.json["domain"]``.

ONNX is not exported: ``torch.onnx.export`` needs the ``onnx`` and
``onnxscript`` packages (torch >= 2.9 exports through the dynamo exporter),
which are not project dependencies.
"""

from __future__ import annotations

import warnings
from pathlib import Path
from typing import TYPE_CHECKING

import torch

if TYPE_CHECKING:
    from drillfatigue.surrogate.facade import Surrogate


def export_torchscript(surrogate: Surrogate, path: str | Path) -> Path:
    """Script the surrogate's module and save it to ``path``."""
    with warnings.catch_warnings():
        # torch 2.13 marks TorchScript deprecated in favour of torch.export;
        # scripted modules still load in C++ (libtorch) without Python.
        warnings.simplefilter("ignore", DeprecationWarning)
        scripted = torch.jit.script(surrogate.module.eval())
    p = Path(path)
    scripted.save(str(p))
    return p


def load_torchscript(path: str | Path) -> torch.jit.ScriptModule:
    """Load an exported module (CPU)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", DeprecationWarning)
        return torch.jit.load(str(path), map_location="cpu")
