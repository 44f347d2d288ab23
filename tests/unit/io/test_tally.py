"""drillfatigue.io.tally and io.catalogue: descriptions, API sizes, tally files."""

from __future__ import annotations

import math
from pathlib import Path

import pytest

from drillfatigue import units
from drillfatigue.config.string import StringConfig
from drillfatigue.errors import InputError
from drillfatigue.io.catalogue import COLLARS, DRILL_PIPE, HWDP, TOOL_JOINTS
from drillfatigue.io.tally import describe, load_tally, normalise_grade, parse_description

EXAMPLES = Path(__file__).resolve().parents[3] / "data" / "examples" / "field"
STEEL_LB_PER_IN3 = 0.2833  # API 5DP's steel density for plain-end weights


def test_five_inch_pipe_from_one_line() -> None:
    s = describe(parse_description("5in 19.5ppf G-105 NC50"))
    assert (s.type, s.od_in, s.id_in, s.grade, s.connection) == ("drill_pipe", 5.0, 4.276,
                                                                 "G-105", "NC50")
    assert (s.tj_od_in, s.tj_id_in) == (6.625, 3.25)
    assert any("5DP" in r for r in s.references) and any("RP 7G" in r for r in s.references)


@pytest.mark.parametrize(("text", "kind", "od", "bore", "conn"), [
    ('5" 19.50# G105 NC50 DP', "drill_pipe", 5.0, 4.276, "NC50"),
    ("5-1/2in 21.9 lb/ft S135 5-1/2 FH", "drill_pipe", 5.5, 4.778, "5-1/2FH"),
    ("3-1/2in 13.3ppf X-95 NC38", "drill_pipe", 3.5, 2.764, "NC38"),
    ("5in HWDP", "hwdp", 5.0, 3.0, "NC50"),
    ("6-3/4in x 2-13/16in DC", "collar", 6.75, 2.8125, "NC50"),
    ("8in DC NC56", "collar", 8.0, 2.8125, "NC56"),
])
def test_description_spellings(text: str, kind: str, od: float, bore: float, conn: str) -> None:
    s = describe(parse_description(text))
    assert (s.type, s.od_in, s.id_in, s.connection) == (kind, od, bore, conn)


def test_the_default_string_s_pipe_is_the_catalogue_s() -> None:
    # params.yaml's default drill pipe (config/string.py): mm values rounded to 0.1 mm
    dp = StringConfig().components[1]
    s = describe(parse_description("5in 19.5ppf G-105 NC50"))
    for si, inch in ((dp.od_m, s.od_in), (dp.id_m, s.id_in), (dp.tool_joint_od_m, s.tj_od_in),
                     (dp.tool_joint_id_m, s.tj_id_in)):
        assert si == pytest.approx(inch * units.INCH_M, abs=0.0501e-3)


@pytest.mark.parametrize("key", list(DRILL_PIPE))
def test_drill_pipe_table_is_self_consistent(key: tuple[float, float]) -> None:
    # API 5DP: ID = D - 2t (printed to 0.001 in) and plain-end weight 10.68 (D - t) t
    # lb/ft (steel 0.2833 lb/in^3; printed to 0.01 lb/ft, so 0.005 + the 0.0005 in
    # rounding of t times dW/dt ~ 10.68 (D - 2t) <= 0.03 lb/ft)
    b = DRILL_PIPE[key]
    assert b.id_in == pytest.approx(b.od_in - 2 * b.wall_in, abs=0.0015)
    w = math.pi * STEEL_LB_PER_IN3 * 12.0 * (b.od_in - b.wall_in) * b.wall_in
    assert w == pytest.approx(b.plain_end_weight_lb_per_ft, abs=0.03)
    assert b.plain_end_weight_lb_per_ft < b.nominal_weight_lb_per_ft


@pytest.mark.parametrize("key", list(COLLARS))
def test_collar_weight_formula_is_steel_geometry(key: tuple[float, float]) -> None:
    # RP 7G's 2.67 lb/ft per in^2 is steel at 490 lb/ft^3 (pi/4 x 490/144 = 2.6725);
    # the string model's mass (7850 kg/m^3 x area) must agree to the 0.1 % that
    # separates the two densities and the rounded factor
    c = COLLARS[key]
    area_m2 = math.pi / 4 * (c.od_in**2 - c.id_in**2) * units.INCH_M**2
    geometry = 7850.0 * area_m2 / units.LB_PER_FT_KG_PER_M
    assert geometry == pytest.approx(c.weight_lb_per_ft, rel=1.5e-3)


