"""TorchScript and ONNX exports of the surrogate for serving.

The exported module is the :class:`~drillfatigue.surrogate.model.EnsembleModule`
with the feature scaler, the one-hot encoder and the conformal quantile baked
in: ``module(x_num, x_cat) -> (n, 4)`` = log10 damage rate per hour, sigma,
lower and upper interval bound, from raw SI features (float32, columns in the
order of ``metadata.json["preprocessor"]["numeric"]``) and category codes
(int64, levels in ``metadata.json["preprocessor"]["categories"]``). The
out-of-domain test is not part of the export (it needs the reference set);
servers use ``ood_reference.npy`` and ``metadata.json["domain"]``.

The same module is exported to ONNX (``model.onnx``, opset 17, inputs
``x_num`` float32 (n, n_numeric) and ``x_cat`` int64 (n, n_categorical), output
``y`` float32 (n, 4), dynamic batch) through torch's TorchScript-based exporter
(``dynamo=False``: needs only ``onnx``, not ``onnxscript``). It runs in
``onnxruntime`` (C, C++, C#, Java, JavaScript servers) and agrees with the
Python model to float32 round-off (tests/unit/surrogate/test_export.py).
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


ONNX_OPSET = 17


def export_onnx(surrogate: Surrogate, path: str | Path) -> Path:
    """Export the surrogate's module to ONNX at ``path`` (dynamic batch size)."""
    module = surrogate.module.eval()
    x_num = torch.zeros(2, len(surrogate.features), dtype=torch.float32)
    x_cat = torch.zeros(2, len(surrogate.categorical), dtype=torch.int64)
    p = Path(path)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the TorchScript-based exporter is marked deprecated
        torch.onnx.export(module, (x_num, x_cat), str(p), dynamo=False,
                          input_names=["x_num", "x_cat"], output_names=["y"],
                          dynamic_axes={"x_num": {0: "n"}, "x_cat": {0: "n"}, "y": {0: "n"}},
                          opset_version=ONNX_OPSET)
    return p
