"""The stage scripts' shared command line (drillfatigue.stage.stage_main)."""

from __future__ import annotations

from argparse import Namespace
from pathlib import Path
from typing import Any

import pytest

from drillfatigue.errors import InputError
from drillfatigue.files import OutputFolder
from drillfatigue.stage import NO_PROGRESS, Option, stage_main
from drillfatigue.sweep.runner import SweepFailedError

DOC = """DVC stage ``probe``: a stand-in.

More text that --help does not show.
"""


def _params(tmp_path: Path, text: str = "{}\n") -> Path:
    path = tmp_path / "params.yaml"
    path.write_text(text, encoding="utf-8")
    return path


def test_the_stage_gets_the_loaded_params_and_options_and_its_line_is_printed(
        tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    seen: list[Any] = []

    def stage(params: Any, args: Namespace) -> str:
        seen.append((params, args))
        return f"probe: {args.n_workers} workers, progress {not args.no_progress}"

    options = (Option("--n-workers", type=int, default=3), NO_PROGRESS)
    assert stage_main(DOC, stage, options, ["--params", str(_params(tmp_path)), "--no-progress"],
                      load=lambda path: {"path": path}) == 0
    assert capsys.readouterr().out == "probe: 3 workers, progress False\n"
    (params, args), = seen
    assert params == {"path": str(tmp_path / "params.yaml")}
    assert args.no_progress is True and args.n_workers == 3


def test_the_default_loader_validates_the_params_file(
        tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    path = _params(tmp_path, "sweep:\n  n_cases: 0\n")
    assert stage_main(DOC, lambda p, a: "never", (), ["--params", str(path)]) == 2
    err = capsys.readouterr().err
    assert err.startswith("error: sweep.n_cases: ") and err.count("\n") == 1


def test_input_error_of_the_stage_is_one_line_exit_2(
        tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    def stage(params: Any, args: Namespace) -> None:
        raise InputError("--data", "file not found", "an existing file")

    assert stage_main(DOC, stage, (), ["--params", str(_params(tmp_path))]) == 2
    assert capsys.readouterr().err == "error: --data: file not found (allowed: an existing file)\n"


def test_a_failed_sweep_is_exit_1_and_other_errors_propagate(
        tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    argv = ["--params", str(_params(tmp_path))]

    def failed(params: Any, args: Namespace) -> None:
        raise SweepFailedError("3 of 4 cases failed")

    assert stage_main(DOC, failed, (), argv) == 1
    assert capsys.readouterr().err == "error: 3 of 4 cases failed\n"

    def broken(params: Any, args: Namespace) -> None:
        raise RuntimeError("a bug")

    with pytest.raises(RuntimeError, match="a bug"):
        stage_main(DOC, broken, (), argv)


def test_an_output_folder_option_is_checked_before_the_params_are_read(
        tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    plots = tmp_path / "plots"
    plots.mkdir()
    (plots / "mine.png").write_bytes(b"user data")
    options = (Option("--plots", default=str(plots), folder="evaluation"),)
    loaded: list[str] = []
    code = stage_main(DOC, lambda p, a: None, options, ["--params", str(tmp_path / "none.yaml")],
                      load=loaded.append)
    assert code == 2 and loaded == []
    err = capsys.readouterr().err
    assert err.startswith("error: --plots: ") and err.count("\n") == 1
    OutputFolder(tmp_path / "ours", "evaluation")  # a folder of the kind is accepted
    assert stage_main(DOC, lambda p, a: None, options,
                      ["--params", str(_params(tmp_path)), "--plots", str(tmp_path / "ours")],
                      load=loaded.append) == 0
    assert loaded == [str(tmp_path / "params.yaml")]


def test_help_shows_the_first_line_of_the_docstring(capsys: pytest.CaptureFixture[str]) -> None:
    with pytest.raises(SystemExit) as exc:
        stage_main(DOC, lambda p, a: None, (), ["--help"])
    assert exc.value.code == 0
    out = capsys.readouterr().out
    assert "DVC stage ``probe``: a stand-in." in out and "More text" not in out
    assert "--params" in out
