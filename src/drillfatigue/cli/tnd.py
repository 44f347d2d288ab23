"""``drillfatigue tnd CASE.yaml [-o plot.png] [--json]``: soft-string torque and drag.

Prints the surface hook loads for pick-up, slack-off, rotating off bottom and
drilling, and the surface torque rotating and drilling (Johancsik soft-string
model, :mod:`drillfatigue.dynamics.softstring`), the smallest margin to
sinusoidal buckling along the string in slack-off and drilling
(:mod:`drillfatigue.dynamics.buckling`); optionally plots tension and torque
against MD with the buckling onset loads.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import typer
from rich.console import Console
from rich.table import Table

from drillfatigue.cli.app import app
from drillfatigue.config import load_case
from drillfatigue.dynamics.buckling import BucklingProfile, buckling_for_case
from drillfatigue.dynamics.softstring import TorqueDrag, torque_drag_for_case
from drillfatigue.errors import InputError
from drillfatigue.units import KN_N

_PLOT_FORMATS = ("png", "pdf", "svg")


def _check_plot_path(path: Path) -> None:
    suffix = path.suffix.lower().lstrip(".")
    if suffix not in _PLOT_FORMATS:
        raise InputError("-o", f"unsupported file type {path.suffix or '(none)'!r} of {str(path)!r}",
                         ", ".join("." + s for s in _PLOT_FORMATS))
    parent = path.parent if str(path.parent) else Path(".")
    if not parent.is_dir():
        raise InputError("-o", f"folder {str(parent)!r} does not exist", "an existing folder")


def plot_torque_drag(td: TorqueDrag, path: str | Path, title: str,
                     buckling: BucklingProfile | None = None) -> None:
    """Tension (kN) and torque (kN m) against MD for the four modes; written atomically.

    With ``buckling``, the sinusoidal and helical onset loads are drawn as
    negative tensions (compression beyond them buckles the pipe).
    """
    import matplotlib

    matplotlib.use("Agg")
    from matplotlib.figure import Figure

    from drillfatigue.well.survey import atomic_output

    fig = Figure(figsize=(11, 5.5))
    ax1, ax2 = fig.subplots(1, 2, sharey=True)
    for name, t in (("pick-up", td.tension_pickup_N), ("slack-off", td.tension_slackoff_N),
                    ("rotating off bottom", td.tension_rotating_N), ("drilling", td.tension_drilling_N)):
        ax1.plot(t / KN_N, td.md_m, label=name)
    if buckling is not None:
        ax1.plot(-buckling.sinusoidal_onset_N / KN_N, buckling.md_mid_m, "k--", lw=0.8,
                 label="sinusoidal buckling onset")
        ax1.plot(-buckling.helical_onset_N / KN_N, buckling.md_mid_m, "k:", lw=0.8,
                 label="helical buckling onset")
        lo = min(float(td.tension_slackoff_N.min()), float(td.tension_drilling_N.min()))
        ax1.set_xlim(left=min(2.0 * lo, -1.0) / KN_N, right=1.05 * float(td.tension_pickup_N.max()) / KN_N)
    ax1.axvline(0.0, color="k", lw=0.8)
    ax1.set_xlabel("effective tension, kN (compression < 0)")
    ax1.set_ylabel("MD, m")
    ax1.invert_yaxis()
    ax1.legend()
    ax1.grid(alpha=0.3)
    ax2.plot(td.torque_rotating_Nm / KN_N, td.md_m, label="rotating off bottom")
    ax2.plot(td.torque_drilling_Nm / KN_N, td.md_m, label="drilling")
    ax2.set_xlabel("torque, kN m")
    ax2.legend()
    ax2.grid(alpha=0.3)
    fig.suptitle(title)
    fig.tight_layout()
    with atomic_output(path) as tmp:
        fig.savefig(tmp, dpi=120)


@app.command("tnd")
def tnd(
    case: Path = typer.Argument(..., help="case YAML file (sections as in params.yaml)"),
    output: Path | None = typer.Option(None, "--output", "-o", help="plot file (.png/.pdf/.svg)"),
    as_json: bool = typer.Option(False, "--json", help="print the results as JSON (SI units)"),
    cell_m: float = typer.Option(10.0, "--cell-m", help="largest cell length, m"),
    wob_kN: float | None = typer.Option(None, "--wob-kN", help="WOB of the drilling mode, kN "
                                        "(default: from the operation section)"),
) -> None:
    """Soft-string (Johancsik) hook loads and surface torque; tension/torque vs MD plot."""
    if not (math.isfinite(cell_m) and 0.01 <= cell_m <= 1000.0):
        raise InputError("--cell-m", f"got {cell_m}", "0.01 <= cell_m <= 1000")
    if wob_kN is not None and not (math.isfinite(wob_kN) and 0.0 <= wob_kN <= 1e5):
        raise InputError("--wob-kN", f"got {wob_kN}", "0 <= wob_kN <= 1e5")
    if output is not None:
        _check_plot_path(output)
    cfg = load_case(case)
    td = torque_drag_for_case(cfg, cell_m=cell_m, wob_N=None if wob_kN is None else wob_kN * KN_N)
    summary = td.summary()
    buck = buckling_for_case(cfg, td)
    summary.update(buck.summary())
    if as_json:
        summary["mu_torque"] = cfg.friction.mu_dynamic
        summary["mu_drag"] = cfg.friction.mu_axial if cfg.friction.mu_axial is not None \
            else cfg.friction.mu_dynamic
        summary["bit_md_m"] = float(td.md_m[-1])
        typer.echo(json.dumps(summary, indent=2))
    else:
        table = Table(title=f"soft-string torque and drag: {case.name} "
                            f"(bit at MD {td.md_m[-1]:.1f} m)")
        table.add_column("mode")
        table.add_column("hook load, kN", justify="right")
        table.add_column("surface torque, kN m", justify="right")
        for label, key, tq in (("pick-up", "pickup", None), ("slack-off", "slackoff", None),
                               ("rotating off bottom", "rotating", "rotating"),
                               ("drilling", "drilling", "drilling")):
            torque = "-" if tq is None else f"{summary[f'surface_torque_{tq}_Nm'] / KN_N:.2f}"
            table.add_row(label, f"{summary[f'hookload_{key}_N'] / KN_N:.1f}", torque)
        console = Console(width=max(Console().width, 90))
        console.print(table)
        console.print(f"drilling: WOB {td.wob_N / KN_N:.1f} kN, TOB {td.tob_Nm / KN_N:.2f} kN m")
        for mode, label in (("slackoff", "slack-off"), ("drilling", "drilling")):
            console.print(f"{label}: smallest margin to sinusoidal buckling "
                          f"{summary[f'buckling_min_margin_{mode}_N'] / KN_N:.1f} kN at MD "
                          f"{summary[f'buckling_min_margin_{mode}_md_m']:.0f} m; buckled "
                          f"{summary[f'buckled_sinusoidal_{mode}_m']:.0f} m sinusoidal, "
                          f"{summary[f'buckled_helical_{mode}_m']:.0f} m helical")
    if output is not None:
        plot_torque_drag(td, output, f"soft-string torque and drag: {case.name}", buck)
