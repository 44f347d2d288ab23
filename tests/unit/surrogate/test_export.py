"""TorchScript and ONNX exports (scaler, one-hot and conformal quantile baked in) equal the Python model."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest
import torch

from drillfatigue.config.surrogate import SurrogateConfig
from drillfatigue.surrogate import Surrogate, fit_surrogate, make_synthetic_dataset
from drillfatigue.surrogate.export import export_torchscript, load_torchscript

TINY = SurrogateConfig(hidden_layers=(16, 16), max_epochs=8, patience=8, batch_size=128,
                       n_threads=1)


@pytest.fixture(scope="module", params=["silu", "hardswish"])
def model_and_data(request) -> tuple[Surrogate, pd.DataFrame]:
    data = make_synthetic_dataset(30, seed=2)
    return fit_surrogate(data, TINY.model_copy(update={"activation": request.param})), data


def test_torchscript_equals_python_model(model_and_data, tmp_path) -> None:
    model, data = model_and_data
    path = export_torchscript(model, tmp_path / "model.ts")
    ts = load_torchscript(path)
    x_num, x_cat = model.encode(data)
    with torch.inference_mode():
        out = ts(torch.as_tensor(x_num, dtype=torch.float32),
                 torch.as_tensor(x_cat, dtype=torch.long)).numpy()
    p = model.predict(data, refuse=False)  # the export answers every row
    cols = ["log10_damage_rate_per_h", "sigma_log10", "log10_damage_rate_per_h_lower",
            "log10_damage_rate_per_h_upper"]
    # same float32 graph on the same CPU: 1e-6 relative is the float32 round-off bound
    np.testing.assert_allclose(out, p[cols].to_numpy(), rtol=1e-6, atol=0)


def test_saved_folder_contains_working_export(model_and_data, tmp_path) -> None:
    model, data = model_and_data
    model.save(tmp_path / "m")
    ts = load_torchscript(tmp_path / "m" / "model.ts")
    loaded = Surrogate.load(tmp_path / "m")
    x_num, x_cat = loaded.encode(data.iloc[:50])
    with torch.inference_mode():
        out = ts(torch.as_tensor(x_num, dtype=torch.float32), torch.as_tensor(x_cat)).numpy()
    np.testing.assert_allclose(out[:, 0], loaded.predict_array(x_num, x_cat)["log10"], rtol=1e-6)


def test_onnx_export_equals_python_model_in_onnxruntime(model_and_data, tmp_path) -> None:
    ort = pytest.importorskip("onnxruntime")
    from drillfatigue.surrogate.export import export_onnx

    model, data = model_and_data
    path = export_onnx(model, tmp_path / "model.onnx")
    sess = ort.InferenceSession(str(path), providers=["CPUExecutionProvider"])
    x_num, x_cat = model.encode(data)
    # a batch size other than the one traced (dynamic batch axis)
    out = sess.run(None, {"x_num": np.asarray(x_num, dtype=np.float32),
                          "x_cat": np.asarray(x_cat, dtype=np.int64)})[0]
    ref = model.predict_array(x_num, x_cat, ood=False)
    want = np.column_stack([ref["log10"], ref["sigma"], ref["lower"], ref["upper"]])
    # float32 graphs executed by different kernels (onnxruntime vs torch): the sums
    # may be reordered, so allow a few float32 ulps of the output scale (measured 3e-7)
    scale = np.abs(want).max()
    np.testing.assert_allclose(out, want, rtol=0, atol=1e-5 * scale)
    assert (tmp_path / "m2").exists() is False
    model.save(tmp_path / "m2")
    assert (tmp_path / "m2" / "model.onnx").stat().st_size > 1000
