"""Strict CSV tables (:mod:`drillfatigue.io.tables`): what pandas would fill, shift or
rename is a one-line input error naming the data row (from 1, under the header)."""

from __future__ import annotations

from pathlib import Path

import pytest

from drillfatigue.errors import InputError
from drillfatigue.io.logs import load_log
from drillfatigue.io.tables import check_csv_shape, read_csv_file, read_csv_text


@pytest.mark.parametrize("text, message", [
    ("rpm,wob_kN\n120,80\n130\n", "t.csv: row 2 has 1 cells, the header 2 (allowed: one cell "
                                  "per column in every row)"),
    ("rpm,wob_kN\n120,80,5\n", "t.csv: row 1 has 3 cells, the header 2 (allowed: one cell "
                               "per column in every row)"),
    ("rpm,rpm\n120,80\n", "t.csv: column 'rpm' named twice in the header (allowed: each name "
                          "once)"),
    ("rpm, rpm \n120,80\n", "t.csv: column 'rpm' named twice in the header (allowed: each "
                            "name once)"),
    ("rpm,\n120,80\n", "t.csv: header cell 2 is empty (allowed: a name for every column)"),
    ("rpm,wob_kN\n120,80\n\n130, \n", "wob_kN: empty cell (row 2) (allowed: a value in "
                                      "every row)"),
    ("", "t.csv: no header (allowed: a comma-separated table with a header)"),
])
def test_shape_errors(text: str, message: str) -> None:
    with pytest.raises(InputError) as e:
        check_csv_shape(text, "t.csv")
    assert str(e.value) == message


def test_a_good_table_reads_as_pandas_does(tmp_path: Path) -> None:
    p = tmp_path / "t.csv"
    p.write_text("\ufeffrpm,component_type\n120,collar\n\n130,drill_pipe\n", encoding="utf-8")
    table = read_csv_file(p)
    assert list(table.columns) == ["rpm", "component_type"]
    assert table["rpm"].tolist() == [120, 130]
    # empty cells allowed where a table may have gaps (a log's null samples)
    assert read_csv_text("a,b\n1,\n2,3\n", "t", allow_empty=True)["b"].isna().tolist() == [
        True, False]


def test_csv_log_with_a_ragged_row_or_a_column_twice(tmp_path: Path) -> None:
    """A CSV operating log: pandas used to NaN-fill a short row (then held the previous
    sample) and rename a second rpm column rpm.1."""
    p = tmp_path / "log.csv"
    p.write_text("time_s,bit_md_m,rpm\n0,1000,120\n60,1001\n120,1002,120\n")
    with pytest.raises(InputError, match=r"row 2 has 2 cells, the header 3"):
        load_log(p)
    p.write_text("time_s,bit_md_m,rpm,rpm\n0,1000,120,121\n60,1001,120,121\n")
    with pytest.raises(InputError, match=r"column 'rpm' named twice"):
        load_log(p)
    p.write_text("time_s,bit_md_m,rpm\n0,1000,120\n60,1001,\n120,1002,120\n")
    assert load_log(p).filled  # an empty cell is a null sample, held as before
