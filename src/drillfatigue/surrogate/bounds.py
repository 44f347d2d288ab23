"""The domain a surrogate answers: ranges from the sweep's design, not from its rows.

A surrogate trained on a sweep knows the conditions that sweep could draw.
:func:`domain_bounds` turns ``params.yaml`` into a (low, high) range per
numeric feature:

- a design variable (``sweep.variables`` with ``low``/``high``, e.g.
  ``operation.rpm``) takes its design range;
- the location features follow from the design: ``s_from_bit_m`` spans the
  string's locations (the training rows' distances: the string is fixed by
  params, not drawn), ``md_m`` = bit MD - distance from the bit, so [bit low
  - largest distance, bit high - smallest distance], and
  the hole geometry (:data:`drillfatigue.well.features.POSITION_COLUMNS`) is
  computed from each designed profile's survey at every location for bit
  depths on a 1 m grid across the bit-depth range (or the fixed bit depth);
- any other feature is left out (the domain test bounds it by the training
  rows).

The training rows' own min/max would refuse conditions the design covers but
a few dozen cases happened to miss (a bit inclination just beyond the rows')
and accept nothing the design does not.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

from drillfatigue.well import build_survey
from drillfatigue.well.features import POSITION_COLUMNS, survey_features

_BIT_GRID_M = 1.0


def design_bounds(variables: dict[str, Any], features: Sequence[str]
                  ) -> dict[str, tuple[float, float]]:
    """(low, high) of each numeric design variable of ``sweep.variables`` that is a feature.

    ``variables``: name -> an object (or mapping) with ``low``/``high`` (a
    numeric variable) or ``choices`` (categorical: skipped, unseen levels are
    rejected by the encoder).
    """
    out: dict[str, tuple[float, float]] = {}
    for name, spec in variables.items():
        get = spec.get if isinstance(spec, dict) else (lambda k, sp=spec: getattr(sp, k, None))
        lo, hi = get("low"), get("high")
        if name in features and lo is not None and hi is not None:
            out[name] = (float(lo), float(hi))
    return out


def _spec(variables: dict[str, Any], name: str, key: str) -> Any:
    spec = variables.get(name)
    if spec is None:
        return None
    return spec.get(key) if isinstance(spec, dict) else getattr(spec, key, None)


def domain_bounds(params: Any, features: Sequence[str],
                  s_from_bit_m: np.ndarray) -> dict[str, tuple[float, float]]:
    """Design ranges of the features (see the module docstring).

    Parameters
    ----------
    params : Params
        The whole ``params.yaml`` (``sweep``, ``operation``, ``well``).
    features : sequence of str
        The model's numeric features.
    s_from_bit_m : ndarray
        Distances from the bit of the string's locations (the training rows'), m.
    """
    variables = dict(params.sweep.variables)
    out = design_bounds(variables, features)
    s = np.unique(np.asarray(s_from_bit_m, dtype=np.float64))
    lo, hi = _spec(variables, "operation.bit_md_m", "low"), _spec(
        variables, "operation.bit_md_m", "high")
    if lo is None or hi is None:
        lo = hi = float(params.operation.bit_md_m)
    if "md_m" in features and s.size:
        out["md_m"] = (float(lo) - float(s.max()), float(hi) - float(s.min()))
    if "s_from_bit_m" in features and s.size:
        out["s_from_bit_m"] = (float(s.min()), float(s.max()))
    geo = tuple(c for c in POSITION_COLUMNS if c in features)
    if not geo or not s.size:
        return out
    profiles = _spec(variables, "well.profile", "choices") or [params.well.profile]
    bits = np.linspace(float(lo), float(hi), max(2, int((hi - lo) / _BIT_GRID_M) + 1))
    bit = np.repeat(bits, s.size)
    md = bit - np.tile(s, bits.size)
    keep = md >= 0.0
    lows = {c: np.inf for c in geo}
    highs = {c: -np.inf for c in geo}
    for name in profiles:
        f = survey_features(build_survey(params.well, str(name)), md[keep], bit[keep], geo)
        for c in geo:
            lows[c] = min(lows[c], float(np.min(f[c])))
            highs[c] = max(highs[c], float(np.max(f[c])))
    out.update({c: (lows[c], highs[c]) for c in geo})
    return out
