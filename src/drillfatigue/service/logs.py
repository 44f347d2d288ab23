"""Operating-log readers of the service: text or bytes in, the twin's log table out.

A reader turns an uploaded log into the table
:func:`drillfatigue.surrogate.twin.replay_log` takes (``time_s`` or
``time``, ``bit_md_m`` or ``bit_md_ft``, surface channels in user units).
``csv``, ``las`` (LAS 2.0) and ``witsml`` (WITSML 1.4.1.1 log) are built in
(the last two through :mod:`drillfatigue.io.logs`); another format is added
with :func:`register_log_reader` and is then accepted as the ``log.format``
of ``POST /v1/twin/replay``::

    from drillfatigue.service.logs import register_log_reader
    register_log_reader("las", my_las_reader)   # bytes -> DataFrame
"""

from __future__ import annotations

import tempfile
from collections.abc import Callable
from pathlib import Path

import pandas as pd

from drillfatigue.errors import InputError
from drillfatigue.io.logs import load_log
from drillfatigue.io.tables import read_csv_text

LogReader = Callable[[bytes], pd.DataFrame]

_READERS: dict[str, LogReader] = {}


def register_log_reader(fmt: str, reader: LogReader) -> None:
    """Accept ``fmt`` (lower case letters, digits, ``_``) as a log format."""
    if not fmt or not all(c.islower() or c.isdigit() or c == "_" for c in fmt):
        raise ValueError(f"bad log format name {fmt!r} (lower case letters, digits, _)")
    _READERS[fmt] = reader


def log_formats() -> list[str]:
    """Names of the registered log formats."""
    return sorted(_READERS)


def read_log(fmt: str, data: bytes, field: str = "log") -> pd.DataFrame:
    """Parse ``data`` with the reader of ``fmt``; errors name ``field``.

    Raises
    ------
    InputError
        Unknown format, unreadable content, no rows.
    """
    reader = _READERS.get(fmt)
    if reader is None:
        raise InputError(f"{field}.format", f"unknown log format {fmt!r}",
                         ", ".join(log_formats()))
    try:
        table = reader(data)
    except InputError as exc:
        raise InputError(f"{field}.{exc.field}", exc.problem, exc.allowed) from None
    if len(table) == 0:
        raise InputError(f"{field}.text", "the log has no rows", ">= 2 rows")
    return table


def read_csv_table(data: bytes, what: str = "table", allow_empty: bool = False
                   ) -> pd.DataFrame:
    """A comma-separated table with a header line (UTF-8), read strictly
    (:func:`drillfatigue.io.tables.read_csv_text`: a ragged row, a column named twice
    and, unless ``allow_empty``, an empty cell are refused, naming the row)."""
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise InputError("text", f"unreadable CSV {what} (not UTF-8 text, byte "
                         f"0x{data[exc.start]:02x} at offset {exc.start})",
                         "a comma-separated table with a header line") from None
    return read_csv_text(text, "text", allow_empty)


register_log_reader("csv", lambda data: read_csv_table(data, "log", allow_empty=True))


def _field_log_reader(suffix: str) -> LogReader:
    """A reader of field logs (:func:`drillfatigue.io.logs.load_log`) from uploaded bytes."""
    def read(data: bytes) -> pd.DataFrame:
        with tempfile.TemporaryDirectory() as folder:
            path = Path(folder) / f"log{suffix}"
            path.write_bytes(data)
            try:
                return load_log(path).table
            except InputError as exc:
                # the temporary file's name means nothing to the client
                field = exc.field.replace(str(path), "text")
                raise InputError(field, exc.problem, exc.allowed) from None
    return read


register_log_reader("las", _field_log_reader(".las"))
register_log_reader("witsml", _field_log_reader(".xml"))
