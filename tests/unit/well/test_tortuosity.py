"""Hole tortuosity (drillfatigue.well.tortuosity): geometry, the option's wiring, its report.

A sine tilt ``delta = A sin(2 pi s / P)`` of a straight hole turns it at
``2 pi A / P |cos|``: peak dogleg severity 2 pi A / P, mean 4 A / P. Minimum
curvature between stations h apart sees the mean turning rate of each interval,
``2 A sin(pi h / P) |cos(phase)| / h``: with 32 stations per period and
intervals up to 1.125 h (a grid station within h/8 of a plan station is left
out), the largest interval rate lies between sinc(1.125 pi / 32) cos(1.125 pi / 32)
= 0.9919 and 1 times the peak, hence the 1 % tolerance below.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from drillfatigue.config import WellConfig, case_from_dict
from drillfatigue.config.well import TortuosityConfig
from drillfatigue.errors import InputError
from drillfatigue.sweep.cases import position_columns
from drillfatigue.well import (
    apply_tortuosity,
    build_plan_survey,
    build_survey,
    build_wellbore,
    minimum_curvature,
    profile_report,
    tortuosity_index_per_m,
)
from drillfatigue.well.features import WINDOW_M
from drillfatigue.well.tortuosity import dls_statistics, tilt_rad, tortuosity_report

DEG30 = math.degrees(1.0) * 30.0  # rad/m -> deg/30 m
#: largest interval rate of a sampled sine over its peak rate (module docstring)
SAMPLED_PEAK_LOW = 0.99


def straight(inc_deg: float, azi_deg: float, td_m: float) -> object:
    """A straight hole from the surface: two stations."""
    return minimum_curvature(np.array([0.0, td_m]), np.radians([inc_deg, inc_deg]),
                             np.radians([azi_deg, azi_deg]))


def spec(**kw: object) -> TortuosityConfig:
    return TortuosityConfig(**{"model": "sine", "amplitude_deg": 1.0, "period_m": 30.0, **kw})


@pytest.mark.parametrize("inc_deg", [0.0, 30.0, 90.0])
@pytest.mark.parametrize("direction", ["inclination", "azimuth"])
@pytest.mark.parametrize("amp_deg, period_m", [(1.0, 30.0), (0.5, 50.0), (2.0, 100.0),
                                               (0.25, 7.0)])
def test_sine_on_a_straight_hole_peaks_at_2_pi_a_over_p(inc_deg: float, direction: str,
                                                       amp_deg: float, period_m: float) -> None:
    sv = apply_tortuosity(straight(inc_deg, 40.0, 900.0),
                          spec(amplitude_deg=amp_deg, period_m=period_m, direction=direction,
                               md_start_m=35.0))
    peak = 2.0 * math.pi * math.radians(amp_deg) / period_m * DEG30
    assert SAMPLED_PEAK_LOW * peak <= sv.max_dls_deg_per_30m <= peak * (1.0 + 1e-9)
    assert spec(amplitude_deg=amp_deg, period_m=period_m).peak_added_dls_deg_per_30m \
        == pytest.approx(peak, rel=1e-12)


def test_sine_mean_dls_is_4_a_over_p_over_whole_periods() -> None:
    """In the plan's vertical plane the interval dogleg is the change of inclination; the
    grid holds the wave's extremes (32 stations per period, a multiple of 4), so the sum
    over whole periods is the wave's total variation, 4 A per period, to rounding."""
    a, p = 1.5, 40.0
    sv = apply_tortuosity(straight(60.0, 10.0, 100.0 + 20 * p),
                          spec(amplitude_deg=a, period_m=p, md_start_m=100.0))
    _, mean = dls_statistics(sv, 100.0)
    assert mean == pytest.approx(4.0 * math.radians(a) / p * DEG30, rel=1e-9)
    # the tilt is the change of inclination, the azimuth stays
    inc = np.degrees(sv.inc_rad)
    assert inc.max() == pytest.approx(60.0 + a, abs=1e-9)
    assert inc.min() == pytest.approx(60.0 - a, abs=1e-9)
    assert np.allclose(np.degrees(sv.azi_rad), 10.0, atol=1e-9)


