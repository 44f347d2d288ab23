"""Off-bottom stick-slip in a deep deviated well against Aarsnes & Shor's distributed torsional model.

Reference: the wave equation with distributed wall friction of Aarsnes & Shor
(Torsional vibrations with bit off bottom, J. Petrol. Sci. Eng. 163 (2018) 712-721),
written in :mod:`testkit.torsional_wave` from its equations and discretised
independently of the simulator (10 m finite volumes, implicit friction per cell),
driven by the same PI top drive and the same friction law and parameters as the
simulator's case. The well: :mod:`testkit.off_bottom_well` (3010 m, 60 deg, 40 rpm).

What is pinned (docs/rig.md#off-bottom-stick-slip-and-the-stick-band):

1. With the same law the simulator and the reference agree: the default ``tanh_exp``
   and the ``stick_band`` law at Aarsnes & Shor's band (1.5 rad/s of their script,
   95 mm/s at the surface of the 5 in pipe).
2. The stick band sets the period: Aarsnes & Shor's law sticks longer and more often
   than ``tanh_exp`` with the same mu_s and mu_d, in both models.
3. The torsional mud drag decides whether the default law sustains the stick-slip at
   60 rpm: the default 0.05 N m s/rad per m removes it in both models, 0.03 (about
   Aarsnes & Shor's field fit) keeps it. In the reference their stick-band law keeps
   it at 0.05; the simulator's does not (severity 0.7): at this boundary the 3-D string
   loses more (the pipe's climb and roll, lateral mud drag, joint damping) than the
   torsional reference, so only the reference's side of it is asserted.

Tolerances. Period and break-off torque 10 %: the reference's own grid (20, 10, 5 m
cells) moves its period by 3 % and its break-off torque by 1 %, the median over four
to six cycles moves by a sample of the cycle-to-cycle scatter (a few %), and the
simulator's pipe climbs the wall with a lag the reference does not have (its
break-off torque sits 3-5 % lower). Stuck fraction 0.08 absolute: the reference's grid
moves it by 0.02, a cycle more or less in the window by about 0.05.
"""

from __future__ import annotations

import functools

import pytest

from testkit import off_bottom_well as W

pytestmark = pytest.mark.slow


@functools.cache
def _run(model: str, law: str, damping: float = 0.05, rpm: float = 40.0) -> dict[str, float]:
    run = W.simulate_case if model == "simulator" else W.simulate_reference
    res = run(law=law, damping=damping, rpm=rpm)
    if model == "simulator":
        assert abs(res["wob"]).max() == 0.0  # off bottom all along: no bit torque
    return W.metrics(res, rpm)


def test_simulator_matches_the_distributed_model_with_either_law() -> None:
    for law in ("tanh_exp", "stick_band"):
        sim, ref = _run("simulator", law), _run("reference", law)
        print(f"{law}: simulator {sim}, reference {ref}")
        assert sim["n_cycles"] >= 3 and ref["n_cycles"] >= 3, (law, sim, ref)
        assert sim["period_s"] == pytest.approx(ref["period_s"], rel=0.10), (law, sim, ref)
        assert sim["break_off_Nm"] == pytest.approx(ref["break_off_Nm"], rel=0.10), (law, sim, ref)
        assert sim["stuck_fraction"] == pytest.approx(ref["stuck_fraction"], abs=0.08), (law, sim, ref)


def test_the_stick_band_sets_the_period_and_the_time_stuck() -> None:
    for model in ("simulator", "reference"):
        smooth, band = _run(model, "tanh_exp"), _run(model, "stick_band")
        # measured: 17-18 % longer, 0.19-0.22 more of the time stuck
        assert band["period_s"] > 1.10 * smooth["period_s"], (model, smooth, band)
        assert band["stuck_fraction"] > smooth["stuck_fraction"] + 0.12, (model, smooth, band)


def test_torsional_mud_drag_decides_the_default_law_at_60_rpm() -> None:
    for model in ("simulator", "reference"):
        default = _run(model, "tanh_exp", damping=0.05, rpm=60.0)
        published = _run(model, "tanh_exp", damping=0.03, rpm=60.0)
        print(f"{model} at 60 rpm: tanh_exp 0.05 {default}, 0.03 {published}")
        assert default["n_cycles"] == 0 and default["stuck_fraction"] == 0.0, (model, default)
        assert published["n_cycles"] >= 3 and published["stuck_fraction"] > 0.1, (model, published)
    band = _run("reference", "stick_band", damping=0.05, rpm=60.0)
    assert band["n_cycles"] >= 3 and band["stuck_fraction"] > 0.1, band
