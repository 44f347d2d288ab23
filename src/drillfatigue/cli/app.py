"""The typer application object shared by every CLI command module."""

from __future__ import annotations

import typer

app = typer.Typer(
    name="drillfatigue",
    help="Drill-string dynamics and fatigue: simulate, count cycles, estimate life.",
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_enable=False,
)

