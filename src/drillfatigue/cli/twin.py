"""``drillfatigue twin replay LOG``: the digital twin's operating-log replay.

    drillfatigue twin replay LOG.csv --string STRING.yaml --well WELL.yaml \\
        --model data/surrogate/model --set mu_static=0.35 ... --out runs/twin
    drillfatigue twin replay data/examples/operating_log.csv \\
        --model data/surrogate/model --components data/examples/components.csv \\
        --survey data/examples/survey.csv --set mu_static=0.35 ... --out runs/twin

The log is a LAS 2.0 file, a WITSML 1.4.1.1 log or a CSV, read by
:mod:`drillfatigue.io.logs` (channel aliases, units, fill rules; what was
filled is printed and reported in ``summary.json``).
``--string``/``--well`` take a case or params file (its ``string``/``well``
section) or the bare section, ``--string`` also a tally CSV
(:mod:`drillfatigue.io.tally`); ``--components`` takes a CSV table and
``--survey`` a survey file (:mod:`drillfatigue.well.survey_file`). ``--units
field`` prints and plots in ft.
The log may carry a hook-load channel instead of WOB (``hook_load_kN`` with
``--set off_bottom_hook_load_kN=...``).

Writes ``OUT/components_damage.csv`` (per component: accumulated damage with
interval, remaining life at the last rate, time in hole, out-of-domain time),
``OUT/summary.json`` and ``OUT/damage_along_string.png``.
"""

from __future__ import annotations

from pathlib import Path

import typer

from drillfatigue.cli.app import app
from drillfatigue.cli.vocabulary import model_option, out_option
from drillfatigue.config import StringConfig, WellConfig
from drillfatigue.config.base import read_yaml, validate
from drillfatigue.errors import InputError
from drillfatigue.files import OutputFolder
from drillfatigue.io.display import Display, check_system
from drillfatigue.io.logs import DEFAULT_MAX_FILL_S, DEFAULT_MAX_GAP_S, load_log
from drillfatigue.well.survey_file import twin_survey_table
from drillfatigue.io.tables import read_csv_file
from drillfatigue.io.tally import load_tally

#: Kind of the ownership marker of a twin output folder.
TWIN_KIND = "twin"

twin_app = typer.Typer(help="Digital twin: replay operating logs through the surrogate.",
                       no_args_is_help=True)
app.add_typer(twin_app, name="twin")


def _read_csv(path: Path, option: str):  # noqa: ANN202
    if not path.is_file():
        raise InputError(option, f"file {str(path)!r} not found", "an existing CSV file")
    table = read_csv_file(path)  # ragged rows, empty cells, a column twice: refused
    if len(table) == 0:
        raise InputError(str(path), "no rows", ">= 1 row")
    return table


def parse_settings(items: list[str], option: str = "--set") -> dict[str, str]:
    """``['mu_static=0.3']`` -> ``{'mu_static': '0.3'}`` (values converted later)."""
    out: dict[str, str] = {}
    for it in items:
        if "=" not in it:
            raise InputError(option, f"{it!r} is not NAME=VALUE", "NAME=VALUE")
        k, v = it.split("=", 1)
        k = k.strip().replace("-", "_")
        if k in out:
            raise InputError(option, f"{k!r} given twice", "each name once")
        out[k] = v.strip()
    return out


def read_section(path: Path, key: str, option: str, model: type) -> object:
    """A config section from YAML: a file holding ``key:`` (a case or params file) or
    the section itself."""
    if not path.is_file():
        raise InputError(option, f"file {str(path)!r} not found", "an existing YAML file")
    data = read_yaml(path)
    if isinstance(data, dict) and isinstance(data.get(key), dict):
        data = data[key]
    return validate(model, data, key)


