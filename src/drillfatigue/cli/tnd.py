"""``drillfatigue tnd CASE.yaml [-o plot.png] [--json]``: soft-string torque and drag.

Prints the surface hook loads for pick-up, slack-off, rotating off bottom and
drilling, and the surface torque rotating and drilling (Johancsik soft-string
model, :mod:`drillfatigue.softstring.march`), the smallest margin to
sinusoidal buckling along the string in slack-off and drilling
(:mod:`drillfatigue.softstring.buckling`); optionally plots tension and torque
against MD with the buckling onset loads.
"""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Any

import typer
from rich.console import Console
from rich.table import Table

from drillfatigue.cli.app import app
from drillfatigue.config import load_case
from drillfatigue.softstring.buckling import BucklingProfile, buckling_for_case
from drillfatigue.softstring.torque_drag import TorqueDrag, torque_drag_for_case
from drillfatigue.errors import InputError
from drillfatigue.limits import check_value
from drillfatigue.files import atomic_output, check_output_file
from drillfatigue.io.display import Display, check_system
from drillfatigue.plotting import figure
from drillfatigue.units import KN_N

_PLOT_FORMATS = ("png", "pdf", "svg")


def _check_plot_path(path: Path) -> None:
    check_output_file(path, "--out")
    suffix = path.suffix.lower().lstrip(".")
    if suffix not in _PLOT_FORMATS:
        raise InputError("--out", f"unsupported file type {path.suffix or '(none)'!r} of {str(path)!r}",
                         ", ".join("." + s for s in _PLOT_FORMATS))
    parent = path.parent if str(path.parent) else Path(".")
    if not parent.is_dir():
        raise InputError("--out", f"folder {str(parent)!r} does not exist", "an existing folder")


def plot_torque_drag(td: TorqueDrag, path: str | Path, title: str,
                     display: Display | None = None,
                     buckling: BucklingProfile | None = None) -> None:
    """Tension and torque against MD for the four modes (kN, kN m, m or, with a field
    ``display``, klbf, kft lbf, ft); written atomically.

    With ``buckling``, the sinusoidal and helical onset loads are drawn as
    negative tensions (compression beyond them buckles the pipe).
    """
    d = display if display is not None else Display("si")
    fu, tu, lu = d.unit("force"), d.unit("torque"), d.unit("length")
    md = d.value("length", td.md_m)
    fig = figure(figsize=(11, 5.5))
    ax1, ax2 = fig.subplots(1, 2, sharey=True)
    for name, t in (("pick-up", td.tension_pickup_N), ("slack-off", td.tension_slackoff_N),
                    ("rotating off bottom", td.tension_rotating_N), ("drilling", td.tension_drilling_N)):
        ax1.plot(d.value("force", t), md, label=name)
    if buckling is not None:
        mdb = d.value("length", buckling.md_mid_m)
        ax1.plot(d.value("force", -buckling.sinusoidal_onset_N), mdb, "k--", lw=0.8,
                 label="sinusoidal buckling onset")
        ax1.plot(d.value("force", -buckling.helical_onset_N), mdb, "k:", lw=0.8,
                 label="helical buckling onset")
        lo = min(float(td.tension_slackoff_N.min()), float(td.tension_drilling_N.min()))
        ax1.set_xlim(left=d.value("force", min(2.0 * lo, -1.0)),
                     right=d.value("force", 1.05 * float(td.tension_pickup_N.max())))
    ax1.axvline(0.0, color="k", lw=0.8)
    ax1.set_xlabel(f"effective tension, {fu} (compression < 0)")
    ax1.set_ylabel(f"MD, {lu}")
    ax1.invert_yaxis()
    ax1.legend()
    ax1.grid(alpha=0.3)
    ax2.plot(d.value("torque", td.torque_rotating_Nm), md, label="rotating off bottom")
    ax2.plot(d.value("torque", td.torque_drilling_Nm), md, label="drilling")
    ax2.set_xlabel(f"torque, {tu}")
    ax2.legend()
    ax2.grid(alpha=0.3)
    fig.suptitle(title)
    fig.tight_layout()
    with atomic_output(path) as tmp:
        fig.savefig(tmp, dpi=120)


