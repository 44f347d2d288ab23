"""drillfatigue.well.survey_file: field survey files (CSV m/ft, WITSML) against known values."""

from __future__ import annotations

import math
import os
from pathlib import Path

import numpy as np
import pytest

from drillfatigue.cli import main
from drillfatigue.config import WellConfig
from drillfatigue.errors import InputError
from drillfatigue.well.survey_file import load_survey, read_survey, twin_survey_table, write_survey
from drillfatigue.units import FT_M
from drillfatigue.well import build_survey

EXAMPLES = Path(__file__).resolve().parents[3] / "data" / "examples" / "field"

# A hand-made export: vertical to 1000 ft, then a 3 deg/100 ft build to 6 deg
# at 1200 ft, azimuth 45. For an arc starting vertical, TVD = R sin(I) and the
# horizontal departure R (1 - cos I), R = 100 ft / (3 deg in rad) = 1909.859 ft:
# TVD(1100) = 1000 + 1909.859 sin 3 = 1099.954, TVD(1200) = 1000 + 1909.859 sin 6
# = 1199.634.
HAND_FT = """Measured Depth (ft),Incl (deg),Azimuth (deg),TVD (ft),N/S (ft),DLS (deg/100ft)
0.00,0.00,0.00,0.00,0.00,
1000.00,0.00,0.00,1000.00,0.00,0.00
1100.00,3.00,45.00,1099.95,1.77,3.00
1200.00,6.00,45.00,1199.63,7.07,3.00
"""

HAND_WITSML = """<?xml version="1.0" encoding="UTF-8"?>
<trajectorys xmlns="http://www.witsml.org/schemas/1series" version="1.4.1.1">
 <trajectory uidWell="W" uidWellbore="B" uid="T">
  <nameWell>hand</nameWell><nameWellbore>hand</nameWellbore><name>hand</name>
  <trajectoryStation uid="1"><md uom="m">0</md><tvd uom="m">0</tvd>
   <incl uom="dega">0</incl><azi uom="rad">0</azi></trajectoryStation>
  <trajectoryStation uid="2"><md uom="m">304.8</md><tvd uom="m">304.8</tvd>
   <incl uom="dega">0</incl><azi uom="rad">0</azi></trajectoryStation>
  <trajectoryStation uid="3"><md uom="m">335.28</md><tvd uom="m">335.266</tvd>
   <incl uom="dega">3.000</incl><azi uom="rad">0.785398163397</azi></trajectoryStation>
 </trajectory>
</trajectorys>
"""


def _closed_form_tvd_ft(md_ft: float) -> float:
    r = 100.0 / math.radians(3.0)
    return 1000.0 + r * math.sin(math.radians(3.0 * (md_ft - 1000.0) / 100.0))


def test_hand_made_ft_csv(tmp_path: Path) -> None:
    p = tmp_path / "s.csv"
    p.write_text(HAND_FT)
    r = load_survey(p)
    sv = r.survey
    np.testing.assert_array_equal(sv.md_m, [0.0, 304.8, 335.28, 365.76])
    np.testing.assert_allclose(np.degrees(sv.inc_rad), [0, 0, 3, 6], rtol=0, atol=1e-13)
    # minimum curvature of a constant build is the circular arc: closed form to 1e-9 m
    for i, md_ft in ((2, 1100.0), (3, 1200.0)):
        assert sv.pos_m[i, 2] == pytest.approx(_closed_form_tvd_ft(md_ft) * FT_M, abs=1e-9)
    np.testing.assert_allclose(sv.dls_deg_per_100ft[2:], 3.0, rtol=1e-12)
    assert r.units["md"] == "ft" and r.units["dls"] == "deg/100ft"
    assert r.ignored_columns == ("N/S (ft)",)
    # the file's 2-decimal TVD and DLS agree with the recomputation to their rounding
    assert r.max_tvd_diff_m < 0.005 * FT_M and r.max_dls_diff_deg_per_30m < 1e-9


def test_units_row_and_aliases(tmp_path: Path) -> None:
    p = tmp_path / "s.csv"
    p.write_text("MD,Inc,Azi,Dogleg\nm,deg,deg,deg/30m\n0,0,0,0\n100,0,0,0\n130,3,90,3.00\n")
    r = load_survey(p)
    assert r.units == {"md": "m", "inc": "deg", "azi": "deg", "dls": "deg/30m"}
    assert r.survey.dls_deg_per_30m[2] == pytest.approx(3.0, rel=1e-12)


