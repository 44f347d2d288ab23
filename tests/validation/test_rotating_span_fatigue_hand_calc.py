"""Fatigue of drill pipe rotating on the low side of a straight horizontal hole,
through span bending and the whole fatigue chain, against a hand calculation.

Hand calculation (docs/fatigue.md sections 1 and 3): the support moment wL^2/12 of
the continuous beam on tool joints 9.144 m apart turns once per revolution in
the pipe, so a surface point sees sigma_a = K_b (wL^2/12) r/I about the mean
K_a F_true/A; 50 rpm for 60 s is 50 cycles. Uniaxial route with Goodman:
S = 2 sigma_a / (1 - sigma_m/sigma_u); Matake on the 45 deg plane:
sigma_eq = (f/t)[sigma_a/2 + a (sigma_m + sigma_a)/2]; D = 50 / N(S) with the
DNV-RP-C203 B1 curve in air. The issue asks for 10 %; the chain does the same
arithmetic on a sampled sine, so it agrees to 1e-6 (72 samples per revolution
hit both extremes exactly).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from drillfatigue.config.string import StringConfig
from drillfatigue.fatigue.critical_plane import CriterionParams, DamageOptions, evaluate_location
from drillfatigue.fatigue.sn import get_curve
from drillfatigue.fatigue.stress import SCF, Pressure, Section, true_wall_force_N
from drillfatigue.string import build_segments
from drillfatigue.dynamics.span.beam import continuous_beam_moments, pipe_frame_moments


@pytest.mark.parametrize("scf", [SCF(), SCF(2.0, 2.0, 1.5)], ids=["body", "upset"])
@pytest.mark.parametrize("p", [0.0, 20e6])
@pytest.mark.parametrize("crit", ["uniaxial", "matake"])
def test_rotating_drill_pipe_life_against_hand_calculation(scf: SCF, p: float,
                                                           crit: str) -> None:
    seg = build_segments(StringConfig(), 1200.0)
    k = seg.component_type.index("drill_pipe")
    w = float(seg.buoyed_weight_N[k] / seg.length_m[k])
    ei = float(seg.ei_Nm2[k])
    L, n = 9.144, 30
    beam = continuous_beam_moments([L] * n, ei, np.tile([0.0, -w], (n, 1)))
    M = beam.support_Nm[15]
    rpm, dur = 50.0, 60.0
    t = np.arange(0.0, dur + 1e-9, 60.0 / rpm / 72)
    ang = 2.0 * math.pi * rpm / 60.0 * t
    loads = np.zeros((t.size, 6))
    loads[:, 0] = 1.0e5  # effective tension
    loads[:, 3:5] = pipe_frame_moments(np.tile(M, (t.size, 1)), ang)
    sec = Section(0.127, 0.1086)
    curve = get_curve("B1", "air")
    su = 1.0e9
    prm = CriterionParams()
    r = evaluate_location(loads, sec, scf, curve, crit, prm,
                          options=DamageOptions(mean_stress="goodman", ultimate_Pa=su),
                          pressure=Pressure(p, p))
    sig_a = scf.bending * (w * L * L / 12.0) * sec.r_m / sec.inertia_m4
    F_true = float(true_wall_force_N(1.0e5, sec, Pressure(p, p)))
    sig_m = scf.axial * F_true / sec.area_m2
    if crit == "uniaxial":
        S = 2.0 * sig_a / (1.0 - sig_m / su)
    else:
        ft = 1.0 / prm.torsion_to_tension_ratio
        a = 2.0 * prm.torsion_to_tension_ratio - 1.0
        # the hoop and radial -p of the hydrostatic pressure also sit on the plane
        sn = 0.5 * (sig_m + sig_a) + 0.5 * (-p if p else 0.0)
        S = 2.0 * ft * (0.5 * sig_a + a * max(sn, 0.0))
    D_hand = 50.0 / float(curve.cycles_to_failure(np.array([S]))[0])
    assert r.damage == pytest.approx(D_hand, rel=1e-6)
    life_h = dur / 3600.0 / r.damage
    assert life_h == pytest.approx(dur / 3600.0 / D_hand, rel=0.10)