@app.command("tnd")
def tnd(
    case: Path = typer.Argument(..., help="case YAML file (sections as in params.yaml)"),
    out: Path | None = typer.Option(None, "--out", "-o", help="plot file (.png/.pdf/.svg)"),
    as_json: bool = typer.Option(False, "--json", help="print the results as JSON (SI units)"),
    cell_m: float = typer.Option(10.0, "--cell-m", help="largest cell length, m"),
    wob_kN: float | None = typer.Option(None, "--wob-kN", help="WOB of the drilling mode, kN "
                                        "(default: from the operation section)"),
    unit_system: str = typer.Option("si", "--units", help="table and plot units: si (kN, "
                                    "kN m, m) or field (klbf, kft lbf, ft); --json stays SI"),
) -> None:
    """Soft-string (Johancsik) hook loads and surface torque; tension/torque vs MD plot."""
    output = out
    if not (math.isfinite(cell_m) and 0.01 <= cell_m <= 1000.0):
        raise InputError("--cell-m", f"got {cell_m}", "0.01 <= cell_m <= 1000")
    if wob_kN is not None:  # the physical bound of every entry point (drillfatigue.limits)
        check_value("--wob-kN", "wob_N", wob_kN * KN_N, "wob_kN", KN_N)
    d = Display(check_system(unit_system))
    if output is not None:
        _check_plot_path(output)
    cfg = load_case(case)
    td = torque_drag_for_case(cfg, cell_m=cell_m, wob_N=None if wob_kN is None else wob_kN * KN_N)
    summary: dict[str, Any] = dict(td.summary())
    hook = float(summary["hookload_drilling_N"])
    if wob_kN is not None and hook < 0.0:
        # the block can hold the string back, not push it down: more WOB than the
        # buoyed weight less the drag gives is no drilling state (a WOB from the
        # operation section, the weight below the neutral point, cannot exceed it)
        most = (wob_kN * KN_N + hook) / KN_N
        raise InputError("--wob-kN", f"{wob_kN:g} kN would need a drilling hook load of "
                         f"{hook / KN_N:.1f} kN (the block pushing the string down)",
                         f"0 <= wob_kN <= {most:.1f} (hook load >= 0) for this string")
    buck = buckling_for_case(cfg, td)
    summary.update(buck.summary())
    if as_json:
        summary["mu_torque"] = cfg.friction.mu_dynamic
        summary["mu_drag"] = cfg.friction.mu_axial if cfg.friction.mu_axial is not None \
            else cfg.friction.mu_dynamic
        summary["bit_md_m"] = float(td.md_m[-1])
        typer.echo(json.dumps(summary, indent=2))
    else:
        fu, tu, lu = d.unit("force"), d.unit("torque"), d.unit("length")
        table = Table(title=f"soft-string torque and drag: {case.name} "
                            f"(bit at MD {d.value('length', float(td.md_m[-1])):.1f} "
                            f"{d.unit('length')})")
        table.add_column("mode")
        table.add_column(f"hook load, {fu}", justify="right")
        table.add_column(f"surface torque, {tu}", justify="right")
        for label, key, tq in (("pick-up", "pickup", None), ("slack-off", "slackoff", None),
                               ("rotating off bottom", "rotating", "rotating"),
                               ("drilling", "drilling", "drilling")):
            torque = ("-" if tq is None else
                      f"{d.value('torque', summary[f'surface_torque_{tq}_Nm']):.2f}")
            table.add_row(label, f"{d.value('force', summary[f'hookload_{key}_N']):.1f}", torque)
        console = Console(width=max(Console().width, 90))
        console.print(table)
        console.print(f"drilling: WOB {d.value('force', td.wob_N):.1f} {fu}, "
                      f"TOB {d.value('torque', td.tob_Nm):.2f} {tu}")
        for mode, label in (("slackoff", "slack-off"), ("drilling", "drilling")):
            margin = d.value("force", float(summary[f"buckling_min_margin_{mode}_N"]))
            at = d.value("length", float(summary[f"buckling_min_margin_{mode}_md_m"]))
            sin_l = d.value("length", float(summary[f"buckled_sinusoidal_{mode}_m"]))
            hel_l = d.value("length", float(summary[f"buckled_helical_{mode}_m"]))
            console.print(f"{label}: smallest margin to sinusoidal buckling {margin:.1f} {fu} "
                          f"at MD {at:.0f} {lu}; buckled {sin_l:.0f} {lu} sinusoidal, "
                          f"{hel_l:.0f} {lu} helical")
            for sec in summary[f"buckled_sections_{mode}"]:
                console.print(f"  {sec['mode']} from MD {d.value('length', sec['md_start_m']):.0f} "
                              f"to {d.value('length', sec['md_end_m']):.0f} {lu}")
    if output is not None:
        plot_torque_drag(td, output, f"soft-string torque and drag: {case.name}", d, buck)
