"""Off-bottom stick-slip in a deep deviated well against Aarsnes & Shor's distributed torsional model.

Reference: the wave equation with distributed wall friction of Aarsnes & Shor
(Torsional vibrations with bit off bottom, J. Petrol. Sci. Eng. 163 (2018) 712-721),
written in :mod:`testkit.torsional_wave` from its equations and discretised
independently of the simulator (10 m finite volumes, implicit friction per cell),
driven by the same PI top drive and the same friction law and parameters as the
simulator's case. The well: :mod:`testkit.off_bottom_well` (3010 m, 60 deg, 40 rpm).

What is pinned (docs/rig.md#off-bottom-stick-slip-and-the-stick-band):

1. With the default law (``tanh_exp``) the simulator and the reference agree.
2. The stick band sets the period: with Aarsnes & Shor's law (``stick_band`` at 90 and
   95 mm/s, about the 1.5 rad/s of their script on the 5 in pipe) the reference sticks
   longer and more often than with ``tanh_exp`` of the same mu_s and mu_d, and the same
   at either band.
3. In the simulator the stick band lands the string in one of two states: at 95 mm/s
   the reference's (period, break-off torque and stuck fraction within the tolerances
   below), at 90 mm/s a short-stick state (period 5.3 s, the bit stuck a fifth of the
   time, about what ``tanh_exp`` gives), where the reference does not move. In 3-D the
   band acts on the whole slip at the contact, the pipe's roll and sideways motion with
   its spin, and the sticking of the 50 m segments decides the cycle; measured over
   bands of 80-110 mm/s the simulator took either state (and once no sustained cycle)
   with no order in the band, the reference always the long one.
4. The torsional mud drag decides whether the default law sustains the stick-slip at
   60 rpm: the former default 0.05 N m s/rad per m removes it in both models, 0.03 (the
   default since, Aarsnes & Shor's field fit) keeps it; the reference's stick-band law keeps it at 0.05.

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
def _run(model: str, law: str, damping: float = 0.05, rpm: float = 40.0,
         band: float = 0.095) -> dict[str, float]:
    run = W.simulate_case if model == "simulator" else W.simulate_reference
    res = run(law=law, damping=damping, rpm=rpm, band_m_per_s=band)
    if model == "simulator":
        assert abs(res["wob"]).max() == 0.0  # off bottom all along: no bit torque
    return W.metrics(res, rpm)


def _agree(sim: dict[str, float], ref: dict[str, float]) -> None:
    assert sim["n_cycles"] >= 3 and ref["n_cycles"] >= 3, (sim, ref)
    assert sim["period_s"] == pytest.approx(ref["period_s"], rel=0.10), (sim, ref)
    assert sim["break_off_Nm"] == pytest.approx(ref["break_off_Nm"], rel=0.10), (sim, ref)
    assert sim["stuck_fraction"] == pytest.approx(ref["stuck_fraction"], abs=0.08), (sim, ref)


def test_default_law_simulator_matches_the_distributed_model() -> None:
    sim, ref = _run("simulator", "tanh_exp"), _run("reference", "tanh_exp")
    print(f"tanh_exp: simulator {sim}, reference {ref}")
    _agree(sim, ref)


def test_the_stick_band_sets_the_period_in_the_distributed_model() -> None:
    smooth = _run("reference", "tanh_exp")
    for band in (0.09, 0.095):
        ref = _run("reference", "stick_band", band=band)
        # measured: 19-20 % longer, 0.21-0.22 more of the time stuck
        assert ref["period_s"] > 1.10 * smooth["period_s"], (band, smooth, ref)
        assert ref["stuck_fraction"] > smooth["stuck_fraction"] + 0.12, (band, smooth, ref)
    assert _run("reference", "stick_band", band=0.09)["period_s"] == pytest.approx(ref["period_s"], rel=0.05)


def test_simulator_stick_band_takes_the_reference_state_or_a_short_stick_one() -> None:
    ref = _run("reference", "stick_band", band=0.095)
    long_state = _run("simulator", "stick_band", band=0.095)
    print(f"stick_band 95 mm/s: simulator {long_state}, reference {ref}")
    _agree(long_state, ref)
    short = _run("simulator", "stick_band", band=0.09)
    smooth = _run("simulator", "tanh_exp")
    print(f"stick_band 90 mm/s: simulator {short}")
    assert short["n_cycles"] >= 3, short
    assert short["period_s"] < 0.9 * ref["period_s"] and short["stuck_fraction"] < 0.3, (short, ref)
    assert short["period_s"] == pytest.approx(smooth["period_s"], rel=0.10), (short, smooth)


def test_torsional_mud_drag_decides_the_default_law_at_60_rpm() -> None:
    for model in ("simulator", "reference"):
        default = _run(model, "tanh_exp", damping=0.05, rpm=60.0)
        published = _run(model, "tanh_exp", damping=0.03, rpm=60.0)
        print(f"{model} at 60 rpm: tanh_exp 0.05 {default}, 0.03 {published}")
        assert default["n_cycles"] == 0 and default["stuck_fraction"] == 0.0, (model, default)
        assert published["n_cycles"] >= 3 and published["stuck_fraction"] > 0.1, (model, published)
    band = _run("reference", "stick_band", damping=0.05, rpm=60.0)
    assert band["n_cycles"] >= 3 and band["stuck_fraction"] > 0.1, band