def test_depth_unit_for_headers_without_one(tmp_path: Path) -> None:
    p = tmp_path / "s.csv"
    p.write_text("MD,Inc,Azi\n0,0,0\n1000,10,20\n")
    with pytest.raises(InputError, match="depth without a unit"):
        read_survey(p)
    assert read_survey(p, depth_unit="ft").md_m[1] == 304.8


def test_hand_made_witsml(tmp_path: Path) -> None:
    p = tmp_path / "t.xml"
    p.write_text(HAND_WITSML)
    r = load_survey(p)
    sv = r.survey
    assert sv.n == 3 and sv.md_m[2] == 335.28
    assert math.degrees(sv.inc_rad[2]) == pytest.approx(3.0, abs=1e-13)
    assert math.degrees(sv.azi_rad[2]) == pytest.approx(45.0, abs=1e-10)
    # the 3 decimals of the TVD agree with the arc (100 ft at 3 deg/100 ft)
    assert sv.pos_m[2, 2] == pytest.approx(_closed_form_tvd_ft(1100.0) * FT_M, abs=1e-9)
    assert r.units["inc"] == "dega" and r.units["azi"] == "rad"


def test_same_well_in_ft_and_in_m_to_1e9(tmp_path: Path) -> None:
    sv = build_survey(WellConfig())
    m_rows = ["md_m,inc_deg,azi_deg"] + [
        f"{float(sv.md_m[i])!r},{math.degrees(sv.inc_rad[i])!r},"
        f"{math.degrees(sv.azi_rad[i]) % 360!r}"
        for i in range(sv.n)]
    ft_rows = ["MD (ft),Incl (deg),Azim (deg)"] + [
        f"{float(sv.md_m[i]) / FT_M!r},{math.degrees(sv.inc_rad[i])!r},"
        f"{math.degrees(sv.azi_rad[i]) % 360!r}" for i in range(sv.n)]
    (tmp_path / "m.csv").write_text("\n".join(m_rows) + "\n")
    (tmp_path / "ft.csv").write_text("\n".join(ft_rows) + "\n")
    a, b = read_survey(tmp_path / "m.csv"), read_survey(tmp_path / "ft.csv")
    # md/0.3048 printed with 17 digits and multiplied back: relative 1e-16, i.e.
    # ~1e-13 m at 1000 m; positions accumulate that over ~35 stations
    np.testing.assert_allclose(a.md_m, b.md_m, rtol=0, atol=1e-9)
    np.testing.assert_allclose(a.pos_m, b.pos_m, rtol=0, atol=1e-9)
    np.testing.assert_allclose(a.dls_rad_per_m, b.dls_rad_per_m, rtol=0, atol=1e-12)


def test_field_export_reads_back_bit_for_bit(tmp_path: Path) -> None:
    sv = build_survey(WellConfig())
    write_survey(sv, tmp_path / "ft.csv", "field")
    assert (tmp_path / "ft.csv").read_text().startswith("MD (ft),Inc (deg),Azi (deg),TVD (ft)")
    r = load_survey(tmp_path / "ft.csv")
    # depths come back bit for bit (exact unit fractions); angles pass through
    # degrees -> radians as in an SI file (repr of the degrees, one rounding
    # each way: within 2 ulp), which moves positions by ~1e-15 m
    np.testing.assert_array_equal(r.survey.md_m, sv.md_m)
    np.testing.assert_allclose(r.survey.inc_rad, sv.inc_rad, rtol=4.5e-16, atol=0)
    np.testing.assert_allclose(r.survey.pos_m, sv.pos_m, rtol=0, atol=1e-12)
    assert r.max_dls_diff_deg_per_30m < 1e-12 and r.max_tvd_diff_m < 1e-12


def test_example_files_agree() -> None:
    a = load_survey(EXAMPLES / "survey_ft.csv")
    b = load_survey(EXAMPLES / "survey_witsml.xml")
    np.testing.assert_array_equal(a.survey.pos_m, b.survey.pos_m)
    assert a.ignored_columns == ("N/S", "E/W")


