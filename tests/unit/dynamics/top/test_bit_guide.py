"""Bit boundary off bottom: the lateral guide follows the path at the bit's depth.

Regression: a bit lagging s metres behind the rock face in a build section was
pulled towards the tangent line at the face, which lies ~ s^2 kappa / 2 off the
hole axis at the bit (22 mm at 5 m in a 3 deg/30 m build): with the stiff guide
spring that is a force of order MN into the wall.

Reference (exact): a bit lying on the well path at its own depth feels no
lateral guide force, however far the face is ahead of it; so the total force on
the bit segment must not depend on how far above the face the bit is, once it
is off bottom (WOB = 0 in both states). Tolerance: 1e-4 of the bit segment's
weight: the bit's depth is found by Newton steps on the arc length (the path
point whose normal plane holds the bit face), converged to 1e-9 m; what is
left is round-off (measured 1.6e-7 N at 10 m, 0 at 40 and 120 m; the old guide
gave 6 MN at 10 m, and a projection on the face tangent alone pushed a bit
100 m up the build through the wall).
"""

from __future__ import annotations

import numpy as np
import pytest

from drillfatigue.dynamics.core import layout as L
from drillfatigue.dynamics.core import status
from drillfatigue.dynamics.run.simulation import _wellpath
from drillfatigue.dynamics.run.examples import j_well_rotating_case
from drillfatigue.dynamics.step.forces import compute_forces
from drillfatigue.dynamics.run.model import build_model


def _bit_force(extra_lag_m: float) -> tuple[np.ndarray, float]:
    cfg = j_well_rotating_case(kop_m=60.0, dls_deg_per_30m=3.0, inc_deg=30.0, bit_md_m=300.0,
                               n_segments=20,
                               extra={"operation": {"bit_on_bottom": True,
                                                    "top_axial": "neutral_point",
                                                    "neutral_point_s_from_bit_m": 60.0},
                                      "solver": {"relax_s": 0.0}})
    path = _wellpath(cfg)
    model, s = build_model(cfg, path)
    wk = model.work
    sc = s.sc.copy()
    sc[L.C_MDROCK] += 0.01 + extra_lag_m  # face ahead of the bit: off bottom
    s2 = s.copy()._replace(sc=sc)
    st = compute_forces(s2, model.params, wk)
    assert st == status.OK
    assert wk.ch[L.H_WOB] == 0.0
    return s2.Fw[0].copy(), float(model.seg[0, L.S_W])


@pytest.mark.parametrize("lag_m", [1.0, 5.0, 10.0, 40.0, 120.0])
def test_off_bottom_bit_force_independent_of_face_distance(lag_m: float) -> None:
    f_near, weight = _bit_force(0.0)
    f_far, _ = _bit_force(lag_m)
    np.testing.assert_allclose(f_far, f_near, rtol=0.0, atol=1e-4 * weight)
