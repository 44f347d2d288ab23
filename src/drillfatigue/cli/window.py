"""``drillfatigue window``: the operating-window map of a surrogate.

::

    drillfatigue window --model data/surrogate/model --x rpm=60:180:25 --y wob_kN=30:120:19 \\
        --set md_m=1500 --set s_from_bit_m=8 --set component_type=collar ... --out map.png

Writes the map (:mod:`drillfatigue.surrogate.window`) as a PNG and, with
``--out-csv``, the grid.
"""

from __future__ import annotations

from pathlib import Path

import typer

from drillfatigue.cli.app import app
from drillfatigue.cli.twin import _read_csv, parse_settings
from drillfatigue.cli.vocabulary import model_option, out_option
from drillfatigue.errors import InputError
from drillfatigue.files import atomic_output, check_output_file


@app.command("window")
def window(model: Path = model_option(...),
           x: str = typer.Option("rpm", "--x", help="x axis NAME=START:STOP:NODES, or NAME "
                                 "alone: 31 nodes over the model's domain"),
           y: str = typer.Option("wob_kN", "--y", help="y axis NAME=START:STOP:NODES, or NAME "
                                 "alone: 31 nodes over the model's domain (wob_kN, ...)"),
           settings: list[str] = typer.Option([], "--set", help="fixed input NAME=VALUE, user "
                                              "units (md_m, s_from_bit_m, component_type, ...)"),
           survey: Path | None = typer.Option(None, "--survey", help="survey CSV (md_m, "
                                              "dls_deg_per_30m, inc_deg): hole geometry at "
                                              "md_m and the bit"),
           out: Path = out_option(..., help="PNG file to write"),
           out_csv: Path | None = out_option(None, help="also write the grid as CSV", what="csv"),
           title: str | None = typer.Option(None, "--title", help="figure title")) -> None:
    """Operating-window map: predicted life over rpm x WOB (or x ROP), OOD cells hatched."""
    # optional extra [surrogate]: torch
    from drillfatigue.surrogate import Surrogate
    from drillfatigue.surrogate.window import Axis, operating_window, plot_window

    if out.suffix.lower() != ".png":
        raise InputError("--out", f"{str(out)!r} is not a .png file", "FILE.png")
    if out.is_dir():
        raise InputError("--out", f"{str(out)!r} is a folder", "FILE.png")
    if out_csv is not None and (out_csv.suffix.lower() != ".csv" or out_csv.is_dir()):
        raise InputError("--out-csv", f"{str(out_csv)!r} is not a .csv file", "FILE.csv")
    inputs = [("--model", model), ("--survey", survey)]
    check_output_file(out, "--out", inputs)
    if out_csv is not None:
        check_output_file(out_csv, "--out-csv", [*inputs, ("--out", out)])
    fixed = parse_settings(list(settings))
    survey_t = _read_csv(survey, "--survey") if survey is not None else None
    if not (model / "metadata.json").is_file():
        raise InputError("--model", f"{str(model)!r} is not a surrogate model folder",
                         "a folder written by the train stage")
    sur = Surrogate.load(model)
    ax_x, ax_y = (Axis.parse(spec, opt) if "=" in spec
                  else Axis.in_domain(spec.strip().replace("-", "_"), sur, field=opt)
                  for spec, opt in ((x, "--x"), (y, "--y")))
    wmap = operating_window(sur, ax_x, ax_y, fixed, survey_t)
    plot_window(wmap, out, title)
    if out_csv is not None:
        with atomic_output(out_csv) as tmp:
            wmap.to_frame().to_csv(tmp, index=False)
    best = wmap.best_in_domain()
    print(f"wrote {out}" + (f" and {out_csv}" if out_csv is not None else "")
          + f"; {100 * wmap.ood.mean():.0f} % of the grid out of domain")
    if best is not None:
        print(f"longest life in domain: {best[ax_x.name]:.4g} {ax_x.name}, "
              f"{best[ax_y.name]:.4g} {ax_y.name}: {best['life_h']:.3g} h "
              f"(lower bound {best['life_h_lower']:.3g} h)")
