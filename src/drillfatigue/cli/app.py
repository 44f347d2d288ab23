"""The typer application object shared by every CLI command module."""

from __future__ import annotations

import typer

from drillfatigue.errors import InputError

app = typer.Typer(
    name="drillfatigue",
    help="Drill-string dynamics and fatigue: simulate, count cycles, estimate life.",
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_enable=False,
)


#: ``--output``: the spelling some commands (``well plot``, ``well export``, ``tnd``)
#: used before every command took ``--out``; still accepted, never shown in the help.
LEGACY_OUT = "--output"


def legacy_out_args(args: list[str]) -> list[str]:
    """``args`` with ``--output X`` / ``--output=X`` spelled ``--out``.

    Done before parsing, so that a command's ``--out`` can be a required option
    (shown so in its help) and the old spelling still fills it. Both spellings
    at once is an InputError.
    """
    head, sep, tail = (args, [], []) if "--" not in args else (
        args[:args.index("--")], ["--"], args[args.index("--") + 1:])
    old = [a for a in head if a == LEGACY_OUT or a.startswith(LEGACY_OUT + "=")]
    if not old:
        return args
    if any(a in ("--out", "-o") or a.startswith("--out=") for a in head):
        raise InputError("--out", "given twice (--out and its old spelling --output)", "one --out")
    new = ["--out" + a[len(LEGACY_OUT):] if a in old else a for a in head]
    return new + sep + tail
