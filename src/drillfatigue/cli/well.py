"""``drillfatigue well show|plot|export CASE.yaml``: inspect a case's well profile."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import typer
from rich.console import Console
from rich.table import Table

from drillfatigue.cli.app import app
from drillfatigue.cli.vocabulary import PROFILE, profile_option
from drillfatigue.config import WellConfig, load_case
from drillfatigue.config.well import TortuosityConfig
from drillfatigue.errors import InputError
from drillfatigue.files import check_output_file
from drillfatigue.io.display import Display, check_system
from drillfatigue.well.survey_file import write_survey
from drillfatigue.well import Survey, build_plan_survey, build_survey, key_points
from drillfatigue.well.outputs import plot_survey
from drillfatigue.well.profiles import resolve_profile
from drillfatigue.well.tortuosity import tortuosity_report

well_app = typer.Typer(help="Well profiles: show key points, plot, export the survey.",
                       no_args_is_help=True)
app.add_typer(well_app, name="well")

_PLOT_FORMATS = ("png", "pdf", "svg")

CaseArg = typer.Argument(..., help="case YAML file (sections as in params.yaml)")
ProfileOpt = profile_option(help="profile name (default: well.profile)")
UnitsOpt = typer.Option("si", "--units", help="si (m, deg/30m) or field (ft, deg/100ft)")


def _load(case: Path, profile: str | None) -> tuple[WellConfig, str, Survey]:
    cfg = load_case(case).well
    if profile is not None and profile not in cfg.profiles:
        raise InputError(PROFILE, f"{profile!r} is not defined in well.profiles",
                         ", ".join(cfg.profiles))
    name = resolve_profile(cfg, profile)
    return cfg, name, build_survey(cfg, name)


def _check_output(path: Path, suffixes: tuple[str, ...], option: str = "--out") -> str:
    check_output_file(path, option)
    suffix = path.suffix.lower().lstrip(".")
    if suffix not in suffixes:
        raise InputError(option, f"unsupported file type {path.suffix or '(none)'!r} of "
                         f"{str(path)!r}", ", ".join("." + s for s in suffixes))
    parent = path.parent if str(path.parent) else Path(".")
    if not parent.is_dir():
        raise InputError(option, f"folder {str(parent)!r} does not exist", "an existing folder")
    return suffix


@well_app.command("show")
def show(case: Path = CaseArg, profile: str | None = ProfileOpt,
         unit_system: str = UnitsOpt) -> None:
    """Print MD, inclination, azimuth, TVD, N, E and DLS at the key points, and the
    hole tortuosity (well.tortuosity) with what it does to the plan when it is set."""
    d = Display(check_system(unit_system))
    cfg, name, sv = _load(case, profile)
    keys = key_points(cfg, name)
    table = Table(title=f"well profile {name!r} ({cfg.profiles[name].kind})")
    lu, du = d.unit("length"), d.unit("dogleg")
    for col in ("point", f"MD {lu}", "inc deg", "azi deg", f"TVD {lu}", f"N {lu}", f"E {lu}",
                f"DLS {du}"):
        table.add_column(col, justify="left" if col == "point" else "right", no_wrap=True)
    dls = d.value("dogleg", sv.dls_deg_per_30m)
    md = d.value("length", sv.md_m)
    pos = d.value("length", sv.pos_m)
    rows = [(k.label, int(np.argmin(np.abs(sv.md_m - k.md_m)))) for k in keys]
    imax = int(np.argmax(dls))
    rows.append(("max DLS", imax))
    for label, i in rows:
        n, e, tvd = pos[i]
        table.add_row(label, f"{md[i]:.1f}", f"{math.degrees(sv.inc_rad[i]):.2f}",
                      f"{math.degrees(sv.azi_rad[i]):.2f}", f"{tvd:.2f}", f"{n:.2f}",
                      f"{e:.2f}", f"{dls[i]:.2f}")
    console = Console(width=max(Console().width, 100))
    console.print(table)
    console.print(f"max DLS: {sv.dls_deg_per_30m.max():.3f} deg/30m = "
                  f"{sv.dls_deg_per_100ft.max():.3f} deg/100ft at MD {md[imax]:.1f} {lu}; "
                  f"TD {md[-1]:.1f} {lu}")
    if cfg.tortuosity is not None:
        console.print(_tortuosity_table(cfg.tortuosity, build_plan_survey(cfg, name), sv, d))


def _tortuosity_table(spec: TortuosityConfig, plan: Survey, sv: Survey, d: Display) -> Table:
    """The tortuosity model, and the plan's and the tortuous hole's dogleg severity below
    its start and tortuosity index, in the display's units."""
    rep = tortuosity_report(plan, sv, spec)
    lu, du = d.unit("length"), d.unit("dogleg")
    per_length = float(d.value("length", 1.0))  # display length units in a metre
    seed = f", seed {spec.seed}" if spec.model == "random" else ""
    start = float(d.value("length", spec.md_start_m))
    peak = float(d.value("dogleg", rep["peak_added_dls_deg_per_30m"]))
    table = Table(title=f"tortuosity: {spec.model}, amplitude {spec.amplitude_deg:g} deg, period "
                        f"{float(d.value('length', spec.period_m)):g} {lu}, {spec.direction}{seed}"
                        f"; below MD {start:.1f} {lu}, adding up to {peak:.3f} {du}")
    for col in ("", "plan", "tortuous hole"):
        table.add_column(col, justify="left" if not col else "right", no_wrap=True)
    for label, key in ((f"max DLS below MD {start:.1f} {lu}, {du}", "max_dls_deg_per_30m"),
                       (f"mean DLS below MD {start:.1f} {lu}, {du}", "mean_dls_deg_per_30m")):
        table.add_row(label, *(f"{float(d.value('dogleg', rep[k][key])):.3f}"
                               for k in ("plan", "tortuous")))
    table.add_row(f"tortuosity index, 1/{lu}",
                  *(f"{rep[k]['tortuosity_index_per_m'] / per_length:.3e}"
                    for k in ("plan", "tortuous")))
    return table


@well_app.command("plot")
def plot(case: Path = CaseArg,
         out: Path = typer.Option(..., "--out", "-o", help="figure file (.png/.pdf/.svg)"),
         profile: str | None = ProfileOpt, unit_system: str = UnitsOpt) -> None:
    """Draw the 3D view, the vertical section and DLS vs MD."""
    output = out
    d = Display(check_system(unit_system))
    _check_output(output, _PLOT_FORMATS)
    _, name, sv = _load(case, profile)
    plot_survey(sv, output, f"well profile {name}", d)


@well_app.command("export")
def export(case: Path = CaseArg,
           out: Path = typer.Option(..., "--out", "-o", help="survey CSV file"),
           profile: str | None = ProfileOpt, unit_system: str = UnitsOpt) -> None:
    """Write the profile's survey as CSV: md_m,inc_deg,azi_deg, or in field units
    (MD and TVD in ft, DLS in deg/100ft; reads back to the same SI stations)."""
    output = out
    system = check_system(unit_system)
    _check_output(output, ("csv",))
    _, _, sv = _load(case, profile)
    write_survey(sv, output, system)
