"""Stiff string vs soft string (Johancsik et al., SPE 11380; docs/validation.md).

The 3D rigid-segment model with penalty wall contact, rotating off bottom,
must reproduce the classic soft-string surface torque and hook load once the
torsional start-up has settled: in a smooth low-dogleg J-well against
:func:`torque_drag_for_case` (the soft-string march), and in a straight
inclined hole against the closed forms of docs/validation.md (rotating: no axial
drag, hook load w cos I L; torque mu w sin I r_o L per length).
"""

from __future__ import annotations

import math

import numpy as np

import drillfatigue
from drillfatigue.dynamics.run.examples import j_well_rotating_case
from drillfatigue.softstring.torque_drag import torque_drag_for_case
from drillfatigue.string import build_segments

T_AVG_FROM_S = 1.0  # average after the rpm ramp (0.5 s); ~5 torsional periods of 300 m pipe


def _steady(cfg):
    res = drillfatigue.simulate(cfg, None, progress=False)
    ch = res.channels
    sel = ch["time_s"] > T_AVG_FROM_S
    # the simulated surface torque includes the mud torque c_rot omega L, which the
    # soft-string model leaves out
    op = cfg.operation
    mud = op.mud_damping_torsional_N_m_s_per_m * (op.bit_md_m - op.top_md_m) * op.rpm * math.pi / 30
    return float(ch["surface_torque_Nm"][sel].mean()) - mud, float(ch["hook_load_N"][sel].mean())


def test_j_well_rotating_off_bottom_matches_soft_string_within_10_percent() -> None:
    cfg = j_well_rotating_case()
    torque, hook = _steady(cfg)
    td = torque_drag_for_case(cfg)
    # 10 %: the bound. Measured: torque 1.8 %, hook load 0.02 %. The stiff
    # string rides up the wall to the friction angle, so its normal force is
    # W cos(atan mu) (3 % below W at mu 0.25), and the torsional oscillation
    # left after the ramp does not fully average out.
    assert abs(torque - td.torque_rotating_Nm[0]) < 0.10 * td.torque_rotating_Nm[0]
    assert abs(hook - td.tension_rotating_N[0]) < 0.10 * td.tension_rotating_N[0]


def test_straight_inclined_hole_matches_the_closed_forms() -> None:
    inc = math.radians(30.0)
    cfg = j_well_rotating_case(kop_m=1.0, dls_deg_per_30m=60.0, top_md_m=50.0, n_segments=25)
    torque, hook = _steady(cfg)
    segs = build_segments(cfg.string, cfg.operation.mud_density_kg_per_m3)
    w = float(segs.buoyed_weight_N[0] / segs.length_m[0])
    r_o = float(segs.contact_radius_m[0])
    length = 250.0
    mu = cfg.friction.mu_dynamic
    # docs/validation.md: rotating torque mu w sin I r_o per length; hook load w cos I L
    # (rotation takes the axial drag away). 10 % as above; measured: torque 7 %
    # low (friction angle, residual torsional oscillation), hook load 0.01 %.
    assert abs(torque - mu * w * math.sin(inc) * r_o * length) < 0.10 * mu * w * math.sin(inc) * r_o * length
    np.testing.assert_allclose(hook, w * math.cos(inc) * length, rtol=0.01)
