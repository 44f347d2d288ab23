"""The one place the ledger calls the digital twin.

:func:`twin_increments` has the signature of every damage function
(:data:`drillfatigue.ledger.increments.DamageFunction`): a stretch of a run's
log (SI table of :func:`drillfatigue.io.logs.load_log`, absolute ``time_s``)
and the run's context in, one row per (serial, location) out with
``covered``, ``not_covered_reason``, ``damage``, ``damage_lower``,
``damage_upper`` and ``ood_time_s``. It calls
:func:`drillfatigue.surrogate.twin.replay_log` on the items the model covers.

Coverage: an item whose component type or location is not a level of the
model's categories is listed as not covered, with that reason. A twin that
reports coverage itself (``covered`` and ``not_covered_reason`` columns in
its result, ``damage`` NaN or absent for items it does not cover) is
followed as it reports.
"""

from __future__ import annotations

import hashlib
from functools import lru_cache
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

from drillfatigue.errors import InputError
from drillfatigue.ledger.increments import RunContext

#: A run's model given as an importable damage function instead of a model folder.
PYTHON_PREFIX = "python:"


def model_id(model_ref: str) -> str:
    """Identity of a run's model: the SHA-256 of the folder's ``metadata.json``
    (16 hex digits), or the ``python:MODULE:FUNCTION`` reference itself."""
    if model_ref.startswith(PYTHON_PREFIX):
        return model_ref[:64]
    meta = Path(model_ref) / "metadata.json"
    if not meta.is_file():
        raise InputError("--model", f"{model_ref!r} is not a surrogate model folder",
                         "a folder written by the train stage (with metadata.json)")
    return hashlib.sha256(meta.read_bytes()).hexdigest()[:16]


@lru_cache(maxsize=4)
def _load_model(path: str, ident: str) -> Any:
    # optional extra [surrogate]: torch; loaded once per process and model
    from drillfatigue.surrogate import Surrogate

    return Surrogate.load(path)


def twin_increments(log: pd.DataFrame, context: RunContext) -> pd.DataFrame:
    """Per (serial, location) damage increments of ``log`` from the digital twin.

    Parameters
    ----------
    log : DataFrame
        ``time_s`` (s), ``bit_md_m`` (m) and the surface channels in SI, >= 2 rows.
    context : RunContext
        The run: items from the bit up, model folder, constants, survey.

    Returns
    -------
    DataFrame
        ``serial``, ``location``, ``covered``, ``not_covered_reason``,
        ``damage``, ``damage_lower``, ``damage_upper`` (Miner sums over the
        log's intervals; NaN where not covered) and ``ood_time_s``.
    """
    # optional extra [surrogate]: torch
    from drillfatigue.surrogate.twin import replay_log

    model = _load_model(context.model_ref, model_id(context.model_ref))
    loc = context.locations()
    levels = model.categories
    reason = pd.Series([None] * len(loc), dtype=object)
    for col in ("component_type", "location"):
        if col in levels:
            bad = ~loc[col].astype(str).isin([str(v) for v in levels[col]])
            reason[bad & reason.isna()] = [
                f"{col} {v!r} is not in the model's training data ({', '.join(map(str, levels[col]))})"
                for v in loc.loc[bad & reason.isna(), col]]
    covered = reason.isna().to_numpy()
    out = pd.DataFrame({"serial": loc["serial"].to_numpy(), "location": loc["location"].to_numpy(),
                        "covered": covered, "not_covered_reason": reason.to_numpy(),
                        "damage": np.nan, "damage_lower": np.nan, "damage_upper": np.nan,
                        "ood_time_s": 0.0})
    if not covered.any():
        return out
    # the twin wants unique serials: one key per tracked row, mapped back below
    comps = pd.DataFrame({"serial": [f"k{i}" for i in np.flatnonzero(covered)],
                          "component_type": loc.loc[covered, "component_type"].to_numpy(),
                          "location": loc.loc[covered, "location"].to_numpy(),
                          "s_from_bit_m": loc.loc[covered, "s_from_bit_m"].to_numpy()})
    res = replay_log(log.reset_index(drop=True), comps, model, dict(context.constants),
                     context.survey).components
    idx = np.array([int(str(k)[1:]) for k in res["serial"]])
    if "covered" in res.columns:
        cov = res["covered"].astype(bool).to_numpy()
        out.loc[idx[~cov], "covered"] = False
        out.loc[idx[~cov], "not_covered_reason"] = (
            res.loc[~cov, "not_covered_reason"].to_numpy() if "not_covered_reason" in res.columns
            else "not covered by the model")
    for col in ("damage", "damage_lower", "damage_upper", "ood_time_s"):
        if col in res.columns:
            out.loc[idx, col] = pd.to_numeric(res[col], errors="coerce").to_numpy()
    out.loc[~out["covered"].astype(bool), ["damage", "damage_lower", "damage_upper"]] = np.nan
    return out