def test_twin_table_from_a_survey_and_from_a_geometry_table(tmp_path: Path) -> None:
    p = tmp_path / "s.csv"
    p.write_text(HAND_FT)
    t = twin_survey_table(p)
    assert list(t.columns) == ["md_m", "inc_deg", "dls_deg_per_30m"]
    g = tmp_path / "g.csv"
    g.write_text("MD (ft),DLS (deg/100ft),Inc (deg)\n0,0,0\n1000,3.0,30\n")
    t = twin_survey_table(g)
    assert t["md_m"].tolist() == [0.0, 304.8]
    assert t["dls_deg_per_30m"].iloc[1] == pytest.approx(3.0 * 30 / 30.48, rel=1e-15)


# (id, file name, text, field the error names, a word of the message)
BAD = [
    ("dls_in_wrong_unit", "s.csv", HAND_FT.replace("3.00\n", "9.84\n"), "s.csv:4:DLS (deg/100ft)",
     "minimum-curvature"),
    ("survey_in_m_labelled_ft",
     "s.csv", "MD (ft),Inc,Azi,DLS (deg/30m)\n0,0,0,0\n100,0.00,0.00,0\n130,3.00,0.00,3.00\n",
     "s.csv:4:DLS (deg/30m)", "units"),
    ("tvd_off", "s.csv", HAND_FT.replace("1199.63", "1199.20"), "s.csv:5:TVD (ft)", "TVD"),
    ("unknown_depth_unit", "s.csv", "MD (yd),Inc,Azi\n0,0,0\n10,1,1\n", "MD (yd)",
     "not a length unit"),
    ("dls_without_unit", "s.csv", "MD (m),Inc,Azi,DLS\n0,0,0,0\n10,1,1,3\n", "s.csv:1:DLS",
     "unit"),
    ("two_md_columns", "s.csv", "MD (m),Depth (m),Inc,Azi\n0,0,0,0\n10,10,1,1\n", "s.csv:1",
     "both"),
    ("text_cell", "s.csv", "MD (m),Inc,Azi\n0,0,0\n10,one,1\n", "s.csv:3:Inc", "not a number"),
    ("xml_not_well_formed", "s.xml", "<trajectorys><trajectory>", "s.xml", "XML"),
    ("xml_no_trajectory", "s.xml", "<logs/>", "s.xml", "no trajectory"),
    ("xml_station_without_uom", "s.xml", HAND_WITSML.replace(' uom="dega">0</incl>', ">0</incl>",
                                                             1),
     "s.xml:trajectoryStation[1]:incl", "uom"),
    ("xml_missing_azi", "s.xml",
     HAND_WITSML.replace('<azi uom="rad">0</azi></trajectoryStation>\n  <trajectoryStation '
                         'uid="2">', '</trajectoryStation>\n  <trajectoryStation uid="2">'),
     "s.xml:trajectoryStation[1]:azi", "missing"),
    ("unknown_suffix", "s.dat", "x", "s.dat", "survey file type"),
]


@pytest.mark.parametrize(("name", "text", "field", "word"), [b[1:] for b in BAD],
                         ids=[b[0] for b in BAD])
def test_malformed_survey_one_line_exit_2_nothing_written(tmp_path, monkeypatch, capsys, name,
                                                          text, field, word) -> None:
    monkeypatch.chdir(tmp_path)
    (tmp_path / name).write_text(text)
    (tmp_path / "case.yaml").write_text(
        f"well:\n  profiles:\n    f: {{kind: survey_file, path: {name}}}\n")
    before = set(os.listdir(tmp_path))
    rc = main(["well", "export", "case.yaml", "-o", "out.csv", "--units", "field"])
    out, err = capsys.readouterr()
    assert rc == 2 and out == ""
    assert len(err.splitlines()) == 1, err
    assert err.startswith(f"error: {field}") or err.startswith(f"error: {name}:"), err
    assert field in err and word in err, err
    assert set(os.listdir(tmp_path)) == before


def test_survey_file_profile_with_depth_unit(tmp_path: Path, monkeypatch) -> None:
    monkeypatch.chdir(tmp_path)
    (tmp_path / "s.csv").write_text("MD,Inc,Azi\n0,0,0\n1000,10,20\n")
    cfg = WellConfig(profiles={"f": {"kind": "survey_file", "path": "s.csv", "depth_unit": "ft"}})
    assert build_survey(cfg).md_m[1] == 304.8
    with pytest.raises(InputError, match="depth_unit: m|ft"):
        build_survey(WellConfig(profiles={"f": {"kind": "survey_file", "path": "s.csv"}}))
