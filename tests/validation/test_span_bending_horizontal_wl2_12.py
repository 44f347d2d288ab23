"""Drill pipe rotating on the low side of a straight horizontal hole, through the
simulator: the tool joints are the supports, the recorded span correction
alternates once per revolution with the amplitude of the continuous beam,
w L^2 / 12, and the fatigue chain turns it into the life of a hand calculation.

References
----------
* Continuous beam on many equal spans under a uniform load w (e.g. Roark's
  Formulas for Stress and Strain, 8th ed., table 8.5 / the three-moment
  equation): the moment over an interior support far from the ends is
  w L^2 / 12. Here 10 spans of L = 9.144 m (one joint each) rest on the tool
  joints, pinned at the bit and at the joint below the rig-held top segment;
  over the middle supports the finite chain differs from w L^2 / 12 by less
  than 0.2 % (exact three-moment solution of 10 equal spans), the penalty
  contact lets the supports sink by ~0.05 mm (kc = 5e7 N/m) while the pipe
  stays rigid between them. The issue asks for 5 %.
* Hand calculation of the life (docs/fatigue.md sections 1 and 3): a surface point
  of the body sees sigma_a = K_b (w L^2 / 12) r / I once per revolution,
  S = 2 sigma_a (no mean-stress correction, uniaxial route), damage
  n / N(S) on the DNV-RP-C203 B1 curve in air with n = rpm / 60 x window.
  The B1 slope above 1e7 cycles is 5, so a 1 % moment error is 5 % in life;
  the issue asks for 10 %.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from drillfatigue import rundir
from drillfatigue.config import case_from_dict
from drillfatigue.config.fatigue import FatigueConfig
from drillfatigue.dynamics.run.simulation import simulate
from drillfatigue.dynamics.run.model import advance_model, build_model, straight_path
from drillfatigue.fatigue.run import evaluate_run
from drillfatigue.fatigue.sn import get_curve
from drillfatigue.fatigue.stress import Section

OD, ID, TJ_OD = 0.127, 0.1086, 0.1683
JOINT_M = 9.144
N_JOINTS = 10
RPM = 50.0
START_S = 3.2   # after the 0.5 s relaxation (before t = 0), the 0.5 s rpm ramp and 2.7 s for
#                the span filter to ring down from the start of rotation (span_dynamics: in
#                air it is damped at the 5 % floor, 1 / (zeta omega) ~ 1 s)
WINDOW_S = 2.4  # two revolutions
MIDDLE = (4, 5)  # joints over the middle supports


def _case(span: bool = True, points: str = "string") -> object:
    length = JOINT_M * N_JOINTS + 6.0
    return case_from_dict({
        "string": {"components": [{"type": "drill_pipe", "od_m": OD, "id_m": ID,
                                   "length_m": length, "tool_joint_od_m": TJ_OD,
                                   "tool_joint_id_m": 0.0826, "joints_per_segment": 1}]},
        "operation": {"duration_s": START_S + WINDOW_S, "bit_md_m": length + 1.0,
                      "top_md_m": 1.0, "bit_on_bottom": False, "top_axial": "fixed",
                      "rpm": RPM, "rpm_ramp_s": 0.5, "mud_density_kg_per_m3": 0.0},
        "solver": {"relax_s": 0.5},
        "contact": {"points": points, "span_bending": span},
        "recording": {"loads_rate_hz": 200.0, "start_s": START_S},
    })


def _path():
    return straight_path(200.0, inclination_deg=90.0, n_nodes=21)


@pytest.fixture(scope="module")
def run(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, float]:
    out = tmp_path_factory.mktemp("horizontal") / "run"
    res = simulate(_case(), out, progress=False, path=_path())
    assert res.status == "complete"
    m = res.model
    w = float(m.seg[0, 4] / (2.0 * m.seg[0, 3]))  # weight per length in air (no mud)
    return out, w


def test_the_tool_joints_are_the_supports() -> None:
    model, _ = build_model(_case(), _path())
    n = model.n0
    # every segment below the top has exactly its two tool joints, at the tool-joint radius
    assert np.all(model.cp_n[: n - 1] == 2)
    assert np.allclose(model.cp[: n - 1, :2, 1], 0.5 * TJ_OD, rtol=0, atol=1e-12)
    assert np.allclose(np.abs(model.cp[: n - 1, :2, 0]), 0.5 * JOINT_M, rtol=0, atol=1e-9)


def test_span_moment_at_a_tool_joint_is_wl2_over_12(run: tuple[Path, float]) -> None:
    out, w = run
    loads = pd.read_parquet(out / rundir.LOADS)
    assert set(rundir.SPAN_COLUMNS) <= set(loads.columns)
    summary = json.loads((out / rundir.SUMMARY).read_text())
    assert summary["span_bending_buckled_samples"] == 0
    ref = w * JOINT_M ** 2 / 12.0  # ~1.83 kN m
    for j in MIDDLE:
        lj = loads[loads["joint"] == j]
        mx = lj["span_bending_x_Nm"].to_numpy()
        my = lj["span_bending_y_Nm"].to_numpy()
        amp = 0.5 * (mx.max() - mx.min())  # per-revolution amplitude in the pipe frame
        assert amp == pytest.approx(ref, rel=0.05)
        assert np.hypot(mx, my).mean() == pytest.approx(ref, rel=0.05)
        # it alternates: the x component changes sign within the window
        assert mx.max() > 0.9 * ref and mx.min() < -0.9 * ref
        # the rigid chain alone carries almost nothing there (issue: 1-3 N m)
        jm = np.hypot(lj["bending_x_Nm"], lj["bending_y_Nm"]).to_numpy()
        assert jm.mean() < 0.02 * ref


def test_life_through_the_chain_against_a_hand_calculation(run: tuple[Path, float]) -> None:
    out, w = run
    cfg = FatigueConfig(criterion="uniaxial", mean_stress="none", pressure=False,
                        joints=list(MIDDLE), plots=False)
    df = evaluate_run(out, cfg)
    body = df[df["location"] == "body"].set_index("joint")
    sec = Section(OD, ID)
    kb = cfg.scf["drill_pipe"].body.bending
    sig_a = kb * (w * JOINT_M ** 2 / 12.0) * sec.r_m / sec.inertia_m4
    n_cycles = RPM / 60.0 * WINDOW_S
    curve = get_curve("B1", "air")
    d_hand = n_cycles / float(curve.cycles_to_failure(np.array([2.0 * sig_a]))[0])
    # the chain's life divides the recorded window (not the run's whole simulated
    # time, which adds the START_S before recording starts) by the damage
    life_hand_h = WINDOW_S / 3600.0 / d_hand
    for j in MIDDLE:
        assert body.loc[j, "damage"] == pytest.approx(d_hand, rel=0.10)
        assert math.isfinite(body.loc[j, "life_h"])
        assert body.loc[j, "life_h"] == pytest.approx(life_hand_h, rel=0.10)


def test_span_bending_off_records_no_span_columns() -> None:
    model, state = build_model(_case(span=False, points="ends"), _path())
    got = advance_model(model, state, 30, every=10)
    assert "span_bending" not in got and got["loads"].shape[2] == 6
