"""``friction`` section of params.yaml: wall friction model and its coefficients.

The model is chosen by name; all coefficients of all models live in this one
section so a case can switch model without editing anything else. Kernel:
:mod:`drillfatigue.dynamics.contact.friction` (docs/model.md#friction).
"""

from __future__ import annotations

from typing import Literal

from pydantic import Field, model_validator

from drillfatigue.config.base import StrictModel

FrictionModelName = Literal[
    "coulomb", "benson_hallquist", "karnopp", "tanh", "velocity_trig", "tanh_exp", "stick_band"
]


class FrictionConfig(StrictModel):
    """Settings of the ``friction`` section. Units: SI unless the field name says otherwise.

    Attributes
    ----------
    model : str
        ``coulomb`` (regularised), ``benson_hallquist``, ``karnopp``, ``tanh``
        (Mostaghel), ``velocity_trig`` (Wang & Rui style trigonometric shape),
        ``tanh_exp`` (the paper's hybrid tanh-exponential), ``stick_band``
        (Coulomb with a stick band of width ``stick_band_m_per_s``: mu_s inside,
        mu_d outside; Aarsnes & Shor 2018). Default ``tanh_exp``.
    mu_static, mu_dynamic : float
        Static and dynamic (kinetic) wall friction coefficients, 0..1.5,
        ``mu_dynamic <= mu_static``. Defaults 0.35 / 0.25 (water-base mud
        0.25-0.40, Johancsik et al. SPE 11380).
    mu_axial : float or None
        Coefficient of the axial (drag) direction; ``None`` means the same as
        ``mu_dynamic``. Applied by scaling the axial component of the friction
        force by ``mu_axial / mu_dynamic`` (see ``friction_force_split``).
    v_reg_m_per_s : float
        Regularisation velocity of Coulomb, Benson-Hallquist and stick_band
        (linear ramp below it), m/s.
    v_c_m_per_s : float
        Benson-Hallquist decay velocity, m/s.
    karnopp_dv_m_per_s : float
        Karnopp stick band half-width, m/s.
    stick_band_m_per_s : float
        ``stick_band``: the slip speed below which the wall holds the string, m/s
        (> ``v_reg_m_per_s``). Default 0.066: Aarsnes & Shor's fit to their Well B,
        omega_c = 0.9 rad/s, at the surface of its 5 7/8 in pipe (r = 73.3 mm;
        J. Petrol. Sci. Eng. 163 (2018) 712-721, Fig. 15); their script uses 1.5
        rad/s. docs/rig.md#off-bottom-stick-slip-and-the-stick-band.
    v_t_m_per_s : float
        tanh regularisation velocity (tanh and tanh_exp), m/s.
    v_s_m_per_s : float
        Stribeck decay velocity of tanh_exp, m/s (> v_t).
    trig_v_peak_m_per_s, trig_v_decay_m_per_s : float
        velocity_trig: slip speed at which the coefficient peaks at mu_static,
        and width of the cosine decay from mu_static to mu_dynamic, m/s.
    """

    model: FrictionModelName = "tanh_exp"
    mu_static: float = Field(0.35, ge=0.0, le=1.5)
    mu_dynamic: float = Field(0.25, ge=0.0, le=1.5)
    mu_axial: float | None = Field(None, ge=0.0, le=1.5)
    v_reg_m_per_s: float = Field(1e-3, gt=0.0, le=1.0)
    v_c_m_per_s: float = Field(0.05, gt=0.0, le=10.0)
    karnopp_dv_m_per_s: float = Field(1e-3, gt=0.0, le=1.0)
    stick_band_m_per_s: float = Field(0.066, gt=0.0, le=1.0)
    v_t_m_per_s: float = Field(1e-3, gt=0.0, le=1.0)
    v_s_m_per_s: float = Field(0.05, gt=0.0, le=10.0)
    trig_v_peak_m_per_s: float = Field(5e-3, gt=0.0, le=1.0)
    trig_v_decay_m_per_s: float = Field(0.1, gt=0.0, le=10.0)

    @model_validator(mode="after")
    def _check_order(self) -> FrictionConfig:
        if self.mu_dynamic > self.mu_static:
            raise ValueError(
                f"mu_dynamic ({self.mu_dynamic}) exceeds mu_static ({self.mu_static}) "
                "(allowed: 0 <= mu_dynamic <= mu_static <= 1.5)"
            )
        if self.mu_axial is not None and self.mu_axial > 0.0 and self.mu_dynamic == 0.0:
            raise ValueError(
                "mu_axial > 0 is a scaling of the dynamic friction and needs mu_dynamic > 0 "
                "(allowed: mu_dynamic > 0, or mu_axial 0 or unset)"
            )
        if self.model == "stick_band" and not self.v_reg_m_per_s < self.stick_band_m_per_s:
            raise ValueError(
                f"stick_band needs v_reg_m_per_s ({self.v_reg_m_per_s}) < stick_band_m_per_s "
                f"({self.stick_band_m_per_s}): the ramp must reach mu_static inside the band "
                "(allowed: v_reg_m_per_s < stick_band_m_per_s)"
            )
        if self.model == "tanh_exp" and not self.v_t_m_per_s < self.v_s_m_per_s:
            raise ValueError(
                f"tanh_exp needs v_t_m_per_s ({self.v_t_m_per_s}) < v_s_m_per_s "
                f"({self.v_s_m_per_s}) (allowed: v_t_m_per_s < v_s_m_per_s)"
            )
        return self
