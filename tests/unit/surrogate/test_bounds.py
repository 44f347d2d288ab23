"""The surrogate's domain from the sweep's design (params.yaml), not its rows."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from drillfatigue.config import load_params
from drillfatigue.surrogate.bounds import domain_bounds
from drillfatigue.well import build_survey
from drillfatigue.well.features import survey_features

PARAMS = Path(__file__).resolve().parents[3] / "params.yaml"


def test_domain_bounds_follow_the_design() -> None:
    params = load_params(PARAMS)
    feats = params.surrogate.features
    s = np.array([5.0, 35.0, 300.0])
    b = domain_bounds(params, feats, s)
    v = params.sweep.variables
    assert b["operation.rpm"] == (v["operation.rpm"].low, v["operation.rpm"].high)
    bit_lo, bit_hi = v["operation.bit_md_m"].low, v["operation.bit_md_m"].high
    assert b["md_m"] == (bit_lo - 300.0, bit_hi - 5.0)
    assert b["s_from_bit_m"] == (5.0, 300.0)  # the string's locations
    # any designed condition (profile, bit depth, location) lies inside: sampled
    # apart from the 1 m grid the bounds were built on
    rng = np.random.default_rng(0)
    geo = ("local_dls_deg_per_30m", "local_inc_deg", "bit_inc_deg", "build_to_bit_deg_per_30m")
    for name in v["well.profile"].choices:
        survey = build_survey(params.well, name)
        bit = rng.uniform(bit_lo, bit_hi, 50)
        md = bit - rng.choice(s, 50)
        f = survey_features(survey, md, bit, geo)
        for c in geo:
            # the grid's 1 m spacing can miss a peak between nodes by the change of
            # the feature over 1 m: 0.5 deg (inclination) or deg/30 m here
            assert np.all(f[c] >= b[c][0] - 0.5) and np.all(f[c] <= b[c][1] + 0.5), c
    assert 0.0 <= b["local_inc_deg"][0] < b["local_inc_deg"][1] <= 90.0
