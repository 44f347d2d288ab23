"""Invariants of hole tortuosity (drillfatigue.well.tortuosity) on plans in a vertical plane.

- The hole keeps the plan's stations and measured depth; above the start it is the plan.
- At every station the hole's direction lies within the stated tilt of the plan's
  (``amplitude``, times sqrt 2 for ``both``).
- It never turns faster than the plan's largest dogleg severity plus the peak the
  tortuosity adds (``TortuosityConfig.peak_added_dls_deg_per_30m``): the tilted
  tangent turns at most at the plan's rate plus the tilt's own rate (the tilt is an
  exponential map of the sphere, whose derivative never lengthens a step), and a
  minimum-curvature interval's dogleg is at most the turn along it. For a plan in a
  vertical plane the plan's frame turns at the plan's curvature only.
"""

from __future__ import annotations

import math

import numpy as np
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from drillfatigue.config import WellConfig
from drillfatigue.config.well import TortuosityConfig
from drillfatigue.errors import InputError
from drillfatigue.well import apply_tortuosity, build_plan_survey, build_wellbore
from drillfatigue.well.survey import dogleg_rad

# legs of zero or at least a metre: a leg of a denormal length makes a zero-length interval
# in the profile builder, which is not what is tested here
kops = st.one_of(st.just(0.0), st.floats(1.0, 400.0))
profiles = st.one_of(
    # the hold after the build at least 1 m long: a td_m equal to the build's end to
    # rounding is refused by the profile builder, which is not what is tested here
    st.builds(lambda kop, dls, inc, azi, hold: {
        "kind": "j", "kop_m": kop, "dls_deg_per_30m": dls, "inc_deg": inc, "azi_deg": azi,
        "td_m": kop + inc / dls * 30.0 + hold},
              kops, st.floats(1.0, 15.0), st.floats(5.0, 95.0),
              st.floats(0.0, 359.0), st.floats(1.0, 600.0)),
    st.builds(lambda kop, dls, azi, hl: {"kind": "build_horizontal", "kop_m": kop,
                                         "dls_deg_per_30m": dls, "azi_deg": azi,
                                         "horizontal_length_m": hl},
              kops, st.floats(2.0, 15.0), st.floats(0.0, 359.0),
              st.floats(1.0, 400.0)),
    st.builds(lambda kop, td: {"kind": "vertical", "td_m": td}, st.just(0.0),
              st.floats(50.0, 1200.0)),
)
specs = st.builds(
    lambda model, amp, period, start, direction, seed, per: {
        "model": model, "amplitude_deg": amp, "period_m": period, "md_start_m": start,
        "direction": direction, "seed": seed, "stations_per_period": per},
    st.sampled_from(["sine", "random"]), st.floats(0.0, 4.0), st.floats(5.0, 200.0),
    st.floats(0.0, 1200.0), st.sampled_from(["inclination", "azimuth", "both"]),
    st.integers(0, 2**32 - 1), st.sampled_from([8, 16, 32]))


@settings(max_examples=60, deadline=None)
@given(profiles, specs)
def test_tortuous_hole_stays_within_its_stated_tilt_and_turn(profile: dict, spec: dict) -> None:
    try:
        tort = TortuosityConfig(**spec)
    except ValueError:
        assume(False)  # a peak added dogleg above the profiles' limit: refused, tested apart
    cfg = WellConfig(profiles={"p": profile})
    plan = build_plan_survey(cfg)
    try:
        sv = apply_tortuosity(plan, tort)
    except InputError:
        assume(False)  # plan and tortuosity together beyond 60 deg/30 m
    # stations and measured depth kept; above the start, the plan bit for bit
    assert sv.md_m[0] == plan.md_m[0] and sv.md_m[-1] == plan.md_m[-1]
    assert np.all(np.isin(plan.md_m, sv.md_m)) and np.all(np.diff(sv.md_m) > 0.0)
    k = int(np.searchsorted(plan.md_m, tort.md_start_m, side="right"))
    assert np.array_equal(sv.pos_m[:k], plan.pos_m[:k])
    # the direction within the tilt of the plan's
    _, t_plan = build_wellbore(cfg, survey=plan).point_at_md(sv.md_m)
    tilt = dogleg_rad(sv.tangent, t_plan)
    largest = math.radians(tort.amplitude_deg) * (math.sqrt(2.0) if tort.direction == "both"
                                                  else 1.0)
    assert np.all(tilt <= largest * (1.0 + 1e-9) + 1e-12)
    # never turning faster than the plan plus the tortuosity's peak
    bound = plan.max_dls_deg_per_30m + tort.peak_added_dls_deg_per_30m
    assert sv.max_dls_deg_per_30m <= bound * (1.0 + 1e-9) + 1e-9
    # the same hole again from the same inputs
    again = apply_tortuosity(plan, tort)
    assert np.array_equal(again.pos_m, sv.pos_m)
