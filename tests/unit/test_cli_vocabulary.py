"""One option vocabulary across the ``drillfatigue`` commands."""

from __future__ import annotations

from typing import Any

import typer.main

from drillfatigue.cli import _load_commands
from drillfatigue.cli.app import app


# typer ships its own copy of click: duck-typed, not isinstance(click.*)
def _commands(cmd: Any, path: str = "drillfatigue") -> list[tuple[str, Any]]:
    found = [(path, cmd)]
    if hasattr(cmd, "commands"):
        for name, sub in cmd.commands.items():
            found += _commands(sub, f"{path} {name}")
    return found


def test_every_output_option_is_spelled_out() -> None:
    _load_commands()
    root = typer.main.get_command(app)
    outputs: dict[str, Any] = {}
    n_options = 0
    for path, cmd in _commands(root):
        for param in cmd.params:
            if param.param_type_name == "option" and not param.hidden:
                n_options += 1
                names = set(param.opts) | set(param.secondary_opts)
                assert not names & {"--output", "--output-dir", "--out-dir", "--outdir"}, path
                if "--out" in names:
                    outputs[path] = param
    assert n_options > 20  # the walk saw the options
    # every command that writes a file or folder takes it as --out
    for path in ("drillfatigue simulate", "drillfatigue fatigue", "drillfatigue tnd",
                 "drillfatigue well plot", "drillfatigue well export", "drillfatigue twin replay",
                 "drillfatigue plan rank", "drillfatigue query"):
        assert path in outputs, path
