"""Command-line interface: ``drillfatigue <command> ...``.

Each command lives in its own module of this package and registers itself on
:data:`drillfatigue.cli.app.app` when imported. :func:`main` turns bad input
into one line ``error: <field>: <problem> (allowed: ...)`` on stderr and exit
code 2.
"""

from __future__ import annotations

import importlib
import sys

import click

from drillfatigue.cli.app import app
from drillfatigue.errors import InputError
from drillfatigue.numba_cache import scope_numba_cache

# Command modules, imported for their registration side effect.
COMMAND_MODULES: tuple[str, ...] = (
    "drillfatigue.cli.fatigue",
    "drillfatigue.cli.well",
    "drillfatigue.cli.string",
    "drillfatigue.cli.tnd",
    "drillfatigue.cli.query",
    "drillfatigue.cli.twin",
    "drillfatigue.cli.simulate",
    "drillfatigue.cli.sweep",
    "drillfatigue.cli.plan",
    "drillfatigue.cli.serve",
)


def _load_commands() -> None:
    for name in COMMAND_MODULES:
        importlib.import_module(name)


def main(argv: list[str] | None = None) -> int:
    """Run the CLI; return the process exit code."""
    scope_numba_cache()  # before the command modules import any kernel
    _load_commands()
    try:
        result = app(args=argv, standalone_mode=False)
    except InputError as exc:
        print(f"error: {exc.one_line()}", file=sys.stderr)
        return 2
    except click.exceptions.Abort:
        print("error: interrupted", file=sys.stderr)
        return 130
    except click.exceptions.Exit as exc:
        return int(exc.exit_code)
    except click.ClickException as exc:
        print(f"error: {exc.format_message()}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("error: interrupted", file=sys.stderr)
        return 130
    return int(result) if isinstance(result, int) else 0


def run() -> None:
    """Console-script entry point."""
    sys.exit(main())