def test_both_directions_add_sqrt2_and_tilt_sideways() -> None:
    sv = apply_tortuosity(straight(45.0, 0.0, 600.0), spec(direction="both"))
    peak = math.sqrt(2.0) * 2.0 * math.pi * math.radians(1.0) / 30.0 * DEG30
    assert SAMPLED_PEAK_LOW * peak <= sv.max_dls_deg_per_30m <= peak * (1.0 + 1e-9)
    assert np.ptp(np.degrees(sv.azi_rad)) > 1.0  # an azimuth wave, not only inclination


def test_zero_amplitude_is_the_plan_and_small_amplitudes_converge_to_it() -> None:
    cfg = WellConfig()
    plan = build_plan_survey(cfg)
    assert apply_tortuosity(plan, spec(amplitude_deg=0.0)) is plan
    for amp, tol in ((1e-6, 1e-6), (1e-9, 1e-9)):
        sv = apply_tortuosity(plan, spec(amplitude_deg=amp, md_start_m=200.0))
        assert set(plan.md_m) <= set(sv.md_m)
        at = np.searchsorted(sv.md_m, plan.md_m)
        # the position error grows with the tilt (first order, |delta| * length)
        assert np.max(np.abs(sv.pos_m[at] - plan.pos_m)) < tol * 1.0e3
        assert np.max(np.abs(sv.inc_rad[at] - plan.inc_rad)) < math.radians(amp) * 1.001


def test_above_the_start_the_hole_is_the_plan_bit_for_bit() -> None:
    cfg = WellConfig(tortuosity={"model": "random", "amplitude_deg": 2.0, "period_m": 20.0,
                                 "md_start_m": 600.0, "direction": "both", "seed": 7})
    plan, sv = build_plan_survey(cfg), build_survey(cfg)
    k = int(np.searchsorted(plan.md_m, 600.0, side="right"))
    for name in ("md_m", "inc_rad", "azi_rad", "pos_m", "dls_rad_per_m"):
        assert np.array_equal(getattr(sv, name)[:k], getattr(plan, name)[:k]), name
    assert sv.md_m[-1] == plan.md_m[-1]  # the measured depth is kept
    assert not np.array_equal(sv.pos_m[-1], plan.pos_m[-1])


def test_off_is_the_plan_and_leaves_the_configuration_as_it_was() -> None:
    cfg = WellConfig()
    assert cfg.tortuosity is None
    plan, sv = build_plan_survey(cfg), build_survey(cfg)
    for name in ("md_m", "inc_rad", "azi_rad", "pos_m", "dls_rad_per_m"):
        assert np.array_equal(getattr(sv, name), getattr(plan, name))
    # the dump (case ids, configuration hashes, written case files) has no new key
    assert "tortuosity" not in cfg.model_dump(mode="json")
    assert set(cfg.model_dump()) == set(WellConfig.model_fields) - {"tortuosity"}
    assert "tortuosity" not in profile_report(cfg)["profile_1"]
    on = WellConfig(tortuosity={"model": "sine", "amplitude_deg": 1.0, "period_m": 30.0})
    dumped = on.model_dump(mode="json")
    assert dumped["tortuosity"]["amplitude_deg"] == 1.0
    assert WellConfig.model_validate(dumped) == on


def test_random_is_reproducible_from_its_seed_and_bounded() -> None:
    def hole(seed: int, td_m: float = 900.0) -> object:
        return apply_tortuosity(straight(70.0, 0.0, td_m),
                                spec(model="random", amplitude_deg=1.0, seed=seed,
                                     md_start_m=50.0))

    a, b, c = hole(3), hole(3), hole(4)
    for name in ("md_m", "inc_rad", "azi_rad", "pos_m"):
        assert np.array_equal(getattr(a, name), getattr(b, name))
    assert not np.array_equal(a.inc_rad, c.inc_rad)
    # a deeper hole with the same seed has the same shallower tortuosity
    deep = hole(3, 1500.0)
    k = a.n - 1
    assert np.array_equal(deep.inc_rad[:k], a.inc_rad[:k])
    # linear tilts between draws in [-A, A] every P: a dogleg of at most 2 A / P
    assert a.max_dls_deg_per_30m <= 2.0 * math.radians(1.0) / 30.0 * DEG30 * (1 + 1e-9)
    d_h, d_r = tilt_rad(a.md_m, spec(model="random", amplitude_deg=1.0, seed=3,
                                     md_start_m=50.0))
    assert np.all(np.abs(d_h) <= math.radians(1.0)) and np.all(d_r == 0.0)
    assert np.all(d_h[a.md_m <= 50.0] == 0.0)


