"""Whirl of a free pipe in a horizontal hole (founding paper case 1, docs/model.md#case-studies).

data/cases/case1_whirl.yaml: 5 m of 5 in pipe in 5 segments, both ends free,
horizontal 8 1/2 in hole, constant top torque. With high wall friction the
pipe rolls round the wall without slip: backward whirl, whose orbit rate is
Omega = -r_p / (R_h - r_p) omega (rolling kinematics: the contact point's
surface speed r_p omega equals the orbit speed (R_h - r_p) Omega, opposite
sense). With low friction it only climbs the wall to the friction angle and
slides back. Run with the tanh-exponential and the Karnopp law; the wall-time
ratio is recorded (paper: 47 min Karnopp vs 18 min tanh-exp).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

import drillfatigue
from drillfatigue.config import case_from_dict
from drillfatigue.config.base import read_yaml

CASE = Path(__file__).resolve().parents[2] / "data" / "cases" / "case1_whirl.yaml"
R_P = 0.0635      # pipe contact radius, m (5 in pipe, no tool joints)
R_H = 0.2159 / 2  # hole radius, m (8 1/2 in)


def _run(duration_s: float = 2.0, **friction: object):
    data = read_yaml(CASE)
    data["operation"]["duration_s"] = duration_s
    data["recording"]["events_start_s"] = 1.0
    data["friction"].update(friction)
    res = drillfatigue.simulate(case_from_dict(data), None, progress=False)
    # wall time of the stepping loop (no start-up or compilation)
    return res, res.summary["duration_s"] / res.summary["real_time_factor"]


def _orbit_over_spin(res) -> np.ndarray:
    ev = res.summary["events"]
    return np.array(ev["orbit_angle_rad"]) / np.array(ev["spin_angle_rad"])


def test_high_friction_gives_backward_whirl_at_the_rolling_rate() -> None:
    expected = -R_P / (R_H - R_P)
    walls = {}
    _run(0.05)  # warm-up: loading the compiled kernels is not part of the timing
    for model in ("tanh_exp", "karnopp"):
        res, walls[model] = _run(model=model)
        ev = res.summary["events"]
        assert res.summary["whirl_class"] == "backward", model
        assert ev["whirl_per_segment"] == ["backward"] * 5, model
        # 15 %: the bound (measured -1.41 vs -1.43, 1.3 %: near-pure rolling)
        np.testing.assert_allclose(_orbit_over_spin(res), expected, rtol=0.15)
    # the Karnopp stick band needs a smaller step (paper: 47 vs 18 min, ratio 2.6;
    # measured here: step 2.5e-5 vs 6.9e-5 s, wall-time ratio 2.5)
    print(f"wall time karnopp / tanh_exp = {walls['karnopp'] / walls['tanh_exp']:.2f}")


def test_low_friction_climbs_the_wall_and_slides_back() -> None:
    res, _ = _run(mu_static=0.1, mu_dynamic=0.08)
    assert res.summary["whirl_class"] == "none"
    kin = res.kinematics.to_pandas()
    kin = kin[kin.time_s > 0.3]  # after the drop onto the low side
    clearance = R_H - R_P
    # lying on the wall (centre ~ one clearance from the hole axis) ...
    np.testing.assert_allclose(kin.dist_from_centre_m.median(), clearance, rtol=0.05)
    # ... displaced sideways (the hole is horizontal along north: y is lateral) by
    # about the friction angle: tan(theta) = mu -> y ~ clearance sin(atan 0.1),
    # never near the top of the hole
    y = kin.y_m.to_numpy()
    assert np.abs(y).max() > 0.001  # it does climb ...
    # static friction angle: 4.4 mm; the spinning drop onto the wall overshoots it
    # (measured 7.7 mm with the steel's lateral inertia, 13.5 mm with the mud inside
    # and the confined added mass, string.lateral_mud_mass: 2.6 x the inertia carried
    # into the wall); a whirling pipe would reach the full clearance (44 mm)
    assert np.abs(y).max() < 0.4 * clearance
    ev = res.summary["events"]
    assert max(abs(a) for a in ev["orbit_angle_rad"]) < np.pi  # ... and slides back
