"""One option vocabulary across the ``drillfatigue`` commands (drillfatigue.cli.vocabulary).

The same thing has the same option name in every command, a short option means
one thing, an output is named ``--out`` (``-o``) or ``--out-<what>`` and an
input never is, each command lives in ``cli/<command>.py``; the old spellings
still work for one release, with one deprecation line.
"""

from __future__ import annotations

import os
import re
import subprocess
import sys
from pathlib import Path
from typing import Any

import pytest
import typer.main

from drillfatigue.cli import COMMAND_MODULES, _load_commands, main
from drillfatigue.cli.app import app
from drillfatigue.cli.vocabulary import OLD_SPELLINGS, OldSpelling, deprecation_line, modernize_args

ROOT = Path(__file__).resolve().parents[3]

#: a thing several commands take -> (its option, how its help names it)
CONCEPTS: dict[str, tuple[str, str]] = {
    "surrogate model folder": ("--model", r"\bmodel folder\b"),
    "well profile": ("--well-profile", r"^profile\b"),
    "params file": ("--params", r"^params(\.yaml| file)\b"),
    "worker processes": ("--workers", r"\bworker processes\b"),
    "fatigue criterion": ("--criterion", r"^fatigue criterion\b"),
}
#: a help that says the option is written to: the option is an output
WRITES = re.compile(r"\b(write|writes|written|output)\b")


# typer ships its own copy of click: duck-typed, not isinstance(click.*)
def _commands(cmd: Any, path: str = "drillfatigue") -> list[tuple[str, Any]]:
    found = [(path, cmd)]
    if hasattr(cmd, "commands"):
        for name, sub in cmd.commands.items():
            found += _commands(sub, f"{path} {name}")
    return found


def _root() -> Any:
    _load_commands()
    return typer.main.get_command(app)


def _leaves() -> list[tuple[str, Any]]:
    return [(p, c) for p, c in _commands(_root()) if not hasattr(c, "commands")]


def _options() -> list[tuple[str, Any]]:
    """(command path, option) of every option shown in a help."""
    return [(path, p) for path, cmd in _leaves() for p in cmd.params
            if p.param_type_name == "option" and not p.hidden
            and not set(p.opts) & {"--help", "-h"}]


def _long(param: Any) -> list[str]:
    return [n for n in (*param.opts, *param.secondary_opts) if n.startswith("--")]


def _short(param: Any) -> list[str]:
    return [n for n in (*param.opts, *param.secondary_opts) if not n.startswith("--")]


def test_every_output_option_is_spelled_out() -> None:
    outputs: dict[str, Any] = {}
    options = _options()
    for path, param in options:
        names = set(param.opts) | set(param.secondary_opts)
        assert not names & {"--output", "--output-dir", "--out-dir", "--outdir"}, path
        if "--out" in names:
            outputs[path] = param
    assert len(options) > 20  # the walk saw the options
    # every command that writes a file or folder takes it as --out
    for path in ("drillfatigue simulate", "drillfatigue fatigue", "drillfatigue tnd",
                 "drillfatigue well plot", "drillfatigue well export", "drillfatigue twin replay",
                 "drillfatigue plan rank", "drillfatigue query", "drillfatigue window",
                 "drillfatigue study", "drillfatigue string import",
                 "drillfatigue benchmark leaderboard", "drillfatigue ledger export"):
        assert path in outputs, path


def test_every_out_has_o_and_o_is_only_out() -> None:
    for path, param in _options():
        names = set(param.opts) | set(param.secondary_opts)
        assert ("--out" in names) == ("-o" in names), (path, sorted(names))


def test_a_short_option_means_one_thing() -> None:
    """A short option stands for one long option in every command, and a long option has
    the same short option (or none) in every command."""
    long_of: dict[str, set[str]] = {}
    short_of: dict[str, set[tuple[str, ...]]] = {}
    for _, param in _options():
        for s in _short(param):
            long_of.setdefault(s, set()).update(_long(param))
        for n in _long(param):
            short_of.setdefault(n, set()).add(tuple(sorted(_short(param))))
    assert {"-o", "-p"} <= set(long_of)
    bad = {s: sorted(longs) for s, longs in long_of.items() if len(longs) != 1}
    assert not bad, bad
    mixed = {n: sorted(shorts) for n, shorts in short_of.items() if len(shorts) != 1}
    assert not mixed, mixed


