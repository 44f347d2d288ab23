"""``drillfatigue twin replay LOG.csv``: the digital twin's operating-log replay.

    drillfatigue twin replay data/examples/operating_log.csv \\
        --model models/surrogate --components data/examples/components.csv \\
        --set mu_static=0.35 --set mu_dynamic=0.28 ... --out runs/twin

Writes ``OUT/components_damage.csv`` (per component: accumulated damage with
interval, remaining life at the last rate, time in hole, out-of-domain time),
``OUT/summary.json`` and ``OUT/damage_along_string.png``.
"""

from __future__ import annotations

from pathlib import Path

import typer

from drillfatigue.cli.app import app
from drillfatigue.errors import InputError

twin_app = typer.Typer(help="Digital twin: replay operating logs through the surrogate.",
                       no_args_is_help=True)
app.add_typer(twin_app, name="twin")


def _read_csv(path: Path, option: str):  # noqa: ANN202
    import pandas as pd

    if not path.is_file():
        raise InputError(option, f"file {str(path)!r} not found", "an existing CSV file")
    try:
        table = pd.read_csv(path)
    except (pd.errors.ParserError, pd.errors.EmptyDataError, UnicodeDecodeError) as exc:
        raise InputError(str(path), f"unreadable CSV ({type(exc).__name__})",
                         "a comma-separated table with a header") from None
    if len(table) == 0:
        raise InputError(str(path), "no rows", ">= 1 row")
    return table


def parse_settings(items: list[str]) -> dict[str, str]:
    """``['mu_static=0.3']`` -> ``{'mu_static': '0.3'}`` (values converted later)."""
    out: dict[str, str] = {}
    for it in items:
        if "=" not in it:
            raise InputError("--set", f"{it!r} is not NAME=VALUE", "NAME=VALUE")
        k, v = it.split("=", 1)
        k = k.strip().replace("-", "_")
        if k in out:
            raise InputError("--set", f"{k!r} given twice", "each name once")
        out[k] = v.strip()
    return out


@twin_app.command("replay")
def replay(log: Path = typer.Argument(..., help="operating log CSV (time_s, bit_md_m, rpm, "
                                      "wob_kN, rop_m_per_h, ...)"),
           model: Path = typer.Option(..., "--model", help="surrogate model folder"),
           components: Path = typer.Option(..., "--components", help="component list CSV "
                                           "(serial, component_type, location, s_from_bit_m)"),
           out: Path = typer.Option(..., "--out", help="output folder"),
           settings: list[str] = typer.Option([], "--set", help="constant feature NAME=VALUE "
                                              "(user units, e.g. mud_density_sg=1.2)"),
           survey: Path | None = typer.Option(None, "--survey", help="survey CSV (md_m, "
                                              "dls_deg_per_30m) for the local dogleg")) -> None:
    """Accumulate fatigue damage per component over an operating log."""
    from drillfatigue.surrogate import Surrogate
    from drillfatigue.surrogate.io import write_csv, write_json
    from drillfatigue.surrogate.twin import plot_damage_along_string, replay_log

    if out.exists() and not out.is_dir():
        raise InputError("--out", f"{str(out)!r} exists and is not a folder", "a folder path")
    log_t = _read_csv(log, "LOG")
    comp_t = _read_csv(components, "--components")
    survey_t = _read_csv(survey, "--survey") if survey is not None else None
    consts = parse_settings(list(settings))
    if not (model / "metadata.json").is_file():
        raise InputError("--model", f"{str(model)!r} is not a surrogate model folder",
                         "a folder written by the train stage")
    sur = Surrogate.load(model)
    res = replay_log(log_t, comp_t, sur, consts, survey_t)
    out.mkdir(parents=True, exist_ok=True)
    c = res.components
    write_csv(c, out / "components_damage.csv")
    worst = c.loc[c["damage"].idxmax()]
    write_json({
        "duration_h": res.duration_s / 3600.0,
        "n_components": int(len(c)),
        "criterion": sur.metadata["criterion"],
        "coverage": sur.coverage,
        "max_damage": float(worst["damage"]),
        "max_damage_serial": str(worst["serial"]),
        "total_ood_time_s": float(c["ood_time_s"].sum()),
    }, out / "summary.json")
    plot_damage_along_string(res, str(out / "damage_along_string.png"))
    print(f"replayed {res.duration_s / 3600.0:.3g} h for {len(c)} components; "
          f"max damage {float(worst['damage']):.3g} at {worst['serial']}; wrote {out}/")
