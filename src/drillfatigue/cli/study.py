"""``drillfatigue study case1|case2|case3``: the founding paper's case studies.

::

    drillfatigue study case1|case2|case3 [--params params.yaml] [--out DIR]
"""

from __future__ import annotations

from pathlib import Path

import typer

from drillfatigue.cli.app import app
from drillfatigue.cli.vocabulary import out_option, params_option
from drillfatigue.errors import InputError


@app.command("study")
def study(
    name: str = typer.Argument(..., help="case1, case2 or case3"),
    params: Path = params_option(Path("params.yaml"), help="params file whose NAME section "
                                 "to run"),
    out: Path | None = out_option(None, help="output folder (default: data/NAME)"),
) -> None:
    """Run one of the founding paper's case studies (reduced by default, see params)."""
    from drillfatigue.studies.stages import load_section, run_study  # start-up: every study, ~0.9 s

    if name not in ("case1", "case2", "case3"):
        raise InputError("study", f"unknown study {name!r}", "case1, case2, case3")
    load_section(params, name)  # validate before anything is written
    run_study(name, params, out or Path("data") / name)
    typer.echo(f"wrote {out or Path('data') / name}")
