"""``bit`` section of params.yaml: the bit-rock interaction law (docs/model.md#bit).

Kernel: :mod:`drillfatigue.dynamics.bit.laws`. Defaults: the public parameter set
of the Yigit & Christoforou torque-on-bit shape, b0 = r_b mu0 = 0.0239 m,
b1 = 1.91 s/rad, b2 = 8.5 s/rad, b3 = 5.47 s^2/rad^2, for an 8 1/2 in bit. The
lobed axial bit motion (lobe count, amplitude) and the prescribed ROP value
live in the ``operation`` section (``lobe_count``, ``lobe_amplitude_m``,
``rop_m_per_s``), not here.
"""

from __future__ import annotations

from typing import Literal

from pydantic import Field

from drillfatigue.config.base import StrictModel
from drillfatigue.limits import FEATURE_BOUNDS
from drillfatigue.units import INCH_M

#: Bit radius of an 8 1/2 in bit, m.
DEFAULT_BIT_RADIUS_M = 0.5 * 8.5 * INCH_M
#: Public value of r_b mu0 for the TOB law, m (docs/model.md#bit).
DEFAULT_RB_MU0_M = 0.0239


class BitConfig(StrictModel):
    """Settings of the ``bit`` section. Units: SI unless the field name says otherwise.

    Attributes
    ----------
    model : str
        ``yigit_christoforou``: TOB and ROP from the bit-rock law;
        ``prescribed_rop``: TOB from the same law, ROP given by
        ``operation.rop_m_per_s``; ``given_tob``: TOB = operation.tob_Nm
        tanh(Omega / 0.5 rad/s) and the prescribed ROP (the simple mode of the
        simulator core). In all modes WOB is the axial rock contact force at the
        bit and the bit bounces (WOB = 0) when it lifts off. ``detournay``: TOB
        and ROP from the depth-of-cut law of a PDC bit (Detournay & Defourny
        1992; docs/rig.md#the-rock-face-under-the-bit), fields ``detournay_*``.
    bit_radius_m : float
        Bit radius r_b, m (0.02..0.5). Default 8.5 in / 2.
    mu0 : float
        Bit-rock friction scale mu0 (0..5); default 0.0239 m / r_b, so that
        r_b mu0 = 0.0239 m.
    tob_b1_s_per_rad, tob_b2_s_per_rad, tob_b3_s2_per_rad2 : float
        Shape constants of mu_b(Omega) = mu0 [tanh(b1 Omega) + b2 Omega / (1 + b3 Omega^2)].
    rop_c1_m_per_N_sqrt_s : float
        c1 of ROP = c1 WOB sqrt(Omega) + c2, m/(N sqrt(s)) (Omega in rad/s).
        Default 1.4e-8: 20 m/h at 100 kN and 150 rpm. At most 1e-6 (1400 m/h at
        100 kN and 150 rpm: no rock drills that fast), the bound of
        :data:`drillfatigue.limits.FEATURE_BOUNDS`.
    rop_c2_m_per_s : float
        c2, m/s (may be negative: a drilling threshold).
    wob_threshold_N, omega_threshold_rad_s : float
        Sarker et al. thresholds: no penetration and no cutting torque below
        either (TOB is then the bit's friction term only).
    threshold_band : float
        Relative width over which cutting fades in above each threshold
        (smoothstep), 0..1; 0 is the sharp switch of Sarker et al.
    detournay_eps_Pa : float
        Intrinsic specific energy eps of the rock, Pa. Default 200 MPa.
    detournay_zeta : float
        Ratio of the normal to the tangential cutting force zeta. Default 0.6.
    detournay_sigma_Pa : float
        Contact strength sigma under the wear flats, Pa. Default 60 MPa.
    detournay_wear_flat_m : float
        Total wear-flat length l, m. Default 2 mm.
    detournay_mu_gamma : float
        Bit friction coefficient times bit geometry number. Default 0.6.
        The defaults lie in the ranges Detournay, Richard & Shepherd (Int. J.
        Rock Mech. Min. Sci. 45 (2008) 1347) identified (eps 100-300 MPa, zeta
        0.5-0.8, mu gamma 0.4-1) and give 6.7 mm/rev, 60 m/h at 100 kN and
        150 rpm for an 8 1/2 in bit.
    detournay_omega_reg_rad_s : float
        Speed over which the torque rises through zero speed (tanh), rad/s;
        default 0.5, the saturation speed of the Yigit-Christoforou friction
        term (1 / b1).
    """

    model: Literal["yigit_christoforou", "prescribed_rop", "given_tob", "detournay"] = "prescribed_rop"
    bit_radius_m: float = Field(DEFAULT_BIT_RADIUS_M, ge=0.02, le=0.5)
    mu0: float = Field(DEFAULT_RB_MU0_M / DEFAULT_BIT_RADIUS_M, ge=0.0, le=5.0)
    tob_b1_s_per_rad: float = Field(1.91, gt=0.0, le=1e3)
    tob_b2_s_per_rad: float = Field(8.5, ge=0.0, le=1e3)
    tob_b3_s2_per_rad2: float = Field(5.47, ge=0.0, le=1e4)
    rop_c1_m_per_N_sqrt_s: float = Field(
        1.4e-8, ge=0.0, le=FEATURE_BOUNDS["rop_c1_m_per_N_sqrt_s"].hi,
        description="drillability; physical bound: drillfatigue.limits (docs/trust.md)")
    rop_c2_m_per_s: float = Field(0.0, ge=-1.0, le=1.0)
    wob_threshold_N: float = Field(5e3, ge=0.0, le=1e7)
    omega_threshold_rad_s: float = Field(0.05, ge=0.0, le=100.0)
    threshold_band: float = Field(0.1, ge=0.0, le=1.0)
    detournay_eps_Pa: float = Field(200e6, gt=0.0, le=5e9)
    detournay_zeta: float = Field(0.6, gt=0.0, le=5.0)
    detournay_sigma_Pa: float = Field(60e6, ge=0.0, le=5e9)
    detournay_wear_flat_m: float = Field(2e-3, ge=0.0, le=0.5)
    detournay_mu_gamma: float = Field(0.6, ge=0.0, le=5.0)
    detournay_omega_reg_rad_s: float = Field(0.5, gt=0.0, le=10.0)
