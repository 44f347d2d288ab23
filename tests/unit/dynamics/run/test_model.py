"""Model building: rpm profiles, growth of the top segment, recording options, input errors."""

from __future__ import annotations

import numpy as np
import pytest

from drillfatigue.config import case_from_dict
from drillfatigue.dynamics.core import layout as L
from drillfatigue.dynamics.run.simulation import simulate
from drillfatigue.dynamics.top.boundaries import drive_omega
from drillfatigue.dynamics.run.model import advance_model, build_model, straight_path
from drillfatigue.dynamics.top.pack import rpm_table
from drillfatigue.errors import InputError

STRING = {"components": [
    {"type": "collar", "od_m": 0.17145, "id_m": 0.0714, "length_m": 20.0, "n_segments": 2},
    {"type": "drill_pipe", "od_m": 0.127, "id_m": 0.1086, "length_m": 40.0, "n_segments": 4}]}


def test_rpm_ramp_and_table() -> None:
    cfg = case_from_dict({"operation": {"rpm": 60.0, "rpm_ramp_s": 2.0}})
    t, w = rpm_table(cfg)
    assert drive_omega(1.0, t, w) == pytest.approx(np.pi)  # 30 rpm
    assert drive_omega(5.0, t, w) == pytest.approx(2 * np.pi)
    cfg = case_from_dict({"operation": {"rpm_table": [[0.0, 0.0], [1.0, 60.0], [3.0, 120.0]]}})
    t, w = rpm_table(cfg)
    assert drive_omega(2.0, t, w) == pytest.approx(90.0 * 2 * np.pi / 60)
    with pytest.raises(InputError, match="rpm_table"):
        case_from_dict({"operation": {"rpm_table": [[1.0, 0.0], [0.5, 10.0]]}})


def test_top_segment_grows_with_the_drilled_length() -> None:
    cfg = case_from_dict({"string": STRING, "operation": {
        "bit_md_m": 70.0, "rop_m_per_s": 0.05, "rpm": 60.0, "rpm_ramp_s": 0.2, "tob_Nm": 500.0}})
    model, state = build_model(cfg, straight_path(200.0))
    h0 = model.seg[model.n0 - 1, L.S_H]
    assert 2 * h0 == pytest.approx(20.0)  # 70 m of hole minus the 50 m below the top segment
    m0 = model.seg[model.n0 - 1, L.S_M]
    n_steps = int(round(1.0 / model.dt))
    out = advance_model(model, state, n_steps, every=n_steps)
    assert 2 * model.seg[model.n0 - 1, L.S_H] == pytest.approx(20.0 + 0.05 * 1.0, rel=1e-9)
    assert model.seg[model.n0 - 1, L.S_M] == pytest.approx(m0 * (20.05 / 20.0), rel=1e-9)
    ch = out["channels"][-1]
    assert ch[1 + L.H_BITMD] == pytest.approx(70.05, rel=1e-12)
    # the string follows the bit down: the lowest segment moved ~5 cm
    assert abs(state.x[0, 2] - (70.0 - 5.0) - 0.05) < 5e-3


def test_recording_selected_joints_from_start_time() -> None:
    cfg = case_from_dict({"string": STRING, "operation": {"bit_md_m": 60.0, "duration_s": 0.5},
                          "recording": {"joints": [4, 1], "start_s": 0.25,
                                        "loads_rate_hz": 100.0}})
    res = simulate(cfg, None, progress=False, path=straight_path(100.0))
    assert list(res.joints) == [1, 4]
    assert res.loads.shape[1] == 2
    assert res.times_s[0] == pytest.approx(0.25)
    assert res.times_s.size == 26
    bad = case_from_dict({"string": STRING, "operation": {"bit_md_m": 60.0},
                          "recording": {"joints": [9]}})
    with pytest.raises(InputError, match="recording.joints"):
        simulate(bad, None, progress=False, path=straight_path(100.0))


def test_inconsistent_geometry_is_an_input_error() -> None:
    short = case_from_dict({"string": STRING, "operation": {"bit_md_m": 45.0}})
    with pytest.raises(InputError, match="operation.bit_md_m"):
        build_model(short, straight_path(100.0))
    high_np = case_from_dict({"string": STRING, "operation": {
        "bit_md_m": 60.0, "neutral_point_s_from_bit_m": 500.0}})
    with pytest.raises(InputError, match="neutral_point"):
        build_model(high_np, straight_path(100.0))
    heavy_hook = case_from_dict({"string": STRING, "operation": {
        "bit_md_m": 60.0, "top_axial": "hook_load", "hook_load_N": 1e7}})
    with pytest.raises(InputError, match="hook_load_N"):
        build_model(heavy_hook, straight_path(100.0))