def test_six_and_three_quarter_inch_collar_weighs_about_100_lb_per_ft() -> None:
    # the figure every drilling handbook quotes for 6-3/4 x 2-13/16 in collars
    assert COLLARS[(6.75, 2.8125)].weight_lb_per_ft == pytest.approx(100.0, rel=0.01)


def test_tool_joints_are_wider_and_narrower_than_their_pipe() -> None:
    for (od, w, grade, _), tj in TOOL_JOINTS.items():
        body = DRILL_PIPE[(od, w)]
        assert tj.od_in > body.od_in and tj.id_in < body.id_in, (od, w, grade)
    # a higher grade never gets a larger bore (same torsional-strength rule)
    order = ["E-75", "X-95", "G-105", "S-135"]
    for (od, w, grade, conn), tj in TOOL_JOINTS.items():
        for g2 in order[order.index(grade) + 1:]:
            other = TOOL_JOINTS.get((od, w, g2, conn))
            if other is not None:
                assert other.id_in <= tj.id_in
    for hw in HWDP.values():
        assert hw.tool_joint.od_in > hw.od_in


def test_grades() -> None:
    assert [normalise_grade(g, "g") for g in ("g105", "S 135", "e-75", "X95")] == [
        "G-105", "S-135", "E-75", "X-95"]
    with pytest.raises(InputError, match="E-75, X-95, G-105, S-135"):
        normalise_grade("P-110", "tally.csv:3:grade")


TALLY = """Description,Joints,Length,OD,Grade,Serial
,,ft,in,,
8-1/2in PDC bit,1,1.00,8.5,,B1
6-3/4in x 2-13/16in DC NC50,6,180.00,,,DC
5in HWDP NC50,3,93.00,,,HW
5in 19.5ppf NC50,30,930.00,,S135,DP
"""


def test_hand_made_tally(tmp_path: Path) -> None:
    p = tmp_path / "t.csv"
    p.write_text(TALLY)
    t = load_tally(p)
    bit, dc, hw, dp = t.string.components
    assert (bit.type, bit.od_m, bit.id_m, bit.length_m) == ("bit", 8.5 * units.INCH_M, 0.0,
                                                            1.0 * units.FT_M)
    assert dc.length_m == 180.0 * units.FT_M and dc.id_m == 2.8125 * units.INCH_M
    assert dc.n_segments == math.ceil(180.0 * units.FT_M / 9.0)
    # HWDP: linear mass from the catalogue's 49.3 lb/ft
    assert hw.linear_mass_kg_per_m == pytest.approx(49.3 * units.LB_PER_FT_KG_PER_M, rel=1e-15)
    assert dp.material.grade == "S-135"
    assert (dp.tool_joint_od_m, dp.tool_joint_id_m) == (6.625 * units.INCH_M,
                                                        2.75 * units.INCH_M)
    assert dp.tool_joint_length_fraction == 0.05
    assert t.string.total_length_m == pytest.approx(1204.0 * units.FT_M, rel=1e-15)


def test_example_tally_reads() -> None:
    t = load_tally(EXAMPLES / "tally.csv")
    assert [c.type for c in t.string.components] == [
        "bit", "stabilizer", "mwd", "stabilizer", "collar", "jar", "collar", "hwdp",
        "drill_pipe"]
    assert t.kinds == tuple(c.type for c in t.string.components)
    stab = t.string.components[1]
    assert stab.blade_od_m == pytest.approx(8.4375 * units.INCH_M, rel=1e-15)
    assert stab.blade_length_m == pytest.approx(17.7 * units.INCH_M, rel=1e-15)


def test_a_motor_is_a_sub_of_its_size_the_twin_lists_as_not_covered(tmp_path: Path) -> None:
    p = tmp_path / "t.csv"
    p.write_text("Description,Length,OD,ID\n,ft,in,in\n6-3/4in mud motor,30,6.75,3.0\n"
                 "6-3/4in x 2-13/16in DC NC50,90,,\n")
    t = load_tally(p)
    assert [c.type for c in t.string.components] == ["sub", "collar"]
    assert t.kinds == ("motor", "collar")