def test_tortuosity_index_of_closed_forms() -> None:
    """Straight hole: 0. Hold, a 90 deg arc, hold: three turns, the arc's arc/chord
    = (pi/4) / sin(pi/4). A sine wave cut at its extremes: per half wave the
    arc/chord excess is <delta^2>/2 = A^2/4 (small angles), per end quarter wave
    A^2 (1/4 - 2/pi^2); 2 N + 1 turns over N periods. The minimum-curvature path
    turns at a constant rate between stations h apart, so its tilt is the sine's
    piecewise-linear interpolant, whose mean square is smaller by (2 pi h / P)^2 / 6."""
    assert tortuosity_index_per_m(straight(30.0, 0.0, 500.0)) == 0.0
    cfg = WellConfig(profiles={"b": {"kind": "build_horizontal", "kop_m": 300.0,
                                     "dls_deg_per_30m": 6.0, "horizontal_length_m": 400.0}})
    sv = build_plan_survey(cfg)
    ratio = (math.pi / 4.0) / math.sin(math.pi / 4.0)
    assert tortuosity_index_per_m(sv) == pytest.approx(0.75 * (ratio - 1.0) / sv.md_m[-1],
                                                       rel=1e-9)
    a, p, n = math.radians(1.0), 30.0, 20
    sv = apply_tortuosity(straight(0.0, 0.0, n * p), spec(period_m=p))
    excess = (2 * n - 1) * a * a / 4.0 + 2 * a * a * (0.25 - 2.0 / math.pi ** 2)
    sampled = 1.0 - (2.0 * math.pi / 32.0) ** 2 / 6.0
    turns = 2 * n + 1
    # 0.1 %: the small-angle terms left out are of relative order A^2 ~ 3e-4, those of
    # the interpolant of order (2 pi h / P)^4 ~ 1e-3 / 20
    assert tortuosity_index_per_m(sv) == pytest.approx(
        turns / (turns + 1) * excess * sampled / (n * p), rel=1e-3)


def test_the_contact_wellbore_follows_the_tortuous_hole() -> None:
    cfg = WellConfig(tortuosity={"model": "sine", "amplitude_deg": 1.0, "period_m": 30.0,
                                 "md_start_m": 400.0})
    wb = build_wellbore(cfg)
    sv = build_survey(cfg)
    assert wb.survey.n == sv.n
    at = np.searchsorted(wb.node_md_m, sv.md_m)
    assert np.array_equal(wb.node_md_m[at], sv.md_m)  # every station is a node
    assert np.allclose(wb.node_pos_m[at], sv.pos_m, atol=1e-9)
    # the chain's curvature carries the micro-doglegs below the start, not above it
    mid = 0.5 * (wb.md0_m + wb.md1_m)
    k = np.asarray(wb.curvature_at_md(mid)) * DEG30
    plan_k = np.asarray(build_wellbore(WellConfig()).curvature_at_md(mid)) * DEG30
    assert np.allclose(k[mid < 390.0], plan_k[mid < 390.0], atol=1e-9)
    assert np.max(np.abs(k - plan_k)[mid > 400.0]) > 1.0


def test_surrogate_geometry_features_see_the_tortuous_hole() -> None:
    """The dataset's position columns (sweep.cases.position_columns) come from the case's
    hole: with tortuosity the windowed maximum dogleg in a straight part is the wave's."""
    base = {"well": {"profiles": {"v": {"kind": "vertical", "td_m": 800.0}}},
            "string": {"components": [{"type": "drill_pipe", "od_m": 0.127, "id_m": 0.1086,
                                       "length_m": 800.0, "n_segments": 10}]}}
    tort = {**base, "well": {**base["well"], "tortuosity": {
        "model": "sine", "amplitude_deg": 1.0, "period_m": 30.0, "md_start_m": 100.0}}}
    md = np.array([50.0, 300.0, 500.0])
    off = position_columns(case_from_dict(base).model_dump(mode="json"), md, np.full(3, 100.0))
    on = position_columns(case_from_dict(tort).model_dump(mode="json"), md, np.full(3, 100.0))
    assert np.all(off["local_max_dls_deg_per_30m"] == 0.0)
    peak = 2.0 * math.pi * math.radians(1.0) / 30.0 * DEG30
    assert on["local_max_dls_deg_per_30m"][0] == 0.0  # 50 m: more than the window above
    assert 50.0 + WINDOW_M < 100.0
    assert np.all(on["local_max_dls_deg_per_30m"][1:] >= SAMPLED_PEAK_LOW * peak)
    assert np.all(on["local_max_dls_deg_per_30m"][1:] <= peak * (1 + 1e-9))


