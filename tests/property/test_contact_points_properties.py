"""Invariants of the contact-point lists (hypothesis): every gap within the
spacing bound, points sorted and inside their segment, tool-joint radius
exactly at the tool joints, and the segments unchanged in total length."""

from __future__ import annotations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from drillfatigue.config.string import ComponentConfig, StringConfig
from drillfatigue.string import build_segments
from drillfatigue.string.contacts import KIND_TOOL_JOINT, contact_points


@settings(max_examples=40, deadline=None)
@given(st.floats(20.0, 300.0), st.integers(1, 3), st.floats(20.0, 200.0), st.integers(1, 12),
       st.floats(0.0, 0.01), st.booleans())
def test_contact_point_invariants(dp_len: float, per_seg: int, dc_len: float, n_dc: int,
                                  kappa: float, jointed: bool) -> None:
    dp = dict(type="drill_pipe", od_m=0.127, id_m=0.1086, length_m=dp_len,
              tool_joint_od_m=0.1683, tool_joint_id_m=0.0826)
    dp.update({"joints_per_segment": per_seg} if jointed else {"n_segments": 7})
    cfg = StringConfig(components=[
        ComponentConfig(type="collar", od_m=0.17145, id_m=0.0714, length_m=dc_len,
                        n_segments=n_dc),
        ComponentConfig(**dp)])
    seg = build_segments(cfg, 1200.0)
    assert seg.total_length_m == np.float64(dc_len + dp_len) or abs(
        seg.total_length_m - dc_len - dp_len) < 1e-9 * (dc_len + dp_len)
    cp = contact_points(cfg, seg, 0.2159, kappa)
    top = np.cumsum(seg.length_m)
    for k in range(seg.n_segments):
        s, r, kind = cp.of_segment(k)
        assert s[0] == 0.0 and abs(s[-1] - seg.length_m[k]) < 1e-9
        assert np.all(np.diff(s) > 0.0)
        assert np.all(np.diff(s) <= cp.max_spacing_m[k] * (1 + 1e-12))
        z = top[k] - seg.length_m[k] + s[kind == KIND_TOOL_JOINT]
        # tool joints every 9.144 m from the pipe's bottom, or at its top end
        rel = (z - dc_len) / 9.144
        assert np.all((np.abs(rel - np.round(rel)) < 1e-6) | (np.abs(z - top[-1]) < 1e-6))
        assert np.all(r[kind == KIND_TOOL_JOINT] == 0.1683 / 2)
        if seg.component_index[k] == 1:  # drill pipe: body radius away from tool joints
            assert np.all(r[kind != KIND_TOOL_JOINT] == 0.127 / 2)
        else:
            assert np.all(r == 0.17145 / 2) and not np.any(kind == KIND_TOOL_JOINT)