@pytest.mark.parametrize("concept", sorted(CONCEPTS))
def test_the_same_thing_has_the_same_name(concept: str) -> None:
    """Every option whose help names the thing is its canonical option, and the canonical
    option's help names it."""
    option, pattern = CONCEPTS[concept]
    seen = 0
    for path, param in _options():
        about = re.search(pattern, param.help or "") is not None
        named = option in _long(param)
        assert about == named, (concept, path, _long(param), param.help)
        seen += named
    assert seen >= 2, concept  # a thing several commands take


def test_inputs_and_outputs_never_share_a_name() -> None:
    """An output is ``--out`` or ``--out-<what>`` (its help says it is written); an option
    that is not an output never has such a name or such a help."""
    role: dict[str, set[str]] = {}
    for path, param in _options():
        longs = _long(param)
        is_out = any(n == "--out" or n.startswith("--out-") for n in longs)
        assert len(longs) == 1 or param.is_flag, (path, longs)
        if is_out:
            assert not param.is_flag, (path, longs)
        else:
            # a flag may say what it makes a command write ("--json: print ..."); a value
            # option whose help says it is written is an output and must be named so
            assert param.is_flag or not WRITES.search(param.help or ""), (path, longs,
                                                                           param.help)
        for n in longs:
            role.setdefault(n, set()).add("output" if is_out else "input")
    both = {n for n, r in role.items() if len(r) > 1}
    assert not both, both
    assert {"--out", "--out-csv", "--out-page", "--out-json"} <= set(role)


def test_each_command_lives_in_the_module_named_after_it() -> None:
    modules = {m.rsplit(".", 1)[1] for m in COMMAND_MODULES}
    tops: set[str] = set()
    for path, cmd in _leaves():
        top = path.split()[1]
        tops.add(top)
        assert cmd.callback.__module__ == f"drillfatigue.cli.{top}", (path, cmd.callback.__module__)
        assert (ROOT / "src" / "drillfatigue" / "cli" / f"{top}.py").is_file(), path
    assert tops == modules  # one module per command (or group), each registered
    assert {"window", "study", "dataset"} <= tops


def test_a_group_keeps_its_subcommands_when_loaded_alone() -> None:
    """`python -m drillfatigue.cli.ledger` loads the ledger module only: `ledger` stays a
    group of subcommands (typer makes an app of one command that command), and its old
    spellings are spelled the new way there too."""
    src = str(ROOT / "src")
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(filter(None, [src, os.environ.get(
        "PYTHONPATH")])))
    proc = subprocess.run([sys.executable, "-m", "drillfatigue.cli.ledger", "run", "start",
                           "R", "--well", "W", "--help"], env=env, capture_output=True,
                          text=True, timeout=120)
    assert proc.returncode == 0, proc.stderr
    assert proc.stderr == "drillfatigue: --well is deprecated, use --well-name\n"
    assert "--well-name" in proc.stdout
    root = _root()
    for group in ("well", "string", "twin", "sweep", "dataset", "plan", "ledger", "benchmark"):
        assert hasattr(root.commands[group], "commands"), group
    for command in ("window", "study", "serve", "query", "fatigue", "simulate", "tnd"):
        assert not hasattr(root.commands[command], "commands"), command


def _applies(rule: OldSpelling) -> list[tuple[list[str], Any]]:
    """The commands (argv prefix, click command) that take ``rule.new``."""
    return [(path.split()[1:], cmd) for path, cmd in _leaves()
            if rule.applies_to(path.split()[1:])
            and any(rule.new in p.opts for p in cmd.params)]


def test_old_spellings_name_options_that_exist_and_are_no_option_now() -> None:
    assert len({(r.command, r.old) for r in OLD_SPELLINGS}) == len(OLD_SPELLINGS)
    for rule in OLD_SPELLINGS:
        found = _applies(rule)
        assert found, rule
        for _, cmd in found:
            names = {n for p in cmd.params for n in (*p.opts, *p.secondary_opts)}
            assert rule.old not in names, rule


