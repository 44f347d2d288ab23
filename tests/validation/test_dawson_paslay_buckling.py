"""Lateral (sinusoidal) buckling in a straight inclined hole: Dawson & Paslay (1984).

A pipe lying on the low side of an inclined hole and compressed axially stays
straight below F = 2 sqrt(E I w sin I / r_c) (Dawson & Paslay, SPE 11167;
docs/validation.md) and snakes sideways above it. 100 m of 5 in pipe (50 segments of
2 m, against a ~26 m buckle wavelength) in a 60 deg hole, no wall friction
(the closed form is frictionless), bit on bottom, top held: the top anchor is
lowered step by step (a feedback on the mean axial force of the middle 30
joints) to a target compression, then held; a small lateral velocity in the
buckle's shape is the imperfection. Below the load the lateral offset decays,
above it it grows to a large fraction of the clearance. The test brackets the
onset within +-20 % of the closed form (the issue's bound); measured: 0.85
F_DP stays straight, 1.15 F_DP buckles.
"""

from __future__ import annotations

import math

import numpy as np

from drillfatigue.config import case_from_dict
from drillfatigue.dynamics.core import layout as L
from drillfatigue.dynamics.run.model import advance_model, build_model, straight_path
from drillfatigue.string import build_segments

INC_DEG = 60.0
HOLE_D = 0.2159
OD, ID = 0.127, 0.1086
CHUNK_S = 0.05
HOLD_S = 3.0


def _lateral_history(ratio: float) -> np.ndarray:
    """Largest lateral offset (fraction of the clearance) per chunk, at ``ratio`` x F_DP."""
    cfg = case_from_dict({
        "string": {"components": [{"type": "drill_pipe", "od_m": OD, "id_m": ID,
                                   "length_m": 100.0, "n_segments": 50}]},
        "operation": {"bit_md_m": 110.0, "top_md_m": 10.0, "bit_on_bottom": True,
                      "top_axial": "fixed", "rpm": 0.0, "rpm_ramp_s": 0.0, "rop_m_per_s": 0.0},
        "friction": {"mu_static": 0.0, "mu_dynamic": 0.0},
        "bit": {"model": "given_tob"},
        "solver": {"relax_s": 0.3},
    })
    model, state = build_model(cfg, straight_path(200.0, inclination_deg=INC_DEG,
                                                  hole_diameter_m=HOLE_D))
    segs = build_segments(cfg.string, cfg.operation.mud_density_kg_per_m3)
    w = float(segs.buoyed_weight_N[0] / segs.length_m[0])
    r_c = HOLE_D / 2 - OD / 2
    f_dp = 2.0 * math.sqrt(float(segs.ei_Nm2[0]) * w * math.sin(math.radians(INC_DEG)) / r_c)
    axis = model.path.wall[0, 3:6]
    low = np.array([0.0, 0.0, 1.0]) - axis[2] * axis
    lateral = np.cross(axis, low / np.linalg.norm(low))
    n = model.n0
    s = 2.0 * np.arange(n)
    state.v[:n] += 1e-3 * np.outer(np.sin(2.0 * np.pi * s / 25.0), lateral)
    k_string = 1.0 / (1.0 / model.jp[n - 1, L.J_KA] + float((1.0 / model.jp[: n - 1, L.J_KA]).sum())
                      + 1.0 / model.bp[L.B_KBIT])
    chunk = int(round(CHUNK_S / model.dt))
    force = 0.0
    out_lat = []
    for _ in range(int(HOLD_S / CHUNK_S)):
        # gentle feedback: at most 4 % of F_DP per chunk, no axial overshoot
        step = min(0.3 * (ratio * f_dp - force), 0.04 * f_dp) / k_string
        model.anchor[0:3] += step * model.anchor[7:10]
        res = advance_model(model, state, chunk, every=chunk // 10)
        force = -float(res["loads"][:, 10:40, 0].mean())
        rel = state.x[:n] - model.path.wall[0, 0:3]
        out_lat.append(float(np.abs(rel @ lateral).max()) / r_c)
    assert abs(force - ratio * f_dp) < 0.03 * f_dp  # the target compression was reached
    return np.array(out_lat)


def test_below_dawson_paslay_the_string_stays_on_the_low_side() -> None:
    lat = _lateral_history(0.8)
    assert lat.max() < 0.01
    assert lat[-1] < lat[0]  # the imperfection decays


def test_above_dawson_paslay_the_string_buckles_laterally() -> None:
    lat = _lateral_history(1.2)
    assert lat.max() > 0.3  # snaked a third of the clearance up the side
