"""Properties of the recorded span correction (dynamics.span.record.span_sample).

* Frame: spinning every segment by the same angle psi about its own axis
  changes neither the supports nor the load, so the moment vector is the same
  in the world and its joint-frame components turn by -psi (the frame turned
  by +psi). Checked to 1e-9 relative (round-off of the quaternion products).
* Linearity: the load is the segments' weight (at rest, no forces other than
  the weight's reactions are distributed), so scaling the weight scales the
  moments (1e-9 relative) while no span reaches the wall: up to the weight
  itself here (at 5x the weight the end span's sag, ~90 mm, passes the 44 mm
  clearance and the recorder adds a support there, which is not linear).
"""

from __future__ import annotations

import math

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from drillfatigue.config import case_from_dict
from drillfatigue.dynamics.core import layout as L
from drillfatigue.dynamics.run.model import build_model, evaluate_forces, straight_path
from drillfatigue.dynamics.core.rigid import quat_mul
from drillfatigue.dynamics.span.beam import continuous_beam_moments
from drillfatigue.dynamics.span.record import span_sample

JOINT_M = 9.144


def _model():
    length = 6 * JOINT_M + 5.0
    cfg = case_from_dict({
        "string": {"components": [{"type": "drill_pipe", "od_m": 0.127, "id_m": 0.1086,
                                   "length_m": length, "tool_joint_od_m": 0.1683,
                                   "tool_joint_id_m": 0.0826, "joints_per_segment": 1}]},
        "operation": {"bit_md_m": length + 1.0, "top_md_m": 1.0, "bit_on_bottom": False,
                      "top_axial": "fixed", "rpm": 0.0, "mud_density_kg_per_m3": 0.0},
        "solver": {"relax_s": 0.0},
        "contact": {"points": "string", "span_bending": True},
    })
    model, state = build_model(cfg, straight_path(100.0, 90.0, hole_diameter_m=0.2159))
    # rest every segment on the low side, tool joints 0.1 mm into the wall
    drop = 0.5 * 0.2159 - 0.5 * 0.1683 + 1e-4
    state.x[: model.n0, 2] += drop
    return model, state


MODEL, STATE = _model()
SEL = np.arange(MODEL.n0 - 1, dtype=np.int64)


def _sample(state) -> np.ndarray:
    evaluate_forces(MODEL, state)
    # the distributed load at rest is the weight: zero the net forces of the kinematic
    # placement (a static state, the wall's reactions at the supports)
    state.Fw[:] = 0.0
    state.v[:] = 0.0
    out = np.zeros((SEL.size, 2))
    st = span_sample(MODEL.n0, state, MODEL.params, MODEL.work, SEL, out)
    assert st == 0
    return out


BASE = _sample(STATE.copy())


def test_the_resting_pipe_has_span_moments() -> None:
    w = MODEL.seg[0, L.S_W] / (2.0 * MODEL.seg[0, L.S_H])
    mag = np.hypot(BASE[:, 0], BASE[:, 1])
    # 6 spans pinned at both ends: interior supports 0.077-0.086 w L^2 (three-moment)
    assert np.all(mag[:-1] > 0.07 * w * JOINT_M ** 2)


@settings(max_examples=20, deadline=None)
@given(st.floats(-math.pi, math.pi))
def test_spinning_every_segment_turns_the_components(psi: float) -> None:
    s = STATE.copy()
    qz = np.array([math.cos(0.5 * psi), 0.0, 0.0, math.sin(0.5 * psi)])
    out = np.zeros(4)
    for i in range(MODEL.n0):
        quat_mul(s.q[i].copy(), qz, out)
        s.q[i] = out
    got = _sample(s)
    c, sn = math.cos(psi), math.sin(psi)
    want = np.stack([c * BASE[:, 0] + sn * BASE[:, 1], -sn * BASE[:, 0] + c * BASE[:, 1]],
                    axis=1)
    scale = np.abs(BASE).max()
    assert np.allclose(got, want, rtol=0, atol=1e-9 * scale)


@settings(max_examples=10, deadline=None)
@given(st.floats(0.2, 1.0))
def test_moments_scale_with_the_weight(k: float) -> None:
    saved = MODEL.seg[:, L.S_W].copy()
    try:
        MODEL.seg[:, L.S_W] *= k
        got = _sample(STATE.copy())
    finally:
        MODEL.seg[:, L.S_W] = saved
    assert np.allclose(got, k * BASE, rtol=0, atol=1e-9 * k * np.abs(BASE).max())


def test_a_buckled_segment_gets_a_support_at_its_middle() -> None:
    """Joints 2 and 3 at 1.5 times segment 3's Euler load in compression (segment 3
    at 1.5 P_E, its neighbours at 0.75 P_E): a straight segment 3 cannot exist, the
    pipe bows onto the wall, so the recorder adds a support at its middle (and cuts
    nothing). Every joint's correction equals the continuous beam on the tool joints
    plus that mid-span support (load the weight per length; axial forces as
    recorded; segment 3's halves at 1.5/4 of their Euler load). Tolerance 1e-6
    relative: the recorder's supports are the tool-joint points found in the wall,
    0.1 mm penetration away from the segment ends."""
    s = STATE.copy()
    evaluate_forces(MODEL, s)
    s.Fw[:] = 0.0
    s.v[:] = 0.0
    n = MODEL.n0
    length = 2.0 * MODEL.seg[:n, L.S_H]
    ei = MODEL.params.ei[:n].copy()
    w = MODEL.seg[:n, L.S_W] / length
    p_e = math.pi ** 2 * ei[3] / length[3] ** 2
    loads = MODEL.work.loads
    saved = loads.copy()
    try:
        loads[:, 0] = 0.0
        loads[2, 0] = loads[3, 0] = -1.5 * p_e
        out = np.zeros((SEL.size, 2))
        assert span_sample(n, s, MODEL.params, MODEL.work, SEL, out) == 0  # nothing cut
    finally:
        loads[:] = saved
    T = np.zeros(n)
    T[2] = T[4] = -0.75 * p_e
    T[3] = -1.5 * p_e
    split = [0, 1, 2, 3, 3, 4, 5, 6]  # segment of each span, segment 3 in two halves
    spans = np.array([length[k] * (0.5 if k == 3 else 1.0) for k in split])
    q = np.stack([np.zeros(len(split)), -w[split]], axis=1)
    full = continuous_beam_moments(spans, ei[split], q, T[split])
    want = full.support_Nm[[1, 2, 3, 5, 6, 7], 0]  # the joints (support 4: mid-segment 3)
    mag = np.hypot(out[:, 0], out[:, 1])
    np.testing.assert_allclose(mag, np.abs(want), rtol=1e-6, atol=1e-9 * np.abs(want).max())
    assert np.all(mag > 0.03 * w[0] * JOINT_M ** 2)  # nothing zeroed
