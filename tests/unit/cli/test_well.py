"""``drillfatigue well show|plot|export`` on good input."""

from __future__ import annotations

from pathlib import Path

import pytest

from drillfatigue.cli import main
from drillfatigue.well import read_survey_csv


@pytest.fixture()
def case(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    monkeypatch.chdir(tmp_path)
    path = tmp_path / "case.yaml"
    path.write_text("well:\n  profile: profile_2\n")
    return path


def test_show_prints_key_points_and_max_dls(case: Path, capsys) -> None:
    assert main(["well", "show", str(case)]) == 0
    out = capsys.readouterr().out
    for word in ("profile_2", "surface", "KOP", "end of build", "TD", "max DLS"):
        assert word in out
    # Member 2 of the default family: R = 650 - 450 = 200 m -> 8.594 deg/30 m.
    assert "8.594 deg/30m" in out


def test_show_reports_the_tortuosity(tmp_path: Path, monkeypatch, capsys) -> None:
    """With well.tortuosity: the model, and max/mean DLS below its start and the
    tortuosity index, plan beside tortuous hole; without it, no such table."""
    monkeypatch.chdir(tmp_path)
    path = tmp_path / "t.yaml"
    path.write_text("well:\n  tortuosity: {model: sine, amplitude_deg: 1.0, period_m: 30.0, "
                    "md_start_m: 830.0}\n")
    assert main(["well", "show", str(path)]) == 0
    out = capsys.readouterr().out
    assert "tortuosity: sine, amplitude 1 deg, period 30 m, inclination" in out
    assert "adding up to 6.283 deg/30m" in out  # 2 pi 1 deg / 30 m
    rows = {line.split("│")[1].strip(): [c.strip() for c in line.split("│")[2:4]]
            for line in out.splitlines()
            if (line.startswith("│") and "below MD" in line) or line.startswith("│ tortuosity")}
    assert rows["max DLS below MD 830.0 m, deg/30m"][0] == "0.000"
    assert 6.22 < float(rows["max DLS below MD 830.0 m, deg/30m"][1]) <= 6.283
    assert float(rows["mean DLS below MD 830.0 m, deg/30m"][1]) == pytest.approx(4.0, abs=0.1)
    assert float(rows["tortuosity index, 1/m"][1]) > float(rows["tortuosity index, 1/m"][0])
    path.write_text("well:\n  profile: profile_1\n")
    assert main(["well", "show", str(path)]) == 0
    assert "tortuosity" not in capsys.readouterr().out


def test_show_other_profile(case: Path, capsys) -> None:
    assert main(["well", "show", str(case), "--well-profile", "profile_3"]) == 0
    assert "end of tangent" in capsys.readouterr().out


def test_plot_and_export(case: Path, tmp_path: Path) -> None:
    assert main(["well", "plot", str(case), "-o", "fig.png"]) == 0
    assert (tmp_path / "fig.png").read_bytes()[:4] == b"\x89PNG"
    assert main(["well", "export", str(case), "-o", "s.csv"]) == 0
    sv = read_survey_csv(tmp_path / "s.csv")
    assert sv.pos_m[-1, 2] == pytest.approx(650.0, abs=1e-6)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["case.yaml", "fig.png", "s.csv"]


def test_out_is_the_option_name_and_output_a_hidden_old_spelling(tmp_path, monkeypatch,
                                                                  capsys) -> None:
    """Every command names its output ``--out``; ``--output`` still works but is not shown."""
    case = tmp_path / "case.yaml"
    case.write_text("well: {}\n")
    monkeypatch.chdir(tmp_path)
    assert main(["well", "export", str(case), "--output", "old.csv"]) == 0
    assert (tmp_path / "old.csv").is_file()
    assert main(["well", "export", str(case), "--out", "a.csv", "--output", "b.csv"]) == 2
    assert "given twice" in capsys.readouterr().err
    assert not (tmp_path / "a.csv").exists() and not (tmp_path / "b.csv").exists()
    assert main(["well", "plot", "--help"]) == 0
    text = capsys.readouterr().out
    assert "--out" in text and "--output" not in text
    # tnd took --output too: the same rule
    assert main(["tnd", str(case), "--out", "a.png", "--output", "b.png"]) == 2
    assert "given twice" in capsys.readouterr().err


@pytest.mark.parametrize("command", ["plot", "export"])
def test_out_is_shown_as_required(tmp_path, monkeypatch, capsys, command: str) -> None:
    """`well plot` / `well export` need --out: their help says so (it used to show an
    optional option), and a call without it is a one-line usage error, exit 2."""
    assert main(["well", command, "--help"]) == 0
    line = next(t for t in capsys.readouterr().out.splitlines() if "--out" in t)
    assert "[required]" in line and line.lstrip("│ ").startswith("*"), line
    case = tmp_path / "case.yaml"
    case.write_text("well: {}\n")
    monkeypatch.chdir(tmp_path)
    assert main(["well", command, str(case)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "--out" in err, err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["case.yaml"]
