"""mkdocs hook: the command-line reference page, generated from the typer application.

``docs/cli.md`` is not a file in the repository: it is written at build time
from the same click command tree that ``drillfatigue --help`` prints, so the
reference cannot drift from the code.
"""

from __future__ import annotations

from typing import Any

from mkdocs.structure.files import File, Files


def cli_reference_markdown() -> str:
    """Markdown reference of every ``drillfatigue`` command, option and argument."""
    import typer
    import typer.cli
    import typer.main

    from drillfatigue.cli import _load_commands
    from drillfatigue.cli.app import app

    _load_commands()
    command = typer.main.get_command(app)
    ctx = typer.Context(command)
    body = typer.cli.get_docs_for_click(obj=command, ctx=ctx, name="drillfatigue",
                                        title="Command line")
    intro = ("Generated from the command's own help at each docs build. Every command reports "
             "bad input as one line `error: <field>: <problem> (allowed: ...)` on stderr, exits "
             "with code 2 and writes nothing. The same thing has the same option in every "
             "command: a command writes to `--out` (`-o`), a second file to `--out-<what>`; "
             "`--model` is a surrogate model folder, `--well-profile` a well profile, `--params` "
             "(`-p`) the params file. Old spellings still work for one release and say so "
             "(CHANGELOG.md).\n\n")
    head, _, rest = body.partition("\n\n")
    return f"{head}\n\n{intro}{rest}"


def on_files(files: Files, config: Any, **kwargs: Any) -> Files:
    files.append(File.generated(config, "cli.md", content=cli_reference_markdown()))
    return files
