"""What a damage function receives and returns, and the exposure the ledger counts itself.

A **damage function** turns one stretch of a run's log into per (serial,
location) increments. The ledger calls it with the log rows of a chunk that
are new, preceded by the run's last ingested sample when there is one, so
each interval between consecutive samples is counted exactly once over the
whole run, under the twin's piecewise-constant rule (the values of the row
that starts an interval hold until the next row): the last row only closes
the interval before it. The production damage function is the digital twin
(:func:`drillfatigue.ledger.twin_adapter.twin_increments`); tests and the
benchmark use :func:`drillfatigue.ledger.standin.standin_increments`.

Positions: a joint of a run occupies ``[s_bottom_m, s_top_m]`` from the bit;
its body is tracked at the middle, its connection at the top (the joint's
pin/box pair with the next joint up). A location is in the hole while
``bit_md_m - s_from_bit_m >= 0``, the twin's rule.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass, field

import numpy as np
import pandas as pd

from drillfatigue.errors import InputError

#: Locations the ledger tracks per joint and where along the joint they sit.
LOCATIONS: tuple[str, ...] = ("body", "connection")

#: Columns a damage function returns (one row per tracked serial x location).
INCREMENT_COLUMNS: tuple[str, ...] = ("serial", "location", "covered", "not_covered_reason",
                                      "damage", "damage_lower", "damage_upper", "ood_time_s")

_MINUTE_S = 60.0


@dataclass(frozen=True)
class RunContext:
    """A run as a damage function sees it.

    Attributes
    ----------
    run : str
        Run name.
    items : DataFrame
        One row per joint, from the bit up: ``serial``, ``component_type``,
        ``position`` (1 at the bit), ``length_m``, ``s_bottom_m``,
        ``s_top_m``, ``od_m``, ``id_m``, ``grade`` (None where unknown).
    model_ref : str
        The run's model: a surrogate model folder, or ``python:MODULE:FUNCTION``.
    constants : mapping
        ``{user name: value text}`` given with ``--set`` when the run started.
    survey : DataFrame or None
        ``md_m``, ``inc_deg``, ``dls_deg_per_30m`` of the run's well.
    """

    run: str
    items: pd.DataFrame
    model_ref: str
    constants: Mapping[str, str] = field(default_factory=dict)
    survey: pd.DataFrame | None = None

    def locations(self) -> pd.DataFrame:
        """One row per tracked serial x location: the item columns plus
        ``location`` and ``s_from_bit_m`` (body: mid-joint, connection: top)."""
        rows = []
        for loc in LOCATIONS:
            part = self.items.copy()
            part["location"] = loc
            part["s_from_bit_m"] = (0.5 * (part["s_bottom_m"] + part["s_top_m"]) if loc == "body"
                                    else part["s_top_m"])
            rows.append(part)
        out = pd.concat(rows, ignore_index=True)
        return out.sort_values(["position", "location"], kind="stable").reset_index(drop=True)


#: The adapter's signature: ``f(log, context) -> DataFrame`` of :data:`INCREMENT_COLUMNS`.
DamageFunction = Callable[[pd.DataFrame, RunContext], pd.DataFrame]


def rpm_of(log: pd.DataFrame, constants: Mapping[str, str]) -> np.ndarray:
    """Surface rotary speed per row, rev/min: the log's ``rpm`` or the run's constant."""
    if "rpm" in log.columns:
        v = pd.to_numeric(log["rpm"], errors="coerce").to_numpy(dtype=np.float64)
    elif "rpm" in constants:
        try:
            v = np.full(len(log), float(constants["rpm"]))
        except ValueError:
            raise InputError("rpm", f"not a number: {constants['rpm']!r}", "rev/min >= 0") from None
    else:
        raise InputError("rpm", "no rotary speed in the log nor in the run's constants",
                         "an RPM channel, or --set rpm=VALUE when the run starts")
    if not np.all(np.isfinite(v)) or np.any(v < 0):
        raise InputError("rpm", "negative, NaN or non-numeric value", "rev/min >= 0")
    return v


def exposure(log: pd.DataFrame, locations: pd.DataFrame,
             constants: Mapping[str, str]) -> pd.DataFrame:
    """Time in hole and revolutions per tracked location over the log's intervals.

    Parameters
    ----------
    log : DataFrame
        ``time_s`` and ``bit_md_m`` (m) in SI, ``rpm`` (rev/min) unless a constant.
    locations : DataFrame
        ``serial``, ``location``, ``s_from_bit_m`` (m), as
        :meth:`RunContext.locations`.

    Returns
    -------
    DataFrame
        ``serial``, ``location``, ``time_in_hole_s`` and ``revolutions``:
        sums over intervals ``i`` of ``dt_i`` and ``rpm_i / 60 * dt_i`` where
        the location is in the hole at row ``i`` (previous value held).
    """
    t = log["time_s"].to_numpy(dtype=np.float64)
    bit = log["bit_md_m"].to_numpy(dtype=np.float64)
    rpm = rpm_of(log, constants)
    dt = np.diff(t)
    s = locations["s_from_bit_m"].to_numpy(dtype=np.float64)
    in_hole = (bit[:-1, None] - s[None, :]) >= 0.0      # (n_intervals, n_locations)
    hole_s = (dt[:, None] * in_hole).sum(axis=0)
    revs = ((rpm[:-1] / _MINUTE_S * dt)[:, None] * in_hole).sum(axis=0)
    return pd.DataFrame({"serial": locations["serial"].to_numpy(),
                         "location": locations["location"].to_numpy(),
                         "time_in_hole_s": hole_s, "revolutions": revs})


def check_increments(frame: pd.DataFrame, locations: pd.DataFrame, source: str) -> pd.DataFrame:
    """Validate a damage function's answer against the tracked locations.

    Every tracked (serial, location) must appear exactly once; a covered row
    needs finite damage with ``0 <= lower <= damage <= upper``; a row not
    covered needs a reason (its damage is ignored). Returns the rows in the
    order of ``locations``.
    """
    missing = [c for c in INCREMENT_COLUMNS if c not in frame.columns
               and c not in ("covered", "not_covered_reason")]
    if missing:
        raise RuntimeError(f"{source}: damage function returned no column {missing[0]!r}")
    out = frame.copy()
    if "covered" not in out.columns:
        out["covered"] = np.isfinite(pd.to_numeric(out["damage"], errors="coerce"))
    if "not_covered_reason" not in out.columns:
        out["not_covered_reason"] = None
    out["covered"] = out["covered"].astype(bool)
    key = out["serial"].astype(str) + "\x00" + out["location"].astype(str)
    if key.duplicated().any():
        raise RuntimeError(f"{source}: damage function returned a serial x location twice")
    want = locations["serial"].astype(str) + "\x00" + locations["location"].astype(str)
    out.index = key.to_numpy()
    if not set(want).issubset(out.index):
        lost = sorted(set(want) - set(out.index))[0].replace("\x00", " ")
        raise RuntimeError(f"{source}: damage function returned nothing for {lost}")
    out = out.loc[want.to_numpy()].reset_index(drop=True)
    cov = out["covered"].to_numpy()
    for col in ("damage", "damage_lower", "damage_upper", "ood_time_s"):
        out[col] = pd.to_numeric(out[col], errors="coerce").astype(np.float64)
    d, lo, hi = (out[c].to_numpy() for c in ("damage", "damage_lower", "damage_upper"))
    good = np.isfinite(d) & np.isfinite(lo) & np.isfinite(hi) & (lo >= 0) & (lo <= d) & (d <= hi)
    if np.any(cov & ~good):
        i = int(np.argmax(cov & ~good))
        raise RuntimeError(f"{source}: damage of {out['serial'].iloc[i]} {out['location'].iloc[i]}"
                           f" not finite with 0 <= lower <= damage <= upper "
                           f"({lo[i]!r}, {d[i]!r}, {hi[i]!r})")
    reasons = out["not_covered_reason"]
    if np.any(~cov & (reasons.isna() | (reasons.astype(str).str.strip() == "")).to_numpy()):
        raise RuntimeError(f"{source}: an item not covered without a reason")
    out.loc[~cov, ["damage", "damage_lower", "damage_upper"]] = np.nan
    out.loc[cov, "not_covered_reason"] = None
    out["ood_time_s"] = out["ood_time_s"].fillna(0.0)
    return out
