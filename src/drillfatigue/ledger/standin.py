"""A deterministic stand-in damage function: rate = f(rpm, WOB) per item, no model.

For the ledger's tests, its benchmark and trying the commands without a
trained surrogate (``drillfatigue ledger run start ... --damage-function
drillfatigue.ledger.standin:standin_increments``). It is not a fatigue model:
its numbers only exercise the bookkeeping. It follows the twin's rules
(:mod:`drillfatigue.ledger.increments`): a location accumulates while in the
hole, each interval at the values of the row that starts it::

    rate_per_h = BASE[type] * (rpm / 100)**2 * (1 + wob_N / 100 kN) * LOC[location]
    lower = rate / 2,  upper = 2 * rate

Time at more than 200 rpm is counted as out of the model's domain, and bits
are listed as not covered, like a model that does not know them.
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from drillfatigue import units
from drillfatigue.ledger.increments import RunContext, rpm_of

#: damage rate per hour at 100 rpm and no WOB, by component type
BASE_RATE_PER_H: dict[str, float] = {"drill_pipe": 2e-5, "hwdp": 1e-5, "collar": 5e-6,
                                      "stabilizer": 5e-6, "sub": 5e-6}
LOCATION_FACTOR: dict[str, float] = {"body": 1.0, "connection": 3.0}
WOB_SCALE_N = 100e3
OOD_RPM = 200.0
NOT_COVERED = {"bit": "the stand-in has no bit model"}


def standin_increments(log: pd.DataFrame, context: RunContext) -> pd.DataFrame:
    """Per (serial, location) increments over ``log`` (see the module docstring)."""
    loc = context.locations()
    t = log["time_s"].to_numpy(dtype=np.float64)
    bit = log["bit_md_m"].to_numpy(dtype=np.float64)
    rpm = rpm_of(log, context.constants)[:-1]
    wob = (log["wob_N"].to_numpy(dtype=np.float64)[:-1] if "wob_N" in log.columns
           else np.zeros(t.size - 1))
    dt_h = np.diff(t) / units.HOUR_S
    s = loc["s_from_bit_m"].to_numpy(dtype=np.float64)
    in_hole = (bit[:-1, None] - s[None, :]) >= 0.0
    types = loc["component_type"].astype(str).to_numpy()
    base = np.array([BASE_RATE_PER_H.get(ct, 1e-5) for ct in types])
    fac = np.array([LOCATION_FACTOR.get(str(x), 1.0) for x in loc["location"]])
    cond = (rpm / 100.0) ** 2 * (1.0 + wob / WOB_SCALE_N) * dt_h      # (n_intervals,)
    weight = (cond[:, None] * in_hole).sum(axis=0)
    damage = base * fac * weight
    ood_s = ((np.diff(t) * (rpm > OOD_RPM))[:, None] * in_hole).sum(axis=0)
    covered = np.array([ct not in NOT_COVERED for ct in types])
    return pd.DataFrame({
        "serial": loc["serial"].to_numpy(), "location": loc["location"].to_numpy(),
        "covered": covered,
        "not_covered_reason": [None if c else NOT_COVERED[ct] for c, ct in zip(covered, types, strict=True)],
        "damage": np.where(covered, damage, np.nan),
        "damage_lower": np.where(covered, 0.5 * damage, np.nan),
        "damage_upper": np.where(covered, 2.0 * damage, np.nan),
        "ood_time_s": ood_s})
