"""Command-line interface: ``drillfatigue <command> ...``.

Each command (or group of commands) lives in the module of this package named
after it and registers itself on :data:`drillfatigue.cli.app.app` when
imported. Option names follow one vocabulary (:mod:`drillfatigue.cli.vocabulary`);
old spellings are accepted for one release with a deprecation line. :func:`main` turns bad input
into one line ``error: <field>: <problem> (allowed: ...)`` on stderr and exit
code 2.
"""

from __future__ import annotations

import importlib
import sys

import click
import typer
import typer.main

from drillfatigue.cli.app import app
from drillfatigue.cli.vocabulary import modernize_args
from drillfatigue.errors import InputError, Interrupted
from drillfatigue.numba_cache import scope_numba_cache

# typer >= 0.16 carries its own copy of click: its usage errors, Exit and
# Abort are not the classes of the installed ``click`` package. Both are
# handled so that the CLI behaves the same with either.
_CLICK_ERRORS: tuple[type[Exception], ...] = (click.ClickException, typer.TyperException)
_EXIT: tuple[type[Exception], ...] = (click.exceptions.Exit, typer.Exit)
_ABORT: tuple[type[Exception], ...] = (click.exceptions.Abort, typer.Abort)

#: Exit code of an interrupted command (128 + SIGINT), as a shell reports it.
EXIT_INTERRUPTED = 130

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
    "drillfatigue.cli.dataset",
    "drillfatigue.cli.plan",
    "drillfatigue.cli.study",
    "drillfatigue.cli.serve",
    "drillfatigue.cli.window",
    "drillfatigue.cli.ledger",
    "drillfatigue.cli.benchmark",
)


def _load_commands(modules: tuple[str, ...] = COMMAND_MODULES) -> None:
    for name in modules:
        importlib.import_module(name)


def main(argv: list[str] | None = None, modules: tuple[str, ...] = COMMAND_MODULES) -> int:
    """Run the CLI; return the process exit code.

    ``modules``: the command modules to load (all by default; one group's
    ``python -m`` entry loads only its own).
    """
    scope_numba_cache()  # before the command modules import any kernel
    _load_commands(modules)
    try:
        args = modernize_args(list(sys.argv[1:] if argv is None else argv),
                              lambda: typer.main.get_command(app))
        result = app(args=args, standalone_mode=False)
    except InputError as exc:
        print(f"error: {exc.one_line()}", file=sys.stderr)
        return 2
    except Interrupted as exc:
        print(f"error: interrupted: {exc}", file=sys.stderr)
        return EXIT_INTERRUPTED
    except _ABORT:
        print("error: interrupted", file=sys.stderr)
        return EXIT_INTERRUPTED
    except _EXIT as exc:
        return int(exc.exit_code)  # type: ignore[attr-defined]
    except _CLICK_ERRORS as exc:
        text = exc.format_message() if hasattr(exc, "format_message") else str(exc)
        if type(exc).__name__ == "NoArgsIsHelpError":
            # a group called without a command: its help is the answer
            print(text)
            return 2
        # usage errors (unknown option, missing argument, bad value) as one line
        print(f"error: {' '.join(str(text).split())}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("error: interrupted", file=sys.stderr)
        return EXIT_INTERRUPTED
    if result == EXIT_INTERRUPTED:
        # typer turns Ctrl-C into a silent exit code 130; say what happened
        print("error: interrupted", file=sys.stderr)
    return int(result) if isinstance(result, int) else 0


def run() -> None:
    """Console-script entry point."""
    sys.exit(main())
