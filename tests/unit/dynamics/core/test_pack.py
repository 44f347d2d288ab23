"""Lateral mud mass in the Newton-Euler step: body-frame mass diag(m r, m r, m).

References: Newton's second law in the body frame (the axial component of a
force accelerates the steel mass m, the part across the axis the lateral mass
m r); the lateral mass per length is steel + mud inside + C_a x displaced mud
(:mod:`drillfatigue.string.added_mass`, Fritz 1972 for C_a). Tolerances are
round-off (1e-12 relative): the kick is a closed-form update.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from drillfatigue.config import CaseConfig, case_from_dict
from drillfatigue.dynamics.core import layout as L
from drillfatigue.dynamics.run.model import advance_model, build_model, straight_path
from drillfatigue.dynamics.core.rigid import kick, kick_lateral

finite = st.floats(-1e4, 1e4, allow_nan=False)


@settings(max_examples=60, deadline=None)
@given(st.lists(finite, min_size=3, max_size=3), st.lists(finite, min_size=3, max_size=3),
       st.floats(1.0, 3.0), st.floats(0.0, math.pi), st.floats(0.0, 2 * math.pi))
def test_axial_and_lateral_parts_see_their_own_mass(F, Mb, ratio, th, ph) -> None:
    axis = np.array([math.sin(th) * math.cos(ph), math.sin(th) * math.sin(ph), math.cos(th)])
    F = np.array(F)
    Mb = np.array(Mb)
    m, It, Ia, h = 250.0, 1800.0, 1.2, 1e-4
    v = np.zeros(3)
    w = np.zeros(3)
    kick_lateral(v, w, F, Mb, m, ratio, It, Ia, axis, h)
    fa = F @ axis
    want = h * (fa * axis / m + (F - fa * axis) / (m * ratio))
    assert np.allclose(v, want, rtol=1e-12, atol=1e-15)
    assert np.allclose(w, h * Mb / np.array([It * ratio, It * ratio, Ia]), rtol=1e-12, atol=1e-15)
    # ratio 1 is the plain kick
    v1, w1, v2, w2 = np.zeros(3), np.zeros(3), np.zeros(3), np.zeros(3)
    kick_lateral(v1, w1, F, Mb, m, 1.0, It, Ia, axis, h)
    kick(v2, w2, F, Mb, m, It, Ia, h)
    assert np.allclose(v1, v2, rtol=1e-12, atol=1e-15) and np.array_equal(w1, w2)


def _case(on: bool, mud: float = 1200.0):
    return case_from_dict({
        "string": {"components": [{"type": "drill_pipe", "od_m": 0.127, "id_m": 0.1086,
                                   "length_m": 60.0, "n_segments": 6}],
                   "lateral_mud_mass": on},
        "operation": {"bit_md_m": 61.0, "top_md_m": 1.0, "bit_on_bottom": False,
                      "top_axial": "fixed", "rpm": 0.0, "mud_density_kg_per_m3": mud},
    })


def test_builder_packs_the_lateral_mass_ratio() -> None:
    hole = 0.2159
    model, _ = build_model(_case(True), straight_path(100.0, 90.0, hole_diameter_m=hole))
    assert model.cpar[L.P_LATMASS] == 1.0
    ro, ri, R = 0.0635, 0.0543, 0.5 * hole
    ca = (R * R + ro * ro) / (R * R - ro * ro)
    steel = 7850.0 * math.pi * (ro * ro - ri * ri)
    mud = 1200.0 * math.pi * (ri * ri + ca * ro * ro)
    assert np.allclose(model.mlat, (steel + mud) / steel, rtol=1e-9)
    off, _ = build_model(_case(False), straight_path(100.0, 90.0, hole_diameter_m=hole))
    assert off.cpar[L.P_LATMASS] == 0.0 and np.all(off.mlat == 1.0)


def test_a_pipe_sinking_in_mud_accelerates_at_weight_over_lateral_mass() -> None:
    # no wall, horizontal: the bit segment, far from the rig-held top, starts to sink
    # under its buoyed weight W; Newton: dv/dt = W / (m r) across the axis
    # (the steel mass alone without the switch). 20 steps of 1e-4 s: the joints
    # stay unloaded (the whole lower string sinks together), so the ratio of the
    # two velocities is r to 1e-9.
    def sink(on: bool) -> tuple[float, float]:
        data = _case(on).model_dump()
        data["contact"]["enabled"] = False
        data["solver"]["relax_s"] = 0.0
        data["solver"]["dt_s"] = 1e-4
        for k in ("mud_damping_lateral_N_s_per_m2", "mud_damping_axial_N_s_per_m2",
                  "mud_damping_torsional_N_m_s_per_m"):
            data["operation"][k] = 0.0
        model, state = build_model(CaseConfig.model_validate(data),
                                   straight_path(100.0, 90.0, hole_diameter_m=0.2159))
        advance_model(model, state, 20, every=20)
        return float(state.v[0, 2]), float(model.mlat[0])

    v_off, _ = sink(False)
    v_on, r = sink(True)
    assert r > 1.5
    assert v_off > 0.0
    assert v_off / v_on == pytest.approx(r, rel=1e-9)
