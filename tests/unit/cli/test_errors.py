"""Bad input through the CLI: one line ``error: <field>: ...`` on stderr, exit 2, no output."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

import drillfatigue
from drillfatigue.cli import main

GOOD_CSV = "md_m,inc_deg,azi_deg\n0,0,0\n100,0,0\n200,10,45\n"


def _survey_case(csv_text: str) -> tuple[str, dict[str, str]]:
    case = "well:\n  profiles:\n    f: {kind: survey_file, path: s.csv}\n"
    return case, {"s.csv": csv_text}


# (id, case YAML text or None for no file, extra files, extra CLI args, expected field prefix,
#  a word the message must contain)
CASES = [
    ("missing_file", None, {}, [], "case.yaml", "not found"),
    ("yaml_syntax", "well: [1, 2\n", {}, [], "case.yaml", "YAML syntax"),
    ("top_level_list", "- 1\n- 2\n", {}, [], "case.yaml", "mapping"),
    ("unknown_top_key", "wel: {}\n", {}, [], "wel", "unknown key"),
    ("unknown_nested_key", "well:\n  min_clearence_m: 0.02\n", {}, [],
     "well.min_clearence_m", "unknown key"),
    ("wrong_type", "well:\n  min_clearance_m: abc\n", {}, [], "well.min_clearance_m",
     "number"),
    ("profiles_not_mapping", "well:\n  profiles: [a, b]\n", {}, [], "well.profiles",
     "dictionary"),
    ("inc_out_of_range",
     "well:\n  profiles:\n    p: {kind: j, inc_deg: 200}\n", {}, [],
     "well.profiles.p.j.inc_deg", "180"),
    ("negative_dls",
     "well:\n  profiles:\n    p: {kind: build_horizontal, dls_deg_per_30m: -2}\n", {}, [],
     "well.profiles.p.build_horizontal.dls_deg_per_30m", "greater than 0"),
    ("azimuth_360",
     "well:\n  profiles:\n    p: {kind: j, azi_deg: 360}\n", {}, [],
     "well.profiles.p.j.azi_deg", "360"),
    ("hole_too_small", "well:\n  hole: [{md_top_m: 0, diameter_m: 0.01}]\n", {}, [],
     "well.hole[0].diameter_m", "0.05"),
    ("hole_smaller_than_clearance", "well:\n  min_clearance_m: 0.2\n", {}, [],
     "well.min_clearance_m", "too small"),
    ("hole_sections_unordered",
     "well:\n  hole: [{md_top_m: 0, diameter_m: 0.3}, {md_top_m: 0, diameter_m: 0.2}]\n",
     {}, [], "well.hole", "increasing"),
    ("unknown_profile_kind", "well:\n  profiles:\n    p: {kind: helix}\n", {}, [],
     "well.profiles.p", "tag"),
    ("profile_not_defined", "well:\n  profile: profile_9\n", {}, [], "well.profile",
     "not defined"),
    ("cli_profile_not_defined", "well: {}\n", {}, ["--well-profile", "nope"], "--well-profile",
     "not defined"),
    ("s_shape_drop_above_build",
     "well:\n  profiles:\n    p: {kind: s_shape, inc_deg: 30, final_inc_deg: 35}\n", {}, [],
     "well.profiles.p.s_shape.final_inc_deg", "smaller"),
    ("j_td_before_end_of_build",
     "well:\n  profiles:\n    p: {kind: j, kop_m: 900, td_m: 950}\n", {}, [],
     "well.profiles.p.td_m", "build"),
    ("family_cannot_land",
     "well:\n  profiles:\n    p: {kind: family_member, member: 2, kop_m: 800}\n", {}, [],
     "well.profiles.p.kop_m", "lands"),
    ("survey_missing_file", "well:\n  profiles:\n    f: {kind: survey_file, path: no.csv}\n",
     {}, [], "no.csv", "not found"),
    ("survey_missing_column", *_survey_case("md_m,inc_deg\n0,0\n10,1\n"), [], "s.csv:1",
     "azi_deg"),
    ("survey_nan", *_survey_case("md_m,inc_deg,azi_deg\n0,0,0\n10,NaN,0\n"), [],
     "s.csv:3:inc_deg", "finite"),
    ("survey_md_not_increasing", *_survey_case("md_m,inc_deg,azi_deg\n0,0,0\n10,1,0\n5,2,0\n"),
     [], "s.csv:4:md_m", "increasing"),
    ("survey_inclination_200", *_survey_case("md_m,inc_deg,azi_deg\n0,0,0\n10,200,0\n"), [],
     "s.csv:3:inc_deg", "0 <= inc_deg <= 180"),
    ("survey_md_1e300", *_survey_case("md_m,inc_deg,azi_deg\n0,0,0\n100,0,0\n1e300,10,45\n"),
     [], "s.csv:4:md_m", "0 <= md_m <= 20000"),
    ("survey_md_negative", *_survey_case("md_m,inc_deg,azi_deg\n-5,0,0\n100,0,0\n"),
     [], "s.csv:2:md_m", "0 <= md_m"),
    ("empty_case_file", "", {}, [], "case.yaml", "empty"),
    ("comments_only_case_file", "# nothing here\n", {}, [], "case.yaml", "empty"),
]


def _run(tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture,
         case_text: str | None, files: dict[str, str], args: list[str],
         command: str = "plot", out_name: str = "fig.png") -> tuple[int, str, str]:
    monkeypatch.chdir(tmp_path)
    if case_text is not None:
        (tmp_path / "case.yaml").write_text(case_text)
    for name, text in files.items():
        (tmp_path / name).write_text(text)
    before = set(os.listdir(tmp_path))
    rc = main(["well", command, "case.yaml", "-o", out_name, *args])
    out, err = capsys.readouterr()
    assert set(os.listdir(tmp_path)) == before, "an output file was written"
    return rc, out, err


@pytest.mark.parametrize(("case_text", "files", "args", "field", "word"),
                         [c[1:] for c in CASES], ids=[c[0] for c in CASES])
def test_bad_input_gives_one_line_and_exit_2(tmp_path, monkeypatch, capsys, case_text, files,
                                             args, field, word) -> None:
    rc, out, err = _run(tmp_path, monkeypatch, capsys, case_text, files, args)
    assert rc == 2
    lines = err.splitlines()
    assert len(lines) == 1, err
    assert lines[0].startswith(f"error: {field}: "), lines[0]
    assert word in lines[0]
    assert "Traceback" not in err and out == ""


def test_there_are_at_least_15_distinct_bad_inputs() -> None:
    assert len({c[0] for c in CASES}) >= 15


@pytest.mark.parametrize(("out_name", "word"), [("fig.txt", ".txt"),
                                                ("missing_dir/fig.png", "does not exist")])
def test_bad_output_path(tmp_path, monkeypatch, capsys, out_name, word) -> None:
    rc, _, err = _run(tmp_path, monkeypatch, capsys, "well: {}\n", {}, [], out_name=out_name)
    assert rc == 2
    assert err.startswith("error: --out: ") and err.count("\n") == 1 and word in err


def test_export_writes_nothing_on_bad_survey(tmp_path, monkeypatch, capsys) -> None:
    case, files = _survey_case("md_m,inc_deg,azi_deg\n0,0,0\n10,1,0\n5,2,0\n")
    rc, _, err = _run(tmp_path, monkeypatch, capsys, case, files, [], command="export",
                      out_name="out.csv")
    assert rc == 2 and err.startswith("error: s.csv:4:md_m")


def test_subprocess_exit_code_2(tmp_path: Path) -> None:
    (tmp_path / "case.yaml").write_text("well:\n  profiles:\n    p: {kind: j, inc_deg: 200}\n")
    src = str(Path(drillfatigue.__file__).resolve().parents[1])
    env = dict(os.environ, PYTHONPATH=src + os.pathsep + os.environ.get("PYTHONPATH", ""))
    proc = subprocess.run([sys.executable, "-m", "drillfatigue", "well", "plot", "case.yaml",
                           "-o", "fig.png"], cwd=tmp_path, env=env, capture_output=True,
                          text=True, timeout=120)
    assert proc.returncode == 2
    assert proc.stderr.splitlines() == [proc.stderr.strip()]
    assert proc.stderr.startswith("error: well.profiles.p.j.inc_deg: ")
    assert not (tmp_path / "fig.png").exists()


def _all_command_paths() -> list[list[str]]:
    """Every leaf command of the CLI as its argv prefix (``['well', 'show']``, ...)."""
    import typer

    from drillfatigue.cli import _load_commands
    from drillfatigue.cli.app import app

    _load_commands()
    paths: list[list[str]] = []

    def walk(cmd, prefix: list[str]) -> None:  # noqa: ANN001
        subs = getattr(cmd, "commands", None)
        if subs:
            for name, sub in subs.items():
                walk(sub, [*prefix, name])
        else:
            paths.append(prefix)

    walk(typer.main.get_command(app), [])
    return paths


def test_every_command_is_checked() -> None:
    names = {" ".join(p) for p in _all_command_paths()}
    assert {"well show", "simulate", "fatigue", "query", "twin replay", "plan rank",
            "sweep run", "dataset export", "tnd"} <= names


@pytest.mark.parametrize("path", _all_command_paths(), ids=" ".join)
def test_unknown_option_is_one_line_exit_2(tmp_path, monkeypatch, capsys, path) -> None:
    """typer's usage error (its own copy of click) is one line, not a traceback, exit 2."""
    monkeypatch.chdir(tmp_path)
    rc = main([*path, "--no-such-option-xyz", "1"])
    out, err = capsys.readouterr()
    assert rc == 2
    assert len(err.splitlines()) == 1, err
    assert err.startswith("error: ") and "Traceback" not in err
    assert os.listdir(tmp_path) == []


