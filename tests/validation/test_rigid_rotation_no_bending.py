"""Rigid rotation of a straight string at constant rpm in a vertical hole: no bending.

A straight, axisymmetric string spinning about its own axis is in equilibrium
with zero bending moments and shears (the gyroscopic term w x I w vanishes for
rotation about the symmetry axis). The model starts at full speed (no ramp)
with the torsional pre-load of the mud damping torque.
"""

from __future__ import annotations

import numpy as np

from drillfatigue.config import case_from_dict
from drillfatigue.dynamics.run.model import advance_model, build_model, straight_path


def test_constant_rpm_gives_no_bending_or_shear() -> None:
    cfg = case_from_dict({
        "string": {"components": [
            {"type": "collar", "od_m": 0.17145, "id_m": 0.0714, "length_m": 40.0, "n_segments": 4},
            {"type": "drill_pipe", "od_m": 0.127, "id_m": 0.1086, "length_m": 160.0,
             "tool_joint_od_m": 0.1683, "n_segments": 16}]},
        "operation": {"bit_md_m": 200.0, "top_axial": "neutral_point", "rpm": 150.0,
                      "rpm_ramp_s": 0.0, "tob_Nm": 0.0},
    })
    model, state = build_model(cfg, straight_path(400.0))
    out = advance_model(model, state, int(1.0 / model.dt), every=10)
    loads = out["loads"]
    # the string really rotates and carries torque and tension ...
    assert np.abs(loads[:, :, 5]).max() > 1.0
    assert np.abs(loads[:, :, 0]).max() > 1e4
    # ... but no bending or shear beyond round-off (relative 1e-9 of the axial load)
    scale = np.abs(loads[:, :, 0]).max()
    assert np.abs(loads[:, :, 1:5]).max() < 1e-9 * scale
