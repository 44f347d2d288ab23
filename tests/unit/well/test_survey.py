"""Survey CSV reading/writing and survey input checks."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from drillfatigue.config import WellConfig
from drillfatigue.errors import InputError
from drillfatigue.well import build_survey, minimum_curvature, read_survey_csv, write_survey_csv


def test_csv_round_trip(tmp_path: Path) -> None:
    sv = build_survey(WellConfig(), "profile_3")
    path = tmp_path / "s.csv"
    write_survey_csv(sv, path)
    assert path.read_text().splitlines()[0] == "md_m,inc_deg,azi_deg"
    back = read_survey_csv(path)
    np.testing.assert_allclose(back.md_m, sv.md_m, rtol=0, atol=0)
    np.testing.assert_allclose(back.pos_m, sv.pos_m, atol=1e-9)
    assert [p.name for p in tmp_path.iterdir()] == ["s.csv"]  # no temp file left


def test_survey_file_profile(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    (tmp_path / "w.csv").write_text("azi_deg,md_m,inc_deg\n0,0,0\n0,100,0\n90,200,30\n")
    monkeypatch.chdir(tmp_path)
    sv = build_survey(WellConfig(profiles={"f": {"kind": "survey_file", "path": "w.csv"}}))
    assert sv.n == 3 and sv.md_m[-1] == 200.0
    assert sv.pos_m[-1, 1] > 0.0  # drilled east


@pytest.mark.parametrize(
    ("text", "where", "what"),
    [
        ("md_m,inc_deg\n0,0\n10,0\n", "s.csv:1", "azi_deg"),
        ("md_m,inc_deg,azi_deg\n0,0,0\n10,nan,0\n", "s.csv:3:inc_deg", "finite"),
        ("md_m,inc_deg,azi_deg\n0,0,0\n10,x,0\n", "s.csv:3:inc_deg", "not a number"),
        ("md_m,inc_deg,azi_deg\n0,0,0\n10,1,0\n10,2,0\n", "s.csv:4:md_m", "increasing"),
        ("md_m,inc_deg,azi_deg\n0,0,0\n10,200,0\n", "s.csv:3:inc_deg", "0 <= inc_deg <= 180"),
        ("md_m,inc_deg,azi_deg\n0,0,0\n10,1,360\n", "s.csv:3:azi_deg", "0 <= azi_deg < 360"),
        ("md_m,inc_deg,azi_deg\n0,0,0\n", "s.csv", "at least 2"),
        ("md_m,inc_deg,azi_deg,x\n0,0,0,1\n10,0,0,1\n", "s.csv:1", "columns"),
        ("", "s.csv:1", "empty"),
    ],
)
def test_bad_survey_files(tmp_path: Path, text: str, where: str, what: str) -> None:
    path = tmp_path / "s.csv"
    path.write_text(text)
    with pytest.raises(InputError) as exc:
        read_survey_csv(path)
    assert exc.value.field.endswith(where)
    assert what in exc.value.one_line()


def test_missing_survey_file(tmp_path: Path) -> None:
    with pytest.raises(InputError, match="not found"):
        read_survey_csv(tmp_path / "none.csv")


def test_minimum_curvature_input_checks() -> None:
    with pytest.raises(InputError, match="increasing"):
        minimum_curvature([0.0, 10.0, 10.0], [0, 0, 0], [0, 0, 0])
    with pytest.raises(InputError, match="NaN"):
        minimum_curvature([0.0, 10.0], [0, np.nan], [0, 0])
    with pytest.raises(InputError, match="lengths"):
        minimum_curvature([0.0, 10.0], [0, 0, 0], [0, 0])
    with pytest.raises(InputError, match="at least 2"):
        minimum_curvature([0.0], [0.0], [0.0])
