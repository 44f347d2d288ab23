"""The typer application object shared by every CLI command module."""

from __future__ import annotations

from pathlib import Path

import typer

from drillfatigue.errors import InputError

app = typer.Typer(
    name="drillfatigue",
    help="Drill-string dynamics and fatigue: simulate, count cycles, estimate life.",
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_enable=False,
)


#: ``--output``: the spelling some commands used before every command took
#: ``--out``; still accepted, hidden from the help.
LegacyOutputOpt = typer.Option(None, "--output", hidden=True,
                               help="deprecated spelling of --out")


def pick_out(out: Path | None, legacy_output: Path | None) -> Path | None:
    """The ``--out`` path, or the deprecated ``--output`` one (None if neither); error if both."""
    if out is not None and legacy_output is not None:
        raise InputError("--out", "given twice (--out and its old spelling --output)", "one --out")
    return out if out is not None else legacy_output


def require_out(out: Path | None, legacy_output: Path | None) -> Path:
    """Like :func:`pick_out` for a command that needs an output: error if neither is given."""
    chosen = pick_out(out, legacy_output)
    if chosen is None:
        raise InputError("--out", "missing", "--out FILE")
    return chosen