@pytest.mark.parametrize("rule", OLD_SPELLINGS, ids=lambda r: f"{r.command or '*'} {r.old}")
def test_an_old_spelling_is_spelled_the_new_way_with_one_line(rule: OldSpelling) -> None:
    for path, cmd in _applies(rule):
        lines: list[str] = []
        new = modernize_args([*path, "ARG", rule.old, "VALUE"], _root, warn=lines.append)
        assert new == [*path, "ARG", rule.new, "VALUE"], (path, new)
        assert lines == [deprecation_line(rule.old, rule.new)]
        # the value of an option is never taken for an option
        other = [p.opts[0] for p in cmd.params if p.param_type_name == "option"
                 and not p.is_flag and rule.new not in p.opts]
        if other:
            args = [*path, other[0], rule.old]
            assert modernize_args(args, _root, warn=lines.append) == args
        attached = f"{rule.old}=V" if rule.old.startswith("--") else f"{rule.old}V"
        assert modernize_args([*path, attached], _root, warn=lines.append) == \
            [*path, f"{rule.new}=V"]


@pytest.mark.parametrize("rule", OLD_SPELLINGS, ids=lambda r: f"{r.command or '*'} {r.old}")
def test_an_old_spelling_is_accepted_by_the_command(rule: OldSpelling, capsys) -> None:  # type: ignore[no-untyped-def]
    """Through ``main``: the command parses the old spelling (an unknown option would be a
    usage error, exit 2, before --help) and says once that it is deprecated."""
    path = _applies(rule)[0][0]
    assert main([*path, rule.old, "VALUE", "--help"]) == 0
    err = capsys.readouterr().err
    assert err == deprecation_line(rule.old, rule.new) + "\n"


def test_old_and_new_spelling_together_is_one_error(capsys) -> None:  # type: ignore[no-untyped-def]
    assert main(["plan", "rank", "c.yaml", "--surrogate", "a", "--model", "b"]) == 2
    err = capsys.readouterr().err
    assert err == "error: --model: given twice (--model and its old spelling --surrogate) " \
                  "(allowed: one --model)\n"


def test_no_old_spelling_no_change() -> None:
    args = ["well", "export", "case.yaml", "--well-profile", "p", "-o", "p.csv"]
    assert modernize_args(args, lambda: pytest.fail("tree built without an old spelling")) \
        is args


def test_well_profile_old_spellings_behave_as_the_new_one(tmp_path: Path, monkeypatch,  # type: ignore[no-untyped-def]
                                                          capsys) -> None:
    case = ROOT / "params.yaml"
    monkeypatch.chdir(tmp_path)
    assert main(["well", "show", str(case), "--well-profile", "profile_2"]) == 0
    new = capsys.readouterr()
    assert "'profile_2'" in new.out and new.err == ""
    for old_spelling in ("-p", "--profile"):
        assert main(["well", "show", str(case), old_spelling, "profile_2"]) == 0
        old = capsys.readouterr()
        assert old.out == new.out
        assert old.err == f"drillfatigue: {old_spelling} is deprecated, use --well-profile\n"


def test_plan_rank_old_model_option_behaves_as_model(tmp_path: Path, monkeypatch,  # type: ignore[no-untyped-def]
                                                     capsys) -> None:
    candidates = ROOT / "data" / "plans" / "case2_candidates.yaml"
    monkeypatch.chdir(tmp_path)
    for spelling in ("--model", "--surrogate"):
        assert main(["plan", "rank", str(candidates), spelling, "nope", "--out", "r"]) == 2
    err = capsys.readouterr().err.splitlines()
    assert err == ["error: --model: folder 'nope' not found (allowed: a model folder written "
                   "by the train stage)",
                   "drillfatigue: --surrogate is deprecated, use --model",
                   "error: --model: folder 'nope' not found (allowed: a model folder written "
                   "by the train stage)"]
    assert list(tmp_path.iterdir()) == []
