"""``drillfatigue query``: ask the surrogate for a damage rate, life, interval, OOD flag.

A condition outside the surrogate's domain (a design variable outside the
sweep's range, or far from every training condition) gets no number: a single
query exits with code 2 and the one-line error naming the variable and its
range; a batch writes the row with empty numbers and the reason. A predicted
life beyond the model's horizon (``surrogate.horizon_h``) is answered as
"longer than" the horizon.

Single query (flags built from the model's features, user units)::

    drillfatigue query --model data/surrogate/model --rpm 120 --wob-kN 80 \\
        --rop-m-per-h 20 ... [--json]

Batch::

    drillfatigue query --model data/surrogate/model --csv conditions.csv --out predictions.csv

With ``--well WELL.yaml`` (a params or case file, or the bare ``well``
section; ``--well-profile`` picks a profile) the model's hole-geometry
features (:mod:`drillfatigue.well.features`) are computed from that well's
survey at ``md_m`` and at the bit (``md_m + s_from_bit_m``) instead of being
given as flags or CSV columns.

Feature names and units: :mod:`drillfatigue.io.names`.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pandas as pd
import typer

from drillfatigue.cli.app import app
from drillfatigue.cli.twin import read_section
from drillfatigue.cli.vocabulary import PROFILE, model_option, out_option, profile_option
from drillfatigue.config import WellConfig
from drillfatigue.errors import InputError
from drillfatigue.files import check_output_file
from drillfatigue.io.names import Vocabulary, unseen_levels, vocabulary_name
from drillfatigue.io.tables import read_csv_file
from drillfatigue.well import build_survey

_CONTEXT = {"allow_extra_args": True, "ignore_unknown_options": True,
            "help_option_names": ["-h", "--help"]}


def parse_feature_flags(args: list[str]) -> dict[str, str]:
    """``['--wob-kN', '80', '--rpm=120']`` -> ``{'wob_kN': '80', 'rpm': '120'}``."""
    out: dict[str, str] = {}
    i = 0
    while i < len(args):
        tok = args[i]
        if not tok.startswith("--") or len(tok) < 3:
            raise InputError(tok, "unexpected argument", "--NAME VALUE feature flags")
        if "=" in tok:
            name, value = tok[2:].split("=", 1)
            i += 1
        else:
            if i + 1 >= len(args):
                raise InputError(tok, "flag without a value", "--NAME VALUE")
            name, value = tok[2:], args[i + 1]
            i += 2
        key = name.replace("-", "_")
        if key in out:
            raise InputError(tok, "given twice", "each flag once")
        out[key] = value
    return out


def _load_model(model: Path):  # noqa: ANN202
    from drillfatigue.surrogate import Surrogate  # optional extra [surrogate]: torch

    if not model.is_dir():
        raise InputError("--model", f"folder {str(model)!r} not found",
                         "a model folder written by the train stage")
    return Surrogate.load(model)


def _finite(v: float) -> float | None:
    return v if math.isfinite(v) else None


def _shown(v: float | None) -> str:
    return "inf" if v is None else f"{v:.3g}"


def _geometry_from_well(sur, well: Path, profile: str | None):  # noqa: ANN001, ANN202
    """(geometry columns the model uses, the well's survey) for ``--well``."""
    from drillfatigue.well.features import POSITION_COLUMNS  # start-up: scipy.ndimage, ~0.1 s

    cols = tuple(c for c in sur.features if c in POSITION_COLUMNS)
    for c in ("md_m", "s_from_bit_m"):
        if c not in sur.features:
            raise InputError("--well", f"the model has no {c} feature to place the location",
                             "a model with md_m and s_from_bit_m features")
    cfg = read_section(well, "well", "--well", WellConfig)
    if profile is not None and profile not in cfg.profiles:
        raise InputError(PROFILE, f"unknown profile {profile!r}",
                         ", ".join(sorted(cfg.profiles)))
    return cols, build_survey(cfg, profile)


def _add_geometry(frame, vocab, cols, survey):  # noqa: ANN001, ANN202
    """``frame`` (SI columns) with the geometry columns from the survey."""
    from drillfatigue.well.features import survey_features  # start-up: scipy.ndimage, ~0.1 s

    for c in cols:
        if c in frame.columns:
            raise InputError(vocab.names_for(c)[0], "given together with --well",
                             "either the value or --well")
    md = frame["md_m"].to_numpy(dtype=float)
    bit = md + frame["s_from_bit_m"].to_numpy(dtype=float)
    td_m = float(survey.md_m[-1])
    for name, values in (("md_m", md), ("md_m + s_from_bit_m (the bit)", bit)):
        if np.any(values > td_m):
            i = int(np.argmax(values > td_m))
            row = f" (row {i + 1})" if values.size > 1 else ""
            raise InputError(name, f"{values[i]:.6g} m is beyond the well's total depth "
                             f"{td_m:.6g} m{row}", f"<= {td_m:.6g} m, the TD of --well")
    return frame.assign(**survey_features(survey, md,
                                          md + frame["s_from_bit_m"].to_numpy(dtype=float), cols))


@app.command("query", context_settings=_CONTEXT)
def query(ctx: typer.Context,
          model: Path = model_option(...),
          csv: Path | None = typer.Option(None, "--csv", help="batch: conditions CSV "
                                          "(columns named like the flags, with _)"),
          out: Path | None = out_option(None, help="batch: predictions CSV to write"),
          as_json: bool = typer.Option(False, "--json", help="print JSON"),
          well: Path | None = typer.Option(None, "--well", help="well YAML: derive the hole-"
                                           "geometry features at md_m and the bit from it"),
          well_profile: str | None = profile_option(help="profile of --well (default: its "
                                                    "active profile)")) -> None:
    """Damage rate per hour, life in hours, the calibrated interval and the OOD flag.

    Feature flags come from the model (e.g. --rpm, --wob-kN, --rop-m-per-h,
    --component-type); run with a model and no flags to list them.
    """
    from drillfatigue.surrogate.facade import prediction_frame  # optional extra [surrogate]: torch
    from drillfatigue.surrogate.io import write_csv  # optional extra [surrogate]: torch

    flags = parse_feature_flags(list(ctx.args))
    if csv is not None and flags:
        raise InputError(next(iter(flags)), "feature flags cannot be combined with --csv",
                         "either --csv FILE --out FILE or feature flags")
    if csv is None and out is not None:
        raise InputError("--out", "only used with --csv", "--csv FILE --out FILE")
    if csv is not None and out is None:
        raise InputError("--out", "missing", "--csv FILE --out FILE")
    if csv is not None and not csv.is_file():
        raise InputError("--csv", f"file {str(csv)!r} not found", "an existing CSV file")
    if out is not None:
        check_output_file(out, "--out", [("--csv", csv), ("--model", model), ("--well", well)])
        if out.suffix.lower() != ".csv":  # the predictions are written as CSV text
            raise InputError("--out", f"{str(out)!r} is not a .csv file", "FILE.csv")
    if well is None and well_profile is not None:
        raise InputError(PROFILE, "only used with --well", "--well FILE")
    sur = _load_model(model)
    vocab = Vocabulary(sur.features, sur.categorical)
    geometry = _geometry_from_well(sur, well, well_profile) if well is not None else None
    need = [c for c in sur.features + sur.categorical
            if geometry is None or c not in geometry[0]]
    if csv is not None:
        # an empty cell, a ragged row or a column named twice: refused, naming the row
        table = read_csv_file(csv)
        if len(table) == 0:
            raise InputError(str(csv), "no rows", ">= 1 condition row")
        # field-style headers ('WOB (klbf)', 'ROP (ft/h)') to vocabulary names
        table = table.rename(columns={c: vocabulary_name(str(c), vocab) for c in table.columns})
        frame = vocab.frame_from_table(table, require=need)
        if geometry is not None:
            frame = _add_geometry(frame, vocab, *geometry)
            table = table.assign(**{c: frame[c].to_numpy() for c in geometry[0]})
        # a level the model never saw (a bit, a motor) is that row's "no answer", not the batch's
        cats = {c: frame[c].tolist() for c in sur.categorical if c in frame.columns}
        unseen, why = unseen_levels(cats, sur.categories)
        if unseen.any():
            frame = frame.copy()
            for c in cats:
                frame.loc[unseen, c] = sur.categories[c][0]
        pred = sur.predict(frame)
        if unseen.any():
            numbers = [c for c in pred.columns if c not in ("ood", "ood_reason",
                                                            "beyond_horizon")]
            pred.loc[unseen, numbers] = np.nan
            pred.loc[unseen, "beyond_horizon"] = False
            pred.loc[unseen, "ood"] = True
            pred.loc[unseen, "ood_reason"] = why[unseen]
        result = pd.concat([table.reset_index(drop=True), pred.reset_index(drop=True)], axis=1)
        write_csv(result, out)
        n_ood = int(pred["ood"].sum())
        print(f"wrote {len(result)} predictions to {out} ({n_ood} out of domain: refused, "
              "no number)")
        return
    frame = vocab.frame_from_mapping(flags, require=need)
    if geometry is not None:
        frame = _add_geometry(frame, vocab, *geometry)
    x_num, x_cat = sur.encode(frame)
    r = sur.predict_array(x_num, x_cat)
    if r["ood"][0]:
        raise sur.domain.refusal(x_num[0], float(r["knn_distance"][0]), cat_row=x_cat[0])
    row = prediction_frame(r, np.full(1, "", dtype=object)).iloc[0]
    horizon = sur.horizon_h
    res = {
        "criterion": sur.metadata["criterion"],
        "coverage": sur.coverage,
        "damage_rate_per_h": float(row["damage_rate_per_h"]),
        "damage_rate_per_h_interval": [float(row["damage_rate_per_h_lower"]),
                                       float(row["damage_rate_per_h_upper"])],
        "life_h": _finite(float(row["life_h"])),
        "life_h_interval": [_finite(float(row["life_h_lower"])),
                            _finite(float(row["life_h_upper"]))],
        "log10_damage_rate_per_h": float(row["log10_damage_rate_per_h"]),
        "horizon_h": horizon,
        "beyond_horizon": bool(row["beyond_horizon"]),
        "out_of_domain": bool(row["ood"]),
        "ood_reason": str(row["ood_reason"]),
        "inputs_si": {c: (float(frame[c].iloc[0]) if c in sur.features else str(frame[c].iloc[0]))
                      for c in sur.features + sur.categorical},
    }
    if as_json:
        print(json.dumps(res, indent=2))
        return
    pct = round(100 * sur.coverage)
    lo, hi = res["damage_rate_per_h_interval"]
    print(f"damage rate ({res['criterion']}): {res['damage_rate_per_h']:.4g} per h "
          f"({pct} % interval {lo:.3g} .. {hi:.3g})")
    llo, lhi = res["life_h_interval"]
    if res["beyond_horizon"]:
        print(f"life: longer than the horizon {horizon:.4g} h (lives beyond it are "
              "trained as censored, not as numbers)")
    else:
        print(f"life: {res['life_h']:.4g} h ({pct} % interval {llo:.3g} .. "
              f"{_shown(lhi)} h)")
    print("in the training domain")
