"""The command line every ``pipeline/*.py`` stage script shares.

A stage script is its stage function plus a two-line ``main``::

    def main(argv: list[str] | None = None) -> int:
        return stage_main(__doc__, wells, OPTIONS, argv)

:func:`stage_main` parses ``--params`` and the stage's own options, checks the
output folders they name, loads the params file, calls the stage function and
prints the line it returns. Bad input (a bad params file, a missing input, a
folder holding files drillfatigue did not write) is one line ``error: <field>:
...`` on stderr and exit code 2, before the stage writes anything; a sweep
with more failed cases than ``sweep.failure_threshold`` is exit code 1.
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

from drillfatigue.config import load_params
from drillfatigue.errors import InputError
from drillfatigue.files import OutputFolder

#: A stage function: the loaded params and the parsed options in, the line to
#: print (or None) out.
Stage = Callable[[Any, argparse.Namespace], str | None]


@dataclass(frozen=True)
class Option:
    """One command-line option of a stage script besides ``--params``.

    ``switch`` makes it a flag (``store_true``); ``folder`` names the kind of
    output folder the option's value is (:class:`drillfatigue.files.OutputFolder`):
    a folder holding anything else is refused before the params are read.
    """

    flag: str
    default: Any = None
    help: str | None = None
    type: Callable[[str], Any] = str
    switch: bool = False
    folder: str | None = None

    def add_to(self, parser: argparse.ArgumentParser) -> None:
        if self.switch:
            parser.add_argument(self.flag, action="store_true", help=self.help)
        else:
            parser.add_argument(self.flag, default=self.default, help=self.help, type=self.type)


#: ``--no-progress``: no progress bars.
NO_PROGRESS = Option("--no-progress", switch=True, help="no progress bars")

#: The options of the stages that run a sweep of cases.
SWEEP_OPTIONS = (Option("--scheduler", help="override sweep.scheduler"),
                 Option("--n-workers", type=int, help="override sweep.n_workers"),
                 NO_PROGRESS,
                 Option("--metrics", help="also write the sweep report here (JSON)"))


def stage_main(doc: str | None, stage: Stage, options: Sequence[Option] = (),
               argv: list[str] | None = None, *,
               load: Callable[[str], Any] = load_params) -> int:
    """Run ``stage`` as a command line; return the exit code.

    Parameters
    ----------
    doc : str
        The script's docstring; its first line is the ``--help`` description.
    stage : callable
        ``stage(params, args)``: ``params`` is what ``load`` returned for
        ``--params`` (by default the validated :class:`drillfatigue.config.Params`),
        ``args`` the parsed options. Its return value, when not None, is printed.
    options : sequence of Option
        The stage's options besides ``--params`` (default ``params.yaml``).
    argv : list of str, optional
        The arguments (default: ``sys.argv[1:]``).
    load : callable, optional
        Reads and validates the params file.
    """
    parser = argparse.ArgumentParser(description=(doc or "").strip().splitlines()[0])
    parser.add_argument("--params", default="params.yaml")
    for option in options:
        option.add_to(parser)
    args = parser.parse_args(argv)
    try:
        for option in options:
            value = getattr(args, option.flag.lstrip("-").replace("-", "_"))
            if option.folder is not None and value is not None:
                OutputFolder.check(value, option.folder, option.flag)
        message = stage(load(args.params), args)
    except InputError as exc:
        print(f"error: {exc.one_line()}", file=sys.stderr)
        return 2
    except RuntimeError as exc:
        if not _sweep_failed(exc):
            raise
        print(f"error: {exc}", file=sys.stderr)
        return 1
    if message is not None:
        print(message)
    return 0


def _sweep_failed(exc: BaseException) -> bool:
    """Whether ``exc`` is the sweep engine's :class:`~drillfatigue.sweep.runner.SweepFailedError`.

    Only a stage that imported the engine can raise one: the stages that run no
    sweep are spared its import.
    """
    runner = sys.modules.get("drillfatigue.sweep.runner")
    return runner is not None and isinstance(exc, runner.SweepFailedError)
