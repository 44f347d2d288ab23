"""Unit tests of the bit-rock law (docs/model.md#bit)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from drillfatigue.config.base import validate
from drillfatigue.config.bit import BitConfig
from drillfatigue.dynamics.core import status
from drillfatigue.dynamics.bit.laws import I_B0, bit_response, pack_bit_params
from drillfatigue.errors import InputError


YC = BitConfig(model="yigit_christoforou")


def resp(wob, omega, cfg=None, rop=0.0):
    mid, p = pack_bit_params(cfg or YC, rop)
    out = np.empty(2)
    assert bit_response(mid, p, wob, omega, out) == status.OK
    return out


def test_public_parameter_set():
    _, p = pack_bit_params(BitConfig())
    assert p[I_B0] == pytest.approx(0.0239, rel=1e-12)


def test_tob_shape_zero_peak_weakening():
    wob = 1e5
    om = np.linspace(0.0, 20.0, 4001)
    tob = np.array([resp(wob, w)[0] for w in om])
    assert tob[0] == 0.0
    k = int(np.argmax(tob))
    # peak near 1/sqrt(b3) = 0.43 rad/s (the tanh term shifts it a little)
    assert 0.3 < om[k] < 0.7
    assert tob[k] / (wob * 0.0239) == pytest.approx(2.5, abs=0.15)
    # velocity weakening beyond the peak: TOB decreases monotonically toward wob r_b mu0
    assert np.all(np.diff(tob[k:]) < 0)
    assert tob[-1] == pytest.approx(wob * 0.0239 * (1 + 8.5 * 20 / (1 + 5.47 * 400)), rel=1e-9)


def test_tob_odd_and_no_cutting_backward():
    a, b = resp(8e4, 3.0), resp(8e4, -3.0)
    assert b[1] == 0.0
    # backward: friction term only
    assert b[0] == pytest.approx(-8e4 * 0.0239 * math.tanh(1.91 * 3.0))
    assert a[1] > 0.0


def test_rop_law_and_thresholds():
    cfg = BitConfig(model="yigit_christoforou", threshold_band=0.0)
    wob, om = 1e5, 150 * 2 * math.pi / 60
    assert resp(wob, om, cfg)[1] == pytest.approx(1.4e-8 * wob * math.sqrt(om))
    # below the WOB threshold: no penetration, TOB is friction only
    below = resp(4.9e3, om, cfg)
    assert below[1] == 0.0
    assert below[0] == pytest.approx(4.9e3 * 0.0239 * math.tanh(1.91 * om))
    # below the speed threshold
    assert resp(wob, 0.049, cfg)[1] == 0.0
    assert resp(wob, 0.051, cfg)[1] > 0.0


def test_bit_bounce_gives_nothing():
    np.testing.assert_array_equal(resp(0.0, 10.0), 0.0)
    np.testing.assert_array_equal(resp(-5.0, 10.0), 0.0)


def test_continuous_through_thresholds_with_band():
    om = np.linspace(0.0, 1.0, 20001)
    out = np.array([resp(1e5, w) for w in om])
    assert np.abs(np.diff(out[:, 0])).max() < 0.005 * 1e5 * 0.0239 * 2.5
    wob = np.linspace(0.0, 2e4, 20001)
    out = np.array([resp(w, 10.0) for w in wob])
    assert np.abs(np.diff(out[:, 1])).max() < 1e-3 * out[-1, 1]


def test_prescribed_rop():
    cfg = BitConfig(model="prescribed_rop")
    out = resp(5e4, 10.0, cfg, rop=0.5)
    assert out[1] == 0.5
    assert out[0] == pytest.approx(resp(5e4, 10.0)[0])
    assert resp(0.0, 10.0, cfg, rop=0.5)[1] == 0.0


def test_unknown_model_and_bad_config():
    _, p = pack_bit_params(BitConfig())
    out = np.ones(2)
    assert bit_response(9, p, 1.0, 1.0, out) == status.UNKNOWN_BIT
    with pytest.raises(InputError) as exc:
        validate(BitConfig, {"bit_radius_m": 2.0}, "bit")
    assert exc.value.field == "bit.bit_radius_m"
