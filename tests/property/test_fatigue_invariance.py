"""Frame and time invariance of the fatigue evaluation (hypothesis)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from drillfatigue.config.fatigue import FatigueConfig
from drillfatigue.fatigue.critical_plane import (CriterionParams, DamageOptions, PlaneSearch,
                                                 evaluate_location)
from drillfatigue.fatigue.run import evaluate_run
from drillfatigue.fatigue.sn import get_curve
from drillfatigue.fatigue.stress import SCF, Section

from testkit.fatigue_runs import synthetic_loads, write_run_dir

SEC = Section(0.127, 0.1086)
LOADS = synthetic_loads(1200, seed=3)


def rotate(L: np.ndarray, alpha: float) -> np.ndarray:
    """Express the loads in a frame turned by -alpha about z: vectors turn by +alpha."""
    c, s = np.cos(alpha), np.sin(alpha)
    out = L.copy()
    out[:, 1], out[:, 2] = c * L[:, 1] - s * L[:, 2], s * L[:, 1] + c * L[:, 2]
    out[:, 3], out[:, 4] = c * L[:, 3] - s * L[:, 4], s * L[:, 3] + c * L[:, 4]
    return out


@settings(max_examples=8, deadline=None)
@given(k=st.integers(1, 35), criterion=st.sampled_from(["matake", "findley", "uniaxial"]))
def test_rotating_the_load_frame_about_the_axis(k: int, criterion: str) -> None:
    alpha = np.radians(10.0 * k)  # a multiple of the 10 deg point spacing: exact mapping
    opt = DamageOptions(mean_stress="goodman")
    s1, s0 = PlaneSearch(plane_step_deg=15.0, n_refine=1), PlaneSearch(plane_step_deg=15.0, n_refine=0)
    curve, prm = get_curve("B1"), CriterionParams()
    a = evaluate_location(LOADS, SEC, SCF(), curve, criterion, prm, search=s1, options=opt)
    b = evaluate_location(rotate(LOADS, alpha), SEC, SCF(), curve, criterion, prm, search=s1,
                          options=opt)
    # same stress histories at relabelled points; only the rounding of the
    # rotation (1e-16 relative) separates them
    assert b.damage == pytest.approx(a.damage, rel=1e-9)
    # without refinement every point's damage maps to the point 10 k deg further on
    a0 = evaluate_location(LOADS, SEC, SCF(), curve, criterion, prm, search=s0, options=opt)
    b0 = evaluate_location(rotate(LOADS, alpha), SEC, SCF(), curve, criterion, prm, search=s0,
                           options=opt)
    np.testing.assert_allclose(np.roll(a0.point_damage, k), b0.point_damage, rtol=1e-9)


@pytest.fixture(scope="module")
def run_dir(tmp_path_factory: pytest.TempPathFactory) -> Path:
    return write_run_dir(tmp_path_factory.mktemp("run") / "r", n_joints=2, n_t=800)


@settings(max_examples=5, deadline=None)
@given(shift=st.floats(-1e4, 1e4, allow_nan=False))
def test_constant_time_shift_changes_nothing(run_dir: Path, shift: float, tmp_path_factory
                                             ) -> None:
    import pandas as pd

    cfg = FatigueConfig(plane_step_deg=15.0, n_refine=1, plots=False)
    ref = evaluate_run(run_dir, cfg)
    d = tmp_path_factory.mktemp("shift")
    for name in ("joints.parquet", "summary.json"):
        (d / name).write_bytes((run_dir / name).read_bytes())
    df = pd.read_parquet(run_dir / "loads.parquet")
    df["time_s"] = df["time_s"] + shift
    df.to_parquet(d / "loads.parquet", index=False)
    got = evaluate_run(d, cfg)
    np.testing.assert_allclose(got["damage"], ref["damage"], rtol=1e-12)
