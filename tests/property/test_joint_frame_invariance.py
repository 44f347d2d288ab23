"""Joint loads are frame-invariant and the joint dampers never add energy.

Rotating the two neighbours of a joint (positions, velocities, orientations,
angular velocities) by the same rigid rotation leaves the joint-frame loads
unchanged, because the joint frame is the mid frame of the two segments
(docs/model.md#joints); swapping which segment is the reference is not needed.
"""

from __future__ import annotations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from drillfatigue.dynamics.core.joints import joint_force
from drillfatigue.dynamics.core.rigid import quat_from_rot, quat_mul, quat_to_rot

K = (4e8, 8e7, 2e6, 1.5e6, 1e4, 5e3, 50.0, 30.0)  # k_a, k_s, k_b, k_t, c_a, c_s, c_b, c_t


def _quat(v: np.ndarray) -> np.ndarray:
    a = np.linalg.norm(v)
    if a < 1e-15:
        return np.array([1.0, 0.0, 0.0, 0.0])
    return np.r_[np.cos(a / 2), np.sin(a / 2) * v / a]


def _rot(q: np.ndarray) -> np.ndarray:
    r = np.zeros((3, 3))
    quat_to_rot(q, r)
    return r


def _loads(x_lo, v_lo, q_lo, w_lo, x_up, v_up, q_up, w_up, h=4.5):
    out = {k: np.zeros(3) for k in ("F", "Ml", "Mu")}
    loads, ed = np.zeros(6), np.zeros(2)
    joint_force((x_lo, v_lo, _rot(q_lo), q_lo, w_lo, h), (x_up, v_up, _rot(q_up), q_up, w_up, h),
                np.array(K), (out["F"], out["Ml"], out["Mu"], loads, ed))
    return loads, ed, out


vec = st.lists(st.floats(-1.0, 1.0), min_size=3, max_size=3).map(np.array)
small = st.lists(st.floats(-0.05, 0.05), min_size=3, max_size=3).map(np.array)


@settings(max_examples=40, deadline=None)
@given(base=vec, rel=small, gap=small, v1=vec, v2=vec, w1=vec, w2=vec, rot=vec)
def test_loads_invariant_under_rigid_rotation(base, rel, gap, v1, v2, w1, w2, rot) -> None:
    h = 4.5
    q_lo = _quat(3.0 * base)
    q_up = np.zeros(4)
    quat_mul(q_lo, _quat(rel), q_up)
    r_lo, r_up = _rot(q_lo), _rot(q_up)
    x_lo = np.array([1.0, 2.0, 3.0])
    # upper centre so that its lower end sits near the lower segment's upper end
    x_up = x_lo - h * r_lo[:, 2] - h * r_up[:, 2] + 1e-3 * gap
    ref, ed_ref, _ = _loads(x_lo, v1, q_lo, w1, x_up, v2, q_up, w2)
    Q = _rot(_quat(3.0 * rot))
    qQ = quat_from_rot(Q)
    ql2, qu2 = np.zeros(4), np.zeros(4)
    quat_mul(qQ, q_lo, ql2)
    quat_mul(qQ, q_up, qu2)
    got, ed_got, _ = _loads(Q @ x_lo, Q @ v1, ql2, Q @ w1, Q @ x_up, Q @ v2, qu2, Q @ w2)
    scale = np.abs(ref).max() + 1.0
    np.testing.assert_allclose(got, ref, atol=1e-9 * scale)
    np.testing.assert_allclose(ed_got, ed_ref, rtol=1e-9, atol=1e-9)


@settings(max_examples=40, deadline=None)
@given(base=vec, rel=small, gap=small, v1=vec, v2=vec, w1=vec, w2=vec)
def test_forces_balance_and_dampers_dissipate(base, rel, gap, v1, v2, w1, w2) -> None:
    h = 4.5
    q_lo = _quat(3.0 * base)
    q_up = np.zeros(4)
    quat_mul(q_lo, _quat(rel), q_up)
    r_lo, r_up = _rot(q_lo), _rot(q_up)
    x_lo = np.zeros(3)
    x_up = x_lo - h * r_lo[:, 2] - h * r_up[:, 2] + 1e-3 * gap
    _, ed, out = _loads(x_lo, v1, q_lo, w1, x_up, v2, q_up, w2)
    # damper power is a sum of c * (relative velocity)^2 >= 0: never adds energy
    assert ed[1] >= 0.0
    # action = reaction: total moment about the origin vanishes (angular momentum)
    total = np.cross(x_lo, out["F"]) + out["Ml"] + np.cross(x_up, -out["F"]) + out["Mu"]
    scale = np.abs(out["Ml"]).max() + np.abs(out["F"]).max() * 10 + 1.0
    np.testing.assert_allclose(total, 0.0, atol=1e-9 * scale)
