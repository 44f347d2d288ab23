"""CSV tables read strictly: what pandas would shift, fill or rename is an input error.

``pandas.read_csv`` is lenient where a user's table is wrong: a row with a
missing cell is filled with NaN, a row with a cell too many shifts the first
column into the index or stops with a parser message naming a file line, a
header naming a column twice becomes ``rpm`` and ``rpm.1``, and an empty
header cell becomes ``Unnamed: 2``. :func:`check_csv_shape` refuses each of
these with the one-line :class:`~drillfatigue.errors.InputError`, naming the
data row (counted from 1, the first row under the header; blank lines are
skipped, as pandas skips them) and the column; :func:`read_csv_text` checks,
then reads the table with pandas.

Used by the condition tables of ``query --csv``, the component lists and
surveys of ``twin replay`` and the service, and (empty cells allowed: a
null sample is held from the previous one) the CSV operating logs.
"""

from __future__ import annotations

import csv
import io
from pathlib import Path

import pandas as pd

from drillfatigue.config.base import read_utf8
from drillfatigue.errors import InputError

_SHAPE = "one cell per column in every row"


def check_csv_shape(text: str, source: str, allow_empty: bool = False) -> None:
    """Raise InputError for a duplicate or empty header name, a ragged row or (unless
    ``allow_empty``) an empty cell. ``source`` names the table (its path)."""
    try:
        rows = [r for r in csv.reader(io.StringIO(text)) if r]
    except csv.Error as exc:
        raise InputError(source, f"unreadable CSV ({exc})",
                         "a comma-separated table with a header") from None
    if not rows:
        raise InputError(source, "no header", "a comma-separated table with a header")
    header = [h.strip() for h in rows[0]]
    seen: set[str] = set()
    for j, name in enumerate(header):
        if not name:
            raise InputError(source, f"header cell {j + 1} is empty", "a name for every column")
        if name in seen:
            raise InputError(source, f"column {name!r} named twice in the header",
                             "each name once")
        seen.add(name)
    for k, row in enumerate(rows[1:], start=1):
        if len(row) != len(header):
            raise InputError(source, f"row {k} has {len(row)} cells, the header "
                             f"{len(header)}", _SHAPE)
        if not allow_empty:
            for j, cell in enumerate(row):
                if not cell.strip():
                    raise InputError(header[j], f"empty cell (row {k})", "a value in every row")


def read_csv_text(text: str, source: str, allow_empty: bool = False,
                  **read_csv: object) -> pd.DataFrame:
    """The table of CSV ``text`` after :func:`check_csv_shape` (``read_csv``: options of
    :func:`pandas.read_csv`)."""
    text = text.removeprefix("\ufeff")
    check_csv_shape(text, source, allow_empty)
    try:
        return pd.read_csv(io.StringIO(text), **read_csv)  # type: ignore[arg-type]
    except (pd.errors.ParserError, pd.errors.EmptyDataError) as exc:
        raise InputError(source, f"unreadable CSV ({type(exc).__name__})",
                         "a comma-separated table with a header") from None


def read_csv_file(path: str | Path, allow_empty: bool = False,
                  **read_csv: object) -> pd.DataFrame:
    """:func:`read_csv_text` of a UTF-8 file."""
    return read_csv_text(read_utf8(path), str(path), allow_empty, **read_csv)