def test_report_states_the_model_and_its_effect() -> None:
    """Below the end of profile_1's build (821 m) the plan is straight: the micro-doglegs
    raise the dogleg severity from 0 and add turns to the index."""
    cfg = WellConfig(tortuosity={"model": "sine", "amplitude_deg": 1.0, "period_m": 30.0,
                                 "md_start_m": 830.0})
    rep = profile_report(cfg)["profile_1"]["tortuosity"]
    assert rep["model"] == "sine" and rep["period_m"] == 30.0 and "seed" not in rep
    peak = 2 * math.pi * math.radians(1.0) / 30.0 * DEG30
    assert rep["peak_added_dls_deg_per_30m"] == pytest.approx(peak, rel=1e-12)
    assert rep["plan"]["max_dls_deg_per_30m"] == 0.0
    assert SAMPLED_PEAK_LOW * peak <= rep["tortuous"]["max_dls_deg_per_30m"] <= peak * 1.000001
    assert rep["tortuous"]["mean_dls_deg_per_30m"] == pytest.approx(
        4 * math.radians(1.0) / 30.0 * DEG30, rel=0.02)  # 191 m: 6.4 periods, not whole ones
    assert rep["tortuous"]["tortuosity_index_per_m"] > rep["plan"]["tortuosity_index_per_m"]
    same = tortuosity_report(build_plan_survey(cfg), build_plan_survey(cfg), None)
    assert same["plan"] == same["tortuous"] and "model" not in same


@pytest.mark.parametrize(("data", "field"), [
    ({"model": "sine", "amplitude_deg": 11.0, "period_m": 30.0}, "well.tortuosity.amplitude_deg"),
    ({"model": "sine", "amplitude_deg": -1.0, "period_m": 30.0}, "well.tortuosity.amplitude_deg"),
    ({"model": "sine", "amplitude_deg": 1.0, "period_m": 0.5}, "well.tortuosity.period_m"),
    ({"model": "sine", "amplitude_deg": 1.0, "period_m": 2000.0}, "well.tortuosity.period_m"),
    ({"model": "sine", "amplitude_deg": 10.0, "period_m": 30.0},
     "well.tortuosity.amplitude_deg"),  # 63 deg/30 m added
    ({"model": "spiral", "amplitude_deg": 1.0, "period_m": 30.0}, "well.tortuosity.model"),
    ({"model": "sine", "period_m": 30.0}, "well.tortuosity.amplitude_deg"),
    ({"model": "sine", "amplitude_deg": 1.0, "period_m": 30.0, "phase_deg": 3.0},
     "well.tortuosity.phase_deg"),
    ({"model": "sine", "amplitude_deg": 1.0, "period_m": 30.0, "md_start_m": -1.0},
     "well.tortuosity.md_start_m"),
])
def test_bad_tortuosity_is_a_one_line_input_error(data: dict, field: str) -> None:
    with pytest.raises(InputError) as exc:
        case_from_dict({"well": {"tortuosity": data}})
    assert exc.value.field == field
    assert "\n" not in str(exc.value)
    assert exc.value.allowed or exc.value.problem == "required key is missing"


def test_a_hole_turning_faster_than_the_profiles_allow_is_refused() -> None:
    cfg = WellConfig(profiles={"j": {"kind": "j", "kop_m": 100.0, "dls_deg_per_30m": 58.0,
                                     "inc_deg": 80.0, "td_m": 600.0}},
                     tortuosity={"model": "sine", "amplitude_deg": 1.0, "period_m": 30.0})
    with pytest.raises(InputError, match=r"well\.tortuosity\.amplitude_deg: the tortuous hole "
                                         r"turns at .* deg/30m"):
        build_survey(cfg)
