"""Unit tests of the friction config and parameter packing."""

from __future__ import annotations

import numpy as np
import pytest

from drillfatigue.config import case_from_dict
from drillfatigue.config.base import validate
from drillfatigue.config.friction import FrictionConfig
from drillfatigue.dynamics.contact.friction import (
    I_AX_RATIO,
    I_MU_D,
    I_MU_S,
    MODEL_IDS,
    STICK_BAND,
    TANH_EXP,
    pack_friction_params,
    slip_coefficient,
)
from drillfatigue.errors import InputError


def test_defaults_and_pack():
    mid, p = pack_friction_params(FrictionConfig())
    assert mid == TANH_EXP
    assert p[I_MU_S] == 0.35 and p[I_MU_D] == 0.25 and p[I_AX_RATIO] == 1.0
    assert p.dtype == np.float64


def test_mu_axial_ratio():
    _, p = pack_friction_params(FrictionConfig(mu_axial=0.5, mu_dynamic=0.25))
    assert p[I_AX_RATIO] == pytest.approx(2.0)


@pytest.mark.parametrize(
    "data, field",
    [
        ({"mu_static": 0.2, "mu_dynamic": 0.3}, "friction"),
        ({"mu_static": 1.6}, "friction.mu_static"),
        ({"model": "stribeck"}, "friction.model"),
        ({"v_t_m_per_s": 0.1, "v_s_m_per_s": 0.05}, "friction"),
        ({"mu_dynamic": 0.0, "mu_static": 0.0, "mu_axial": 0.2}, "friction"),
        ({"unknown": 1}, "friction.unknown"),
        ({"model": "stick_band", "stick_band_m_per_s": 1e-3, "v_reg_m_per_s": 1e-3}, "friction"),
    ],
)
def test_bad_input_names_field_and_allowed(data, field):
    with pytest.raises(InputError) as exc:
        validate(FrictionConfig, data, "friction")
    assert exc.value.field == field
    assert "allowed" in exc.value.one_line()


def test_case_section_partial():
    case = case_from_dict({"friction": {"model": "karnopp"}})
    assert case.friction.model == "karnopp" and case.friction.mu_static == 0.35


def test_velocity_trig_shape_points():
    cfg = FrictionConfig(model="velocity_trig")
    mid, p = pack_friction_params(cfg)
    vp, vw = cfg.trig_v_peak_m_per_s, cfg.trig_v_decay_m_per_s
    assert slip_coefficient(mid, p, 0.0) == 0.0
    assert slip_coefficient(mid, p, vp) == pytest.approx(cfg.mu_static)
    assert slip_coefficient(mid, p, vp + vw / 2) == pytest.approx(0.5 * (cfg.mu_static + cfg.mu_dynamic))
    assert slip_coefficient(mid, p, vp + vw) == pytest.approx(cfg.mu_dynamic)
    assert set(MODEL_IDS.values()) == set(range(7))


def test_stick_band_shape_points():
    """mu_s (after the Coulomb ramp) up to the band, mu_d from its edge on."""
    cfg = FrictionConfig(model="stick_band", stick_band_m_per_s=0.095)
    mid, p = pack_friction_params(cfg)
    assert mid == STICK_BAND
    assert slip_coefficient(mid, p, 0.0) == 0.0
    assert slip_coefficient(mid, p, 0.5 * cfg.v_reg_m_per_s) == pytest.approx(0.5 * cfg.mu_static)
    assert slip_coefficient(mid, p, cfg.v_reg_m_per_s) == cfg.mu_static
    assert slip_coefficient(mid, p, 0.094) == cfg.mu_static
    assert slip_coefficient(mid, p, 0.095) == cfg.mu_dynamic
    assert slip_coefficient(mid, p, 5.0) == cfg.mu_dynamic