def test_a_blade_on_a_collar_row_is_refused(tmp_path: Path) -> None:
    p = tmp_path / "t.csv"
    p.write_text("Description,Length,Blade OD\n,ft,in\n6-3/4in x 2-13/16in DC NC50,90,8.4\n")
    with pytest.raises(InputError, match="blade"):
        load_tally(p)


@pytest.mark.parametrize(("text", "field", "word"), [
    (TALLY.replace(",S135,", ",P110,"), "t.csv:6:grade", "unknown grade"),
    (TALLY.replace("5in 19.5ppf NC50", "5in 17.0ppf NC50"), "t.csv:6", "not in the catalogue"),
    (TALLY.replace("5in 19.5ppf NC50", "5in 19.5ppf NC46"), "t.csv:6", "no catalogue tool joint"),
    (TALLY.replace(",,ft,in,,", ",,,in,,"), "t.csv:3:Length", "no unit"),
    (TALLY.replace(",,ft,in,,", ",,yd,in,,"), "t.csv:1:Length", "not a length unit"),
    (TALLY.replace("Length", "Remarks"), "t.csv:1", "no length column"),
    (TALLY.replace(",6,180.00,", ",6,-180.00,"), "t.csv:4:Length", ">= 0"),
    (TALLY.replace(",3,93.00,", ",2.5,93.00,"), "t.csv:5:joints", "whole number"),
    (TALLY.replace("6-3/4in x 2-13/16in DC NC50", "7in DC"), "t.csv:4", "bore"),
])
def test_bad_tallies(tmp_path: Path, text: str, field: str, word: str) -> None:
    p = tmp_path / "t.csv"
    p.write_text(text)
    with pytest.raises(InputError) as exc:
        load_tally(p)
    assert exc.value.field.endswith(field), exc.value.one_line()
    assert word in exc.value.one_line()


def test_cli_show_and_import(tmp_path: Path, monkeypatch, capsys) -> None:
    from drillfatigue.cli import main
    from drillfatigue.config import load_case

    monkeypatch.chdir(tmp_path)
    (tmp_path / "t.csv").write_text(TALLY)
    assert main(["string", "show", "t.csv", "--units", "field"]) == 0
    out = capsys.readouterr().out
    assert "6.625" in out and "2.750" in out and "length ft" in out
    assert main(["string", "import", "t.csv", "-o", "s.yaml"]) == 0
    case = load_case(tmp_path / "s.yaml")
    assert case.string == load_tally(tmp_path / "t.csv").string


def test_cli_bad_tally_one_line_exit_2_nothing_written(tmp_path: Path, monkeypatch,
                                                       capsys) -> None:
    import os

    from drillfatigue.cli import main

    monkeypatch.chdir(tmp_path)
    (tmp_path / "t.csv").write_text(TALLY.replace(",S135,", ",P110,"))
    before = set(os.listdir(tmp_path))
    assert main(["string", "import", "t.csv", "-o", "s.yaml"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("error: t.csv:6:grade: unknown grade") and err.count("\n") == 1
    assert set(os.listdir(tmp_path)) == before


MM_TALLY = """Description,Type,Joints,Length,OD,ID
,,,ft,mm,mm
Drill collar,collar,6,180.00,{od},71.4
"""


def test_od_in_mm_below_a_drill_string_size_is_refused(tmp_path: Path) -> None:
    """A unit row saying mm over an OD of 6.75 (inches) used to make a 6.75 mm collar; an
    OD outside 25 mm to 1 m (the physical bound of drillfatigue.limits) is refused."""
    p = tmp_path / "t.csv"
    p.write_text(MM_TALLY.format(od="6.75"))
    with pytest.raises(InputError) as exc:
        load_tally(p)
    assert str(exc.value) == (f"{p}:3:OD: 6.75 is outside the physical range: no drill-string "
                              "item is that size (a value in another unit than the header's?) "
                              "(allowed: 25 <= od_mm <= 1000)")
    p.write_text(MM_TALLY.format(od="171.45"))  # the same collar in mm reads
    assert load_tally(p).string.components[0].od_m == pytest.approx(0.17145, rel=1e-12)
