"""The buckling detector on the simulator's own string: slack-off below and above Dawson-Paslay.

Set-up of tests/validation/test_dawson_paslay_buckling.py (100 m of 5 in pipe
in 50 segments, 60 deg hole, frictionless, bit on bottom, top lowered by a
gentle feedback to a target compression, then held 3 s, with a small lateral
imperfection in the shape of a 25 m buckle). The detector reads only the
segment positions, the hole axis and the contact forces, as it will on a
run's kinematics: at 0.8 F_DP every window is ``none``; at 1.2 F_DP (the
issue's +-20 % band) the middle of the string is ``sinusoidal`` with a
wavelength close to the Dawson-Paslay buckle wavelength
(``2 pi (EI r_c / (w sin I))^(1/4)`` = 25.8 m for this pipe). Measured: the
two 52 m windows swing 0.55 and 0.59 of the clearance with wavelengths 24 and
28 m; asked within 25 % of 25.8 m, since a 3 s hold shows the early buckle,
not its settled shape.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from drillfatigue.config import case_from_dict
from drillfatigue.dynamics.run import buckling as BD
from drillfatigue.softstring import buckling as B
from drillfatigue.dynamics.core import layout as L
from drillfatigue.dynamics.run.model import advance_model, build_model, straight_path
from drillfatigue.string import build_segments

INC_DEG = 60.0
HOLE_D = 0.2159
OD, ID = 0.127, 0.1086
CHUNK_S = 0.05
HOLD_S = 3.0


def _final_detection(ratio: float) -> tuple[BD.BucklingDetection, float]:
    cfg = case_from_dict({
        "string": {"components": [{"type": "drill_pipe", "od_m": OD, "id_m": ID,
                                   "length_m": 100.0, "n_segments": 50}]},
        "operation": {"bit_md_m": 110.0, "top_md_m": 10.0, "bit_on_bottom": True,
                      "top_axial": "fixed", "rpm": 0.0, "rpm_ramp_s": 0.0, "rop_m_per_s": 0.0},
        "friction": {"mu_static": 0.0, "mu_dynamic": 0.0},
        "bit": {"model": "given_tob"},
        "solver": {"relax_s": 0.3},
    })
    model, state = build_model(cfg, straight_path(200.0, inclination_deg=INC_DEG, hole_diameter_m=HOLE_D))
    segs = build_segments(cfg.string, cfg.operation.mud_density_kg_per_m3)
    w = float(segs.buoyed_weight_N[0] / segs.length_m[0])
    ei = float(segs.ei_Nm2[0])
    r_c = HOLE_D / 2 - float(segs.contact_radius_m[0])
    f_dp = B.sinusoidal_onset_straight_N(ei, w, math.radians(INC_DEG), r_c)
    p0 = model.path.wall[0, 0:3]
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
    for _ in range(int(HOLD_S / CHUNK_S)):
        step = min(0.3 * (ratio * f_dp - force), 0.04 * f_dp) / k_string
        model.anchor[0:3] += step * model.anchor[7:10]
        res = advance_model(model, state, chunk, every=chunk // 10)
        force = -float(res["loads"][:, 10:40, 0].mean())
    x = state.x[:n]
    along = (x - p0) @ axis
    centre = p0 + along[:, None] * axis
    s_bit = float(along.max()) - along  # distance from the lowest segment centre
    order = np.argsort(s_bit)
    rho, theta = BD.lateral_offsets(x[order], centre[order], np.tile(axis, (n, 1)), r_c)
    # the pipe body clearance: the detector measures the offset of segment centres
    wave = 2.0 * math.pi * (ei * r_c / (w * math.sin(math.radians(INC_DEG)))) ** 0.25
    det = BD.detect_buckling(s_bit[order], rho, theta, np.ones(n, bool), window_m=2.0 * wave)
    return det, wave


@pytest.mark.slow
def test_detector_sees_no_buckle_below_and_a_sinusoidal_buckle_above_dawson_paslay() -> None:
    det, _ = _final_detection(0.8)
    assert set(det.state_names()) == {"none"}
    det, wave = _final_detection(1.2)
    assert "sinusoidal" in det.state_names()
    assert "helical" not in det.state_names()
    waves = det.wavelength_m[det.state == 1]
    assert 0.75 * wave < float(np.nanmedian(waves)) < 1.25 * wave