def test_well_show_unknown_out_option(tmp_path, monkeypatch, capsys) -> None:
    (tmp_path / "case.yaml").write_text("well: {}\n")
    monkeypatch.chdir(tmp_path)
    assert main(["well", "show", "case.yaml", "--out", "DIR"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("error: No such option: --out") and err.count("\n") == 1
    assert not (tmp_path / "DIR").exists()


def test_unknown_option_subprocess_exit_2(tmp_path: Path) -> None:
    src = str(Path(drillfatigue.__file__).resolve().parents[1])
    env = dict(os.environ, PYTHONPATH=src + os.pathsep + os.environ.get("PYTHONPATH", ""))
    proc = subprocess.run([sys.executable, "-m", "drillfatigue", "tnd", "case.yaml",
                           "--cell-m", "abc"], cwd=tmp_path, env=env, capture_output=True,
                          text=True, timeout=120)
    assert proc.returncode == 2
    assert len(proc.stderr.splitlines()) == 1 and proc.stderr.startswith("error: ")
    assert "--cell-m" in proc.stderr


@pytest.mark.parametrize("which", ["case", "survey"])
def test_non_utf8_file_is_one_line(tmp_path, monkeypatch, capsys, which) -> None:
    """A Latin-1 YAML or a UTF-16 survey: one line naming the file and the byte."""
    monkeypatch.chdir(tmp_path)
    if which == "case":
        (tmp_path / "case.yaml").write_bytes("well:\n  min_clearance_m: 0.02 # caf\xe9\n"
                                             .encode("latin-1"))
        field = "case.yaml"
    else:
        (tmp_path / "case.yaml").write_text(_survey_case("")[0])
        (tmp_path / "s.csv").write_bytes(GOOD_CSV.encode("utf-16"))
        field = "s.csv"
    assert main(["well", "show", "case.yaml"]) == 2
    out, err = capsys.readouterr()
    assert out == "" and err.count("\n") == 1, err
    assert err.startswith(f"error: {field}: not ") and "UTF-8" in err


@pytest.mark.parametrize("command", ["plot", "export", "tnd"])
def test_output_file_that_is_a_folder(tmp_path, monkeypatch, capsys, command) -> None:
    """`-o NAME` where NAME is an existing folder: one line, exit 2, folder untouched."""
    monkeypatch.chdir(tmp_path)
    (tmp_path / "case.yaml").write_text("well: {}\n")
    name = "out.csv" if command == "export" else "fig.png"
    (tmp_path / name).mkdir()
    (tmp_path / name / "mine.txt").write_text("x")
    argv = ["tnd", "case.yaml", "-o", name] if command == "tnd" else \
        ["well", command, "case.yaml", "-o", name]
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert err == f"error: --out: {name} is a folder, not a file (allowed: a file path)\n"
    assert os.listdir(tmp_path / name) == ["mine.txt"]


def test_tnd_refuses_more_weight_on_bit_than_the_string_can_give(tmp_path, monkeypatch,
                                                                 capsys) -> None:
    """Soft string: the drilling hook load falls one to one with the WOB (the hook load is
    the rotating off-bottom tension less the WOB), so the largest WOB the string can give
    is the WOB at which it reaches zero; a larger --wob-kN is one line naming that bound,
    exit 2, no plot written. The bound read from the message agrees with a WOB inside it."""
    import json

    monkeypatch.chdir(tmp_path)
    case = Path(drillfatigue.__file__).resolve().parents[2] / "data" / "cases" / "case2_profile.yaml"
    assert main(["tnd", str(case), "--wob-kN", "600", "-o", "td.png"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("error: --wob-kN: 600 kN would need a drilling hook load of -")
    assert err.count("\n") == 1 and not (tmp_path / "td.png").exists()
    most = float(err.split("wob_kN <= ")[1].split(" ")[0])
    assert main(["tnd", str(case), "--wob-kN", "100", "--json"]) == 0
    hook_kN = json.loads(capsys.readouterr().out)["hookload_drilling_N"] / 1e3
    assert hook_kN == pytest.approx(most - 100.0, abs=0.1)  # the bound's rounding
