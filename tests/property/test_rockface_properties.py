"""Invariants of the rock-face kernels: the face never pulls, more weight never cuts less."""

from __future__ import annotations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from drillfatigue.config.bit import BitConfig
from drillfatigue.dynamics.bit import laws as BR
from drillfatigue.dynamics.bit import rockface as RF

finite = dict(allow_nan=False, allow_infinity=False)


@settings(max_examples=200, deadline=None)
@given(st.floats(-1e-2, 1e-2, **finite), st.floats(-10.0, 10.0, **finite), st.floats(-100.0, 100.0, **finite),
       st.floats(-50.0, 50.0, **finite), st.floats(0.0, 5e-3, **finite), st.integers(0, 6),
       st.floats(1e4, 1e10, **finite), st.floats(0.0, 1e7, **finite))
def test_rock_contact_never_pulls(u, ud, phi, om, a, n, k, c) -> None:
    out = np.empty(2)
    on = RF.rock_face_contact(u, ud, phi, om, a, n, k, c, out)
    assert out[0] >= 0.0
    assert out[1] == u - RF.rock_face_height(phi, a, n)
    if not on:
        assert out[0] == 0.0 and out[1] <= 0.0


def _detournay(wob_N: float, omega_rad_s: float, out: np.ndarray) -> None:
    """The unregularised law with BitConfig's detournay defaults (an 8 1/2 in PDC bit)."""
    b = BitConfig(model="detournay")
    BR.detournay_law(b.bit_radius_m, b.detournay_eps_Pa, b.detournay_zeta, b.detournay_sigma_Pa,
                     b.detournay_wear_flat_m, b.detournay_mu_gamma, wob_N, omega_rad_s, out)


@settings(max_examples=200, deadline=None)
@given(st.floats(0.0, 5e5, **finite), st.floats(0.0, 5e5, **finite), st.floats(0.01, 40.0, **finite))
def test_detournay_more_weight_cuts_and_turns_no_less(w1, w2, om) -> None:
    lo, hi = sorted((w1, w2))
    a = np.empty(3)
    b = np.empty(3)
    _detournay(lo, om, a)
    _detournay(hi, om, b)
    assert 0.0 <= a[1] <= b[1] and 0.0 <= a[2] <= b[2]
    assert a[0] <= b[0] * (1 + 1e-12)


@settings(max_examples=200, deadline=None)
@given(st.floats(0.0, 5e5, **finite), st.floats(-40.0, 40.0, **finite))
def test_detournay_bit_model_torque_resists_the_rotation_and_cuts_only_forward(w, om) -> None:
    mid, p = BR.pack_bit_params(BitConfig(model="detournay"))
    out = np.empty(2)
    assert BR.bit_response(mid, p, w, om, out) == 0
    assert out[0] * om >= 0.0  # the torque on bit opposes the rotation: it only dissipates
    assert out[1] >= 0.0
    if om <= 0.0 or w <= 0.0:
        assert out[1] == 0.0
    ref = np.empty(3)
    _detournay(w, abs(om), ref)
    assert abs(out[0]) <= ref[0] * (1.0 + 1e-12)  # the regularisation only lowers the torque
