"""One option vocabulary for every ``drillfatigue`` command.

The same thing has the same option name in every command, a short option means
the same everywhere it exists, and what a command writes is named ``--out``
(``-o``) or, for a second output, ``--out-<what>``: an input is never called
``--out...`` and an output never takes an input's name.

==========================================  ======================
thing                                       option
==========================================  ======================
file or folder the command writes           ``--out``, ``-o``
a second file it writes                     ``--out-<what>``
params file (``params.yaml``)               ``--params``, ``-p``
surrogate model folder                      ``--model``
well profile name                           ``--well-profile``
fatigue criterion                           ``--criterion``, ``-c``
worker processes                            ``--workers``
==========================================  ======================

Old spellings (:data:`OLD_SPELLINGS`) keep working for one release: before the
arguments are parsed, :func:`modernize_args` spells them the new way and prints
one line per old spelling on stderr (``drillfatigue: --surrogate is deprecated,
use --model``). They are not options of any command, so no help shows them.
"""

from __future__ import annotations

import sys
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import typer

from drillfatigue.errors import InputError

OUT = "--out"
OUT_SHORT = "-o"
PARAMS = "--params"
PARAMS_SHORT = "-p"
MODEL = "--model"
#: not ``--profile``: ``query`` takes a model's inputs as flags named after them, and a
#: surrogate trained on the design's ``well.profile`` has an input ``--profile``
PROFILE = "--well-profile"


def out_option(default: Any, help: str, what: str = "") -> Any:
    """The option of a file or folder the command writes: ``--out``/``-o``, or
    ``--out-WHAT`` (no short option) for a second output."""
    if what:
        return typer.Option(default, f"{OUT}-{what}", help=help)
    return typer.Option(default, OUT, OUT_SHORT, help=help)


def params_option(default: Path | None, help: str) -> Any:
    """``--params``/``-p``: the params file a command reads."""
    return typer.Option(default, PARAMS, PARAMS_SHORT, help=help)


def model_option(default: Any, help: str = "surrogate model folder") -> Any:
    """``--model``: a surrogate model folder (written by the train stage)."""
    return typer.Option(default, MODEL, help=help)


def profile_option(help: str) -> Any:
    """``--well-profile``: the name of a well profile (``well.profiles``)."""
    return typer.Option(None, PROFILE, help=help)


@dataclass(frozen=True)
class OldSpelling:
    """An option's spelling of an earlier release, still accepted for one release.

    ``command``: the commands it belongs to, as the words that call them
    (``"plan rank"``; ``"well"``: every ``well`` command; ``""``: every command).
    """

    command: str
    old: str
    new: str

    def applies_to(self, path: Sequence[str]) -> bool:
        words = self.command.split()
        return list(path[:len(words)]) == words


#: Old spellings: accepted in this release, removed in the next (CHANGELOG.md).
OLD_SPELLINGS: tuple[OldSpelling, ...] = (
    OldSpelling("", "--output", OUT),
    OldSpelling("well", "-p", PROFILE),
    OldSpelling("well", "--profile", PROFILE),
    OldSpelling("plan rank", "--surrogate", MODEL),
    OldSpelling("window", "--csv", f"{OUT}-csv"),
    OldSpelling("benchmark leaderboard", "--page", f"{OUT}-page"),
    OldSpelling("benchmark leaderboard", "--json", f"{OUT}-json"),
    OldSpelling("sweep run", "--n-workers", "--workers"),
    OldSpelling("ledger run start", "--well", "--well-name"),
)


def deprecation_line(old: str, new: str) -> str:
    """The one line printed on stderr when ``old`` is used."""
    return f"drillfatigue: {old} is deprecated, use {new}"


def _split(token: str, olds: set[str]) -> tuple[str, str | None] | None:
    """(old spelling, attached value or None) when ``token`` is an old spelling."""
    if token in olds:
        return token, None
    if token.startswith("--"):
        name, eq, value = token.partition("=")
        return (name, value) if eq and name in olds else None
    if len(token) > 2 and token[0] == "-" and token[:2] in olds:  # -pVALUE
        return token[:2], token[2:]
    return None


def modernize_args(args: list[str], get_root: Callable[[], Any],
                   warn: Callable[[str], None] | None = None) -> list[str]:
    """``args`` with the old spellings of their command spelled the new way.

    ``get_root``: returns the click command tree (``typer.main.get_command(app)``);
    called only when an old spelling may be present. ``warn`` gets one
    :func:`deprecation_line` per old spelling used (default: a line on stderr).
    The token after an option that takes a value is that value, copied as it is.
    An old and a new spelling of one option together is an InputError.
    """
    olds = {s.old for s in OLD_SPELLINGS}
    if not any(_split(a, olds) is not None for a in args):
        return args
    cmd = get_root()
    path: list[str] = []
    while getattr(cmd, "commands", None) is not None and len(path) < len(args) \
            and args[len(path)] in cmd.commands:
        cmd = cmd.commands[args[len(path)]]
        path.append(args[len(path)])
    if getattr(cmd, "commands", None) is not None:
        return args  # a group, not a command: nothing to spell
    options = [p for p in cmd.params if p.param_type_name == "option"]
    names_of = {n: set(p.opts) | set(p.secondary_opts) for p in options
                for n in (*p.opts, *p.secondary_opts)}
    takes_value = {n for p in options if not p.is_flag and not p.count
                   for n in (*p.opts, *p.secondary_opts)}
    # an old spelling applies where its command has the new option
    rules = {s.old: s for s in OLD_SPELLINGS if s.applies_to(path) and s.new in names_of}
    if not rules:
        return args
    out = list(args[:len(path)])
    used: dict[str, OldSpelling] = {}
    seen: set[str] = set()
    i = len(path)
    while i < len(args):
        tok = args[i]
        i += 1
        if tok == "--":
            out += args[i - 1:]
            break
        hit = _split(tok, set(rules))
        if hit is not None:
            rule = rules[hit[0]]
            used.setdefault(rule.old, rule)
            name, attached = rule.new, hit[1] is not None
            out.append(name if hit[1] is None else f"{name}={hit[1]}")
        else:
            out.append(tok)
            if tok.startswith("--"):
                name, eq, _ = tok.partition("=")
                attached = bool(eq)
            elif tok.startswith("-") and len(tok) >= 2:
                name, attached = tok[:2], len(tok) > 2
            else:
                continue  # an argument
            seen.add(name)
        if name in takes_value and not attached and i < len(args):
            out.append(args[i])  # the option's value, as written
            i += 1
    for rule in used.values():
        if seen & names_of[rule.new]:
            raise InputError(rule.new, f"given twice ({rule.new} and its old spelling "
                             f"{rule.old})", f"one {rule.new}")
    say = warn if warn is not None else (lambda line: print(line, file=sys.stderr))
    for rule in used.values():
        say(deprecation_line(rule.old, rule.new))
    return out
