"""A run's joint tally: one row per joint, from the bit up, each with its serial.

Columns are recognised by name (any case; units in the header such as
``Length (ft)`` or in a units row below it), as in :mod:`drillfatigue.io.tally`:

``Serial`` (required, unique), ``Length`` or ``Joint Length`` (required, ft or m),
``Description`` (``5in 19.5ppf G-105 NC50``: kind, sizes and grade, completed
from the catalogue) and/or ``Type`` (``dp``, ``hwdp``, ``dc``, ``stab``,
``bit``, ``sub``, ...), ``OD``, ``ID`` (in or mm, override the description),
``Grade``, ``Connection``. A ``Joints`` column, if present, must be 1 on every
row: the ledger follows joints, so each has its own row and serial.
"""

from __future__ import annotations

import csv
import math
import re
from pathlib import Path

import pandas as pd

from drillfatigue import units
from drillfatigue.errors import InputError
from drillfatigue.io.headers import split_header, unit_factor
from drillfatigue.io.tally import (
    TALLY_ALIASES,
    ComponentSpec,
    describe,
    normalise_grade,
    parse_description,
)

_TYPES = {"drill_pipe": "drill_pipe", "dp": "drill_pipe", "drill pipe": "drill_pipe",
          "hwdp": "hwdp", "hw": "hwdp", "collar": "collar", "dc": "collar",
          "stabilizer": "stabilizer", "stab": "stabilizer", "bit": "bit", "sub": "sub",
          "mwd": "sub", "motor": "sub", "jar": "sub"}
#: longest joint the ledger accepts, m (range 3 drill pipe is about 13.7 m; a long BHA tool ~30 m)
MAX_JOINT_LENGTH_M = 40.0
COLUMNS = ("position", "serial", "component_type", "description", "length_m", "od_m", "id_m",
           "grade", "connection", "s_bottom_m", "s_top_m")


def load_joint_tally(path: str | Path) -> pd.DataFrame:
    """Read a joint tally into a table of :data:`COLUMNS` (SI), positions from 1 at the bit.

    Raises
    ------
    InputError
        Missing file or column, bad unit, a length outside ``0 < L <= 40 m``,
        a repeated serial; the field names ``file:row:column``.
    """
    p = Path(path)
    if not p.is_file():
        raise InputError("--tally", f"file {str(p)!r} not found", "an existing CSV tally")
    try:
        with p.open(newline="", encoding="utf-8-sig") as fh:
            rows = [r for r in csv.reader(fh) if r and any(c.strip() for c in r)]
    except UnicodeDecodeError:
        raise InputError(str(p), "not a UTF-8 text file", "a CSV tally") from None
    if len(rows) < 2:
        raise InputError(str(p), "no joints", "a header row, then one row per joint")
    header = rows[0]
    first = 1
    if not any(re.fullmatch(r"\s*-?\d+(\.\d+)?\s*", c) for c in rows[1]) and \
            any(split_header(c)[0] in ("ft", "m", "in", "mm") for c in rows[1]):
        first = 2
    col: dict[str, int] = {}
    unit: dict[str, str | None] = {}
    for j, h in enumerate(header):
        name, u = split_header(h)
        role = next((r for r, names in TALLY_ALIASES.items() if name in names), None)
        if role is None or role in col:
            continue
        col[role] = j
        if first == 2 and j < len(rows[1]) and rows[1][j].strip():
            u = rows[1][j].strip().strip("()[]")
        unit[role] = u
    if "name" not in col:
        raise InputError(f"{p}:1", "no Serial column", "Serial, Length (ft), Description")
    length_role = "joint_length" if "joint_length" in col else "length"
    if length_role not in col:
        raise InputError(f"{p}:1", "no length column", "Length (ft) or Joint Length (ft)")
    if "description" not in col and "type" not in col:
        raise InputError(f"{p}:1", "neither a Description nor a Type column",
                         "Description (e.g. '5in 19.5ppf G-105 NC50') or Type (dp, hwdp, dc, ...)")
    out: list[dict[str, object]] = []
    seen: dict[str, int] = {}
    s = 0.0
    for r, row in enumerate(rows[first:], start=first + 1):
        where = f"{p}:{r}"

        def cell(role: str, row: list[str] = row) -> str:
            j = col.get(role)
            return row[j].strip() if j is not None and j < len(row) else ""

        def si(role: str, where: str = where) -> float | None:
            c = cell(role)
            if not c:
                return None
            head = header[col[role]].strip()
            try:
                v = float(c)
            except ValueError:
                raise InputError(f"{where}:{head}", f"not a number: {c!r}", "a number") from None
            u = unit.get(role)
            if u is None:
                raise InputError(f"{where}:{head}", "no unit in the header",
                                 f"e.g. '{head} ({'ft' if 'length' in role else 'in'})'")
            return v * unit_factor("length", u, f"{p}:1:{head}")

        serial = cell("name")
        if not serial:
            raise InputError(f"{where}:serial", "empty", "a serial on every row")
        if serial in seen:
            raise InputError(f"{where}:serial", f"{serial!r} also on row {seen[serial]}",
                             "each serial once per run")
        seen[serial] = r
        joints = cell("joints")
        if joints and joints not in ("1", "1.0"):
            raise InputError(f"{where}:joints", f"{joints!r}", "1 (one row and serial per joint)")
        desc = cell("description")
        spec = parse_description(desc, f"{where}:description") if desc else ComponentSpec()
        t = cell("type").lower()
        if t:
            if t not in _TYPES:
                raise InputError(f"{where}:type", f"unknown type {t!r}", ", ".join(_TYPES))
            spec.type = _TYPES[t]
        od, idd = si("od"), si("id")
        if od is not None:
            spec.od_in = od / units.INCH_M
        if idd is not None:
            spec.id_in = idd / units.INCH_M
        if cell("grade"):
            spec.grade = normalise_grade(cell("grade"), f"{where}:grade")
        if cell("connection"):
            spec.connection = cell("connection").upper().replace(" ", "")
        if spec.od_in is not None:
            spec = describe(spec, where)
        length = si(length_role)
        if length is None or not math.isfinite(length) or not 0.0 < length <= MAX_JOINT_LENGTH_M:
            raise InputError(f"{where}:{header[col[length_role]].strip()}",
                             f"joint length {length!r} m",
                             f"0 < length <= {MAX_JOINT_LENGTH_M:g} m")
        od_m = None if spec.od_in is None else spec.od_in * units.INCH_M
        id_m = None if spec.id_in is None else spec.id_in * units.INCH_M
        if od_m is not None and id_m is not None and not 0.0 <= id_m < od_m:
            raise InputError(f"{where}:id", f"ID {id_m:.4g} m not below OD {od_m:.4g} m",
                             "0 <= ID < OD")
        out.append({"position": len(out) + 1, "serial": serial, "component_type": spec.type,
                    "description": desc, "length_m": length, "od_m": od_m, "id_m": id_m,
                    "grade": spec.grade, "connection": spec.connection,
                    "s_bottom_m": s, "s_top_m": s + length})
        s += length
    return pd.DataFrame(out, columns=list(COLUMNS))
