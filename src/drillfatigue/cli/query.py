"""``drillfatigue query``: ask the surrogate for a damage rate, life, interval, OOD flag.

Single query (flags built from the model's features, user units)::

    drillfatigue query --model models/surrogate --rpm 120 --wob-kN 80 \\
        --rop-m-per-h 20 ... [--json]

Batch::

    drillfatigue query --model models/surrogate --csv conditions.csv --out predictions.csv

Feature names and units: :mod:`drillfatigue.surrogate.query`.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import typer

from drillfatigue.cli.app import app
from drillfatigue.errors import InputError

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


def _load_model(model: Path):  # noqa: ANN202 (lazy import keeps CLI start fast)
    from drillfatigue.surrogate import Surrogate

    if not model.is_dir():
        raise InputError("--model", f"folder {str(model)!r} not found",
                         "a model folder written by the train stage")
    return Surrogate.load(model)


def _finite(v: float) -> float | None:
    return v if math.isfinite(v) else None


@app.command("query", context_settings=_CONTEXT)
def query(ctx: typer.Context,
          model: Path = typer.Option(..., "--model", help="surrogate model folder"),
          csv: Path | None = typer.Option(None, "--csv", help="batch: conditions CSV "
                                          "(columns named like the flags, with _)"),
          out: Path | None = typer.Option(None, "--out", help="batch: predictions CSV to write"),
          as_json: bool = typer.Option(False, "--json", help="print JSON")) -> None:
    """Damage rate per hour, life in hours, the calibrated interval and the OOD flag.

    Feature flags come from the model (e.g. --rpm, --wob-kN, --rop-m-per-h,
    --component-type); run with a model and no flags to list them.
    """
    import pandas as pd

    from drillfatigue.surrogate.io import write_csv
    from drillfatigue.surrogate.query import Vocabulary

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
    sur = _load_model(model)
    vocab = Vocabulary(sur.features, sur.categorical)
    if csv is not None:
        try:
            table = pd.read_csv(csv)
        except (pd.errors.ParserError, pd.errors.EmptyDataError, UnicodeDecodeError) as exc:
            raise InputError(str(csv), f"unreadable CSV ({type(exc).__name__})",
                             "a comma-separated table with a header") from None
        if len(table) == 0:
            raise InputError(str(csv), "no rows", ">= 1 condition row")
        frame = vocab.frame_from_table(table)
        pred = sur.predict(frame)
        result = pd.concat([table.reset_index(drop=True), pred.reset_index(drop=True)], axis=1)
        write_csv(result, out)
        n_ood = int(pred["ood"].sum())
        print(f"wrote {len(result)} predictions to {out} ({n_ood} out of domain)")
        return
    frame = vocab.frame_from_mapping(flags)
    row = sur.predict(frame).iloc[0]
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
    print(f"life: {res['life_h']:.4g} h ({pct} % interval {llo:.3g} .. {lhi:.3g} h)")
    if res["out_of_domain"]:
        print(f"OUT OF DOMAIN: {res['ood_reason']}")
    else:
        print("in the training domain")