@twin_app.command("replay")
def replay(log: Path = typer.Argument(..., help="operating log: LAS 2.0 (.las), WITSML 1.4.1.1 "
                                      "log (.xml) or CSV (field headers such as 'WOB (klbf)', "
                                      "or time_s, bit_md_m, rpm, wob_kN, rop_m_per_h, ...)"),
           model: Path = model_option(...),
           out: Path = out_option(..., help="output folder"),
           string: Path | None = typer.Option(None, "--string", help="string YAML (a case or "
                                              "params file, or the string section) or a tally "
                                              "CSV: tracks every segment's body and connection"),
           well: Path | None = typer.Option(None, "--well", help="well YAML (a case or params "
                                            "file, or the well section): local dogleg along "
                                            "the hole"),
           components: Path | None = typer.Option(None, "--components", help="component list "
                                                  "CSV (serial, component_type, location, "
                                                  "s_from_bit_m), instead of --string"),
           settings: list[str] = typer.Option([], "--set", help="constant feature NAME=VALUE "
                                              "(user units, e.g. mud_density_sg=1.2)"),
           survey: Path | None = typer.Option(None, "--survey", help="survey file (CSV in m or "
                                              "ft, WITSML trajectory XML) or a geometry table "
                                              "(md_m, dls_deg_per_30m), instead of --well"),
           channels: list[str] = typer.Option([], "--channel", help="STEM=MNEMONIC: the log "
                                              "channel to use for a quantity, e.g. "
                                              "rpm=SURF_RPM"),
           max_fill_s: float = typer.Option(DEFAULT_MAX_FILL_S, "--max-fill-s",
                                            help="longest run of null values held from the "
                                            "previous value, s"),
           max_gap_s: float = typer.Option(DEFAULT_MAX_GAP_S, "--max-gap-s",
                                           help="longest step between log samples, s"),
           unit_system: str = typer.Option("si", "--units", help="units of the printed "
                                           "summary and the plot: si or field")) -> None:
    """Accumulate fatigue damage per component over an operating log."""
    # optional extra [surrogate]: torch
    from drillfatigue.surrogate import Surrogate
    from drillfatigue.surrogate.io import write_csv, write_json
    from drillfatigue.surrogate.twin import (
        components_from_string,
        plot_damage_along_string,
        replay_log,
        replay_summary,
        survey_from_well,
    )

    display = Display(check_system(unit_system))
    OutputFolder.check(out, TWIN_KIND, "--out")
    if (string is None) == (components is None):
        raise InputError("--string", "give exactly one of --string and --components",
                         "--string STRING.yaml or --components FILE.csv")
    if well is not None and survey is not None:
        raise InputError("--well", "give at most one of --well and --survey",
                         "--well WELL.yaml or --survey FILE.csv")
    imported = load_log(log, parse_settings(list(channels), "--channel"), max_fill_s, max_gap_s)
    log_t = imported.table
    if string is not None and string.suffix.lower() == ".csv":
        tally = load_tally(string)
        comp_t = components_from_string(tally.string, kinds=tally.kinds)
    elif string is not None:
        comp_t = components_from_string(read_section(string, "string", "--string", StringConfig))
    else:
        comp_t = _read_csv(components, "--components")
    if well is not None:
        survey_t = survey_from_well(read_section(well, "well", "--well", WellConfig))
    elif survey is not None:
        if not survey.is_file():
            raise InputError("--survey", f"file {str(survey)!r} not found", "an existing file")
        survey_t = twin_survey_table(survey)
    else:
        survey_t = None
    consts = parse_settings(list(settings))
    if not (model / "metadata.json").is_file():
        raise InputError("--model", f"{str(model)!r} is not a surrogate model folder",
                         "a folder written by the train stage")
    sur = Surrogate.load(model)
    res = replay_log(log_t, comp_t, sur, consts, survey_t)
    folder = OutputFolder(out, TWIN_KIND, "--out")
    c = res.components
    write_csv(c, folder.file("components_damage.csv"))
    summary = replay_summary(res)
    write_json({**summary, "criterion": sur.metadata["criterion"], "coverage": sur.coverage,
                "log": imported.report()}, folder.file("summary.json"))
    plot_damage_along_string(res, str(folder.file("damage_along_string.png")), display)
    if summary["max_damage_serial"] is None:
        print(f"replayed {summary['duration_h']:.3g} h for {len(c)} locations; no answer: "
              f"no covered location was ever in the model's domain; wrote {out}/")
    else:
        s_worst = display.value("length", summary["max_damage_s_from_bit_m"])
        print(f"replayed {summary['duration_h']:.3g} h for {len(c)} locations; max damage in "
              f"domain {summary['max_damage_in_domain']:.3g} at {summary['max_damage_serial']} "
              f"({s_worst:.1f} {display.unit('length')} from the bit); wrote {out}/")
    if summary["n_locations_some_time_ood"]:
        print(f"{summary['n_locations_some_time_ood']} of {summary['n_locations_covered']} "
              f"covered locations spent time out of the model's domain (no damage counted "
              f"then; up to {summary['max_ood_time_h']:.3g} h): ood_time_s in "
              "components_damage.csv")
    for entry in summary["not_covered"]:
        print(f"not covered: {entry['item']}: {entry['reason']}")
    if res.ignored_channels or imported.ignored:
        print("log channels not used by the model: "
              + ", ".join([*res.ignored_channels, *imported.ignored]))
    for name, info in imported.filled.items():
        print(f"{name}: {info['samples']} null value(s) held from the previous sample "
              f"(longest gap {info['longest_gap_s']:.0f} s)")
    if imported.dropped_repeated_rows:
        print(f"{imported.dropped_repeated_rows} repeated row(s) dropped")
    for note in imported.notes:
        print(note)
