"""Rig operating logs for the twin: LAS 2.0, WITSML 1.4.1.1 ``log`` XML and CSV.

:func:`load_log` reads a log, recognises its channels by mnemonic or header
(aliases below, any case), converts each to SI once and returns the twin's
log table: ``time_s``, ``bit_md_m`` and the surface channels ``rpm``,
``wob_N``, ``hook_load_N``, ``surface_torque_Nm``, ``rop_m_per_s``,
``standpipe_pressure_Pa``, ``flow_rate_m3_per_s``, ``hole_depth_m``,
``block_position_m`` (those present).

============================  ==============================================  ============
channel                       mnemonics / headers                             units
============================  ==============================================  ============
time                          TIME, ETIM, ELAPSED TIME, DATETIME, TIME_S      s, min, h, ms;
                                                                              or date-time
bit depth                     BITDEP, DBTM, BDEP, BIT DEPTH, BIT_MD           m, ft
hole depth                    DMEA, HDTH, HOLE DEPTH, DEPT (depth index)      m, ft
rotary speed                  RPM, SURF_RPM, RPMA, TRPM, TD RPM               rpm, 1/min
weight on bit                 WOB, SWOB, WOBA                                 klbf, kN, N, lbf, tf
hook load                     HKLD, HKLA, HKL, HOOK LOAD                      klbf, kN, N, lbf, tf
surface torque                TQA, STOR, TORQUE, STQ                          kft.lbf, kN.m, ...
rate of penetration           ROP, ROPA, ROP5                                 ft/h, m/h, m/s
standpipe pressure            SPPA, SPP                                       psi, kPa, bar, MPa
flow rate                     TFLO, FLOWIN, MFIA, FLOW                        gpm, l/min, m3/s
block position                BPOS, BLKPOS                                    ft, m
============================  ==============================================  ============

Other channels are ignored and reported (a LAS file carries dozens). A CSV
column that is already a twin name with a unit suffix (``wob_kN``,
``rop_ft_per_h``, ``mud_density_sg``: :mod:`drillfatigue.io.names`) is taken as
such; ``--channel STEM=MNEMONIC`` picks the mnemonic of a channel when a file
has two candidates (``--channel rpm=SURF_RPM``) or an unusual name.

Bad-input rules
---------------
Errors (one line naming the channel): unknown file type; unreadable file;
a channel's unit that is not a unit of its quantity; no time and no way to
derive it; time going backwards; two rows with the same time but different
values; a step between samples longer than ``max_gap_s``; a run of null
values longer than ``max_fill_s``; a channel without any valid value; the
bit more than 1 m deeper than the deepest hole depth so far (a depth unit
mix-up between the two channels); ROP integrated over the time the hole
deepens differing from the deepening by more than a factor 1.5 (an ROP unit
mix-up: ft/h read as m/h is a factor 3.28).

Fill rules (reported in the output's ``log`` section):

* **null values** (LAS ``NULL``, WITSML ``nullValue`` or an empty cell, an
  empty CSV cell) hold the channel's previous valid value, as the twin holds
  every value until the next sample; a leading run takes the first valid
  value. Each run must be no longer than ``max_fill_s`` (default 300 s).
* **repeated time stamps** with identical values are dropped (a recorder
  writing a row twice).
* **depth-indexed logs** without a time channel get time from the ROP:
  ``dt_i = (md_{i+1} - md_i) / ROP_i``, so the twin charges each depth step
  with the conditions of the row that starts it for as long as drilling it
  took; the depth must be strictly increasing and ROP > 0.
"""

from __future__ import annotations

import math
import xml.etree.ElementTree as ET
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import lasio
import numpy as np
import pandas as pd

from drillfatigue.errors import InputError
from drillfatigue.io.tables import read_csv_file
from drillfatigue.limits import check_feature_values
from drillfatigue.io.headers import UNIT_SPELLINGS, split_header, unit_factor
from drillfatigue.io.names import CHANNEL_FAMILIES, UNIT_FAMILIES, channel_stem

__all__ = ["CHANNELS", "LogImport", "load_log", "log_bit_md_m", "log_times_s"]

DEFAULT_MAX_FILL_S = 300.0
DEFAULT_MAX_GAP_S = 900.0
#: bit below the hole's deepest point by more than this (m) is a depth unit error
BIT_BELOW_HOLE_TOLERANCE_M = 1.0
#: integrated ROP / drilled length outside [1/f, f] is an ROP unit error
ROP_CONSISTENCY_FACTOR = 1.5


@dataclass(frozen=True)
class Channel:
    """A surface channel: its SI column, quantity and recognised names (normalised)."""

    column: str
    quantity: str
    aliases: tuple[str, ...]


#: stem -> channel. Names are normalised like headers (lower case, ``_`` -> blank).
CHANNELS: dict[str, Channel] = {
    "time": Channel("time_s", "time", ("time", "etim", "elapsed time", "datetime",
                                       "date time", "tim", "time s")),
    "bit_md": Channel("bit_md_m", "length", ("bitdep", "dbtm", "bdep", "bit depth",
                                             "bit md", "bitmd", "bit measured depth")),
    "hole_depth": Channel("hole_depth_m", "length", ("dmea", "hdth", "hole depth", "hole md",
                                                     "dept", "depth", "measured depth")),
    "rpm": Channel("rpm", "rotary_speed", ("rpm", "surf rpm", "rpma", "trpm", "td rpm",
                                           "rotary speed", "surface rpm", "top drive rpm")),
    "wob": Channel("wob_N", "force", ("wob", "swob", "woba", "weight on bit")),
    "hook_load": Channel("hook_load_N", "force", ("hkld", "hkla", "hkl", "hook load",
                                                  "hookload")),
    "surface_torque": Channel("surface_torque_Nm", "torque", ("tqa", "stor", "torque", "stq",
                                                              "surface torque", "tq")),
    "rop": Channel("rop_m_per_s", "speed", ("rop", "ropa", "rop5", "rate of penetration")),
    "standpipe_pressure": Channel("standpipe_pressure_Pa", "pressure",
                                  ("sppa", "spp", "standpipe pressure")),
    "flow_rate": Channel("flow_rate_m3_per_s", "flow", ("tflo", "flowin", "mfia", "flow",
                                                        "flow in", "flow rate")),
    "block_position": Channel("block_position_m", "length", ("bpos", "blkpos",
                                                             "block position", "block height")),
}
_FAMILY_OF = {"length": "_m", "force": "_N", "speed": "_m_per_s", "torque": "_Nm",
              "pressure": "_Pa", "flow": "_m3_per_s"}


@dataclass(frozen=True)
class LogImport:
    """A log read into the twin's SI table, with what the reader did.

    Attributes
    ----------
    table : DataFrame
        ``time_s`` (from 0 at the first row), ``bit_md_m`` and the other
        channels in SI; CSV columns with twin names pass through unchanged.
    source : str
        File name.
    index : str
        ``time`` or ``depth``.
    channels : dict
        SI column -> ``"MNEMONIC [unit]"`` it came from.
    ignored : tuple of str
        Channels not used.
    filled : dict
        Channel -> ``{"samples": n, "longest_gap_s": s}`` of held null values.
    dropped_repeated_rows : int
        Rows dropped as exact repeats of a time stamp.
    start_time : str or None
        ISO date-time of the first row when the file gives it.
    notes : list of str
        Other rules applied (time derived from ROP, ...).
    time_origin_s : float
        The first row's time on the file's own clock, s: the elapsed time of
        a numeric time channel, POSIX seconds of a date-time one, 0 for time
        derived from depth. ``time_origin_s + time_s`` places rows of several
        files of one log (chunks) on one time axis.
    """

    table: pd.DataFrame
    source: str
    index: str
    channels: dict[str, str]
    ignored: tuple[str, ...] = ()
    filled: dict[str, dict[str, float]] = field(default_factory=dict)
    dropped_repeated_rows: int = 0
    start_time: str | None = None
    notes: tuple[str, ...] = ()
    time_origin_s: float = 0.0

    def report(self) -> dict[str, Any]:
        """JSON-ready summary of the import (for ``summary.json``)."""
        return {"source": self.source, "index": self.index, "rows": int(len(self.table)),
                "channels": dict(self.channels), "ignored_channels": list(self.ignored),
                "filled_null_values": {k: dict(v) for k, v in self.filled.items()},
                "dropped_repeated_rows": int(self.dropped_repeated_rows),
                "start_time": self.start_time, "notes": list(self.notes)}


def _norm(name: str) -> str:
    return " ".join(name.strip().replace("_", " ").replace("-", " ").lower().split())


@dataclass
class _Raw:
    """Columns read from a file before the common rules: name -> (values, unit, label)."""

    source: str
    index_name: str
    numeric: dict[str, np.ndarray]
    unit: dict[str, str | None]
    text: dict[str, pd.Series] = field(default_factory=dict)  # non-numeric (date-time) columns
    start_time: str | None = None
    origin: dict[str, str] = field(default_factory=dict)  # name -> the file's header, if other


def _assign(raw: _Raw, channel_map: Mapping[str, str]) -> tuple[dict[str, str], list[str]]:
    """stem -> raw column name, and the names left over."""
    for stem in channel_map:
        if stem not in CHANNELS:
            raise InputError("--channel", f"unknown channel {stem!r}", ", ".join(CHANNELS))
    names = list(raw.numeric) + [n for n in raw.text if n not in raw.numeric]
    by_norm = {_norm(n): n for n in names}
    chosen: dict[str, str] = {}
    for stem, mnem in channel_map.items():
        hit = by_norm.get(_norm(mnem))
        if hit is None:
            raise InputError("--channel", f"{stem}={mnem}: no channel {mnem!r} in {raw.source}",
                             ", ".join(names))
        chosen[stem] = hit
    used = set(chosen.values())
    for stem, ch in CHANNELS.items():
        if stem in chosen:
            continue
        hits = [n for n in names if n not in used and _norm(n) in ch.aliases]
        if stem == "hole_depth" and len(hits) > 1:
            # DEPT as a LAS index is the hole depth only when no DMEA/HDTH is given
            hits = [h for h in hits if _norm(h) not in ("dept", "depth")] or hits
        if len(hits) > 1:
            raise InputError(f"{raw.source}:{hits[1]}", f"channels {hits[0]!r} and {hits[1]!r} "
                             f"both look like the {stem.replace('_', ' ')}",
                             f"--channel {stem}=MNEMONIC to choose")
        if hits:
            chosen[stem] = hits[0]
            used.add(hits[0])
    return chosen, [n for n in names if n not in used]


def _holes(v: np.ndarray) -> list[tuple[int, int]]:
    """Runs [a, b) of NaN in ``v``."""
    bad = np.isnan(v)
    if not bad.any():
        return []
    d = np.diff(np.concatenate([[0], bad.astype(np.int8), [0]]))
    return list(zip(np.flatnonzero(d == 1).tolist(), np.flatnonzero(d == -1).tolist(),
                    strict=True))


def _fill(name: str, label: str, v: np.ndarray, t: np.ndarray, max_fill_s: float
          ) -> tuple[np.ndarray, dict[str, float] | None]:
    runs = _holes(v)
    if not runs:
        return v, None
    if len(runs) == 1 and runs[0] == (0, v.size):
        raise InputError(label, "no valid value (all null)", "a channel with data, or leave "
                         "it out")
    out = v.copy()
    longest = 0.0
    n = 0
    for a, b in runs:
        if a == 0:
            span = t[b] - t[0]
            out[a:b] = v[b]
        else:
            span = t[b - 1] - t[a - 1] if b == v.size else t[b] - t[a - 1]
            out[a:b] = v[a - 1]
        if span > max_fill_s:
            raise InputError(label, f"null values for {span:.0f} s from t = {t[a]:.0f} s",
                             f"runs of null values <= {max_fill_s:g} s (--max-fill-s)")
        longest = max(longest, float(span))
        n += b - a
    return out, {"samples": int(n), "longest_gap_s": longest}


def _datetime_seconds(col: pd.Series, label: str) -> tuple[np.ndarray, str]:
    try:
        ts = pd.to_datetime(col, errors="raise", utc=True, format="ISO8601")
    except (ValueError, TypeError):
        raise InputError(label, "time is neither seconds nor ISO 8601 date-time text",
                         "elapsed seconds (with a unit) or ISO 8601 date-times") from None
    if ts.isna().any():
        i = int(np.argmax(ts.isna().to_numpy()))
        raise InputError(label, f"row {i + 1}: no time", "a time in every row")
    sec = (ts - ts.iloc[0]).dt.total_seconds().to_numpy(dtype=np.float64)
    return sec, ts.iloc[0].isoformat()


def _finish(raw: _Raw, channel_map: Mapping[str, str], max_fill_s: float, max_gap_s: float,
            passthrough: Mapping[str, np.ndarray] | None = None) -> LogImport:
    """The rules common to every format: units, time, repeats, gaps, nulls, checks."""
    if not (math.isfinite(max_fill_s) and max_fill_s >= 0):
        raise InputError("--max-fill-s", f"got {max_fill_s}", ">= 0 s")
    if not (math.isfinite(max_gap_s) and max_gap_s > 0):
        raise InputError("--max-gap-s", f"got {max_gap_s}", "> 0 s")
    chosen, left = _assign(raw, channel_map)
    clock_s = 0.0  # POSIX seconds of the first row of a date-time index
    labels: dict[str, str] = {}
    si: dict[str, np.ndarray] = {}
    for stem, name in chosen.items():
        ch = CHANNELS[stem]
        unit = raw.unit.get(name)
        label = f"{raw.source}:{name}"
        labels[stem] = (raw.origin[name] if name in raw.origin
                        else f"{name} [{unit or ''}]".replace(" []", ""))
        if stem == "time" and name in raw.text:
            si[stem], raw.start_time = _datetime_seconds(raw.text[name], label)
            clock_s = pd.Timestamp(raw.start_time).timestamp()
            continue
        if name in raw.text:
            col = raw.text[name]
            bad = pd.to_numeric(col, errors="coerce").isna() & col.notna()
            i = int(np.argmax(bad.to_numpy()))
            raise InputError(label, f"row {i + 1}: not a number: {col.iloc[i]!r}",
                             "numbers (or null values)")
        if unit is None or not unit.strip():
            if ch.quantity == "rotary_speed":
                unit = "rpm"
            else:
                raise InputError(label, f"no unit for the {stem.replace('_', ' ')} channel",
                                 ", ".join(k for k in _units_of(ch.quantity)))
        si[stem] = raw.numeric[name] * unit_factor(ch.quantity, unit, label)
    notes: list[str] = []
    index = "time"
    if "time" not in si:
        depth_stem = "bit_md" if "bit_md" in si else "hole_depth"
        if depth_stem not in si or "rop" not in si:
            raise InputError(f"{raw.source}", "no time channel, and no depth and ROP to "
                             "derive it from", "a TIME channel, or a depth index with ROP")
        index = "depth"
        md, rop = si[depth_stem], si["rop"]
        lab_md = f"{raw.source}:{chosen[depth_stem]}"
        if np.isnan(md).any() or np.any(np.diff(md) <= 0):
            raise InputError(lab_md, "depth not strictly increasing (or null) in a depth-indexed "
                             "log without time", "strictly increasing depth, or a TIME channel")
        lab_rop = f"{raw.source}:{chosen['rop']}"
        r = rop[:-1]
        if np.isnan(r).any() or np.any(r <= 0):
            raise InputError(lab_rop, "ROP null or <= 0 in a depth-indexed log without time",
                             "ROP > 0 on every row, or a TIME channel")
        si["time"] = np.concatenate([[0.0], np.cumsum(np.diff(md) / r)])
        notes.append(f"time derived from depth and ROP: dt = d(depth) / ROP "
                     f"({chosen[depth_stem]}, {chosen['rop']})")
        labels["time"] = f"derived from {chosen[depth_stem]} / {chosen['rop']}"
    t = si["time"]
    lab_t = f"{raw.source}:{chosen.get('time', 'time')}"
    if np.isnan(t).any():
        i = int(np.argmax(np.isnan(t)))
        raise InputError(lab_t, f"row {i + 1}: null time", "a time in every row")
    if t.size < 2:
        raise InputError(lab_t, f"{t.size} row(s)", ">= 2 rows")
    dt = np.diff(t)
    if np.any(dt < 0):
        i = int(np.argmax(dt < 0)) + 1
        raise InputError(lab_t, f"time goes backwards at row {i + 1} ({t[i]:g} s after "
                         f"{t[i - 1]:g} s)", "non-decreasing time")
    cols = {stem: si[stem] for stem in si if stem != "time"}
    extra = dict(passthrough or {})
    keep = np.ones(t.size, dtype=bool)
    dropped = 0
    for i in (np.flatnonzero(dt == 0) + 1).tolist():
        j = i - 1
        for stem, v in cols.items():
            a, b = v[i], v[j]
            if not (a == b or (np.isnan(a) and np.isnan(b))):
                raise InputError(f"{raw.source}:{chosen[stem]}", f"two rows at time "
                                 f"{t[i]:g} s with different values ({b:g}, {a:g} in SI)",
                                 "one row per time stamp (exact repeats are dropped)")
        for name, v in extra.items():
            if not (v[i] == v[j] or (pd.isna(v[i]) and pd.isna(v[j]))):
                raise InputError(f"{raw.source}:{name}", f"two rows at time {t[i]:g} s with "
                                 "different values", "one row per time stamp")
        keep[i] = False
        dropped += 1
    if dropped:
        t = t[keep]
        cols = {k: v[keep] for k, v in cols.items()}
        extra = {k: v[keep] for k, v in extra.items()}
    steps = np.diff(t)
    if steps.size and steps.max() > max_gap_s:
        i = int(np.argmax(steps))
        raise InputError(lab_t, f"no sample for {steps[i]:.0f} s after t = {t[i]:.0f} s",
                         f"steps <= {max_gap_s:g} s (--max-gap-s; conditions are held across "
                         "a gap)")
    filled: dict[str, dict[str, float]] = {}
    for stem in list(cols):
        v, info = _fill(stem, f"{raw.source}:{chosen[stem]}", cols[stem], t, max_fill_s)
        cols[stem] = v
        if info is not None:
            filled[chosen[stem]] = info
    if "bit_md" not in cols:
        if "hole_depth" in cols and index == "depth":
            cols["bit_md"] = cols.pop("hole_depth")
            notes.append(f"bit depth = the depth index {chosen['hole_depth']} (a depth-indexed "
                         "log records the bit on bottom)")
            chosen["bit_md"] = chosen.pop("hole_depth")
            labels["bit_md"] = labels.pop("hole_depth")
        elif "bit_md_m" not in extra and "bit_md_ft" not in extra:
            raise InputError(raw.source, "no bit depth channel",
                             "BITDEP, DBTM, BIT DEPTH (with a unit), or --channel "
                             "bit_md=MNEMONIC")
    _check_depths(raw.source, chosen, cols, t)
    table = pd.DataFrame({"time_s": t - t[0]})
    for stem in CHANNELS:
        if stem in cols:
            table[CHANNELS[stem].column] = cols[stem]
    for name, v in extra.items():
        if name in table.columns:
            raise InputError(f"{raw.source}:{name}", "given twice (also by a field-named "
                             "channel)", "one column per channel")
        table[name] = v
    channels = {CHANNELS[s].column: labels[s] for s in chosen if s in labels}
    return LogImport(table=table, source=raw.source, index=index, channels=channels,
                     ignored=tuple(str(n) for n in left if n not in extra),
                     filled=filled, dropped_repeated_rows=dropped,
                     start_time=raw.start_time, notes=tuple(notes),
                     time_origin_s=0.0 if index == "depth" else clock_s + float(t[0]))


def _units_of(quantity: str) -> list[str]:
    return sorted(UNIT_SPELLINGS[quantity])


def _check_depths(source: str, chosen: Mapping[str, str], cols: Mapping[str, np.ndarray],
                  t: np.ndarray) -> None:
    """Unit mix-ups between channels: bit below the hole, ROP vs the deepening hole."""
    hole = np.maximum.accumulate(cols["hole_depth"]) if "hole_depth" in cols else (
        np.maximum.accumulate(cols["bit_md"]) if "bit_md" in cols else None)
    if "bit_md" in cols and "hole_depth" in cols:
        assert hole is not None  # set from hole_depth just above
        over = cols["bit_md"] - hole
        if over.max() > BIT_BELOW_HOLE_TOLERANCE_M:
            i = int(np.argmax(over))
            raise InputError(f"{source}:{chosen['bit_md']}", f"bit depth {cols['bit_md'][i]:.1f} m "
                             f"is {over[i]:.1f} m below the hole depth {hole[i]:.1f} m at t = "
                             f"{t[i] - t[0]:.0f} s; check the depth units",
                             f"bit depth <= hole depth (+{BIT_BELOW_HOLE_TOLERANCE_M:g} m)")
    if "rop" in cols and hole is not None:
        deepening = np.diff(hole)
        drilled = float(deepening.sum())
        if drilled > 1.0:
            on = deepening > 0
            integrated = float(np.sum(cols["rop"][:-1][on] * np.diff(t)[on]))
            ratio = integrated / drilled
            f = ROP_CONSISTENCY_FACTOR
            if not (1.0 / f <= ratio <= f):
                raise InputError(f"{source}:{chosen['rop']}", f"ROP integrated over the "
                                 f"drilling time gives {integrated:.1f} m but the hole deepened "
                                 f"{drilled:.1f} m (x{ratio:.2f}); check the ROP unit",
                                 f"ROP consistent with the depth within a factor {f:g}")


# --- the twin's table ---------------------------------------------------------

def log_times_s(log: pd.DataFrame) -> np.ndarray:
    """Time stamps of a log in seconds (``time_s``, or ``time`` as date-time or seconds)."""
    if "time_s" in log.columns:
        t = pd.to_numeric(log["time_s"], errors="coerce").to_numpy(dtype=np.float64)
        name = "time_s"
    elif "time" in log.columns:
        name = "time"
        t = pd.to_numeric(log["time"], errors="coerce").to_numpy(dtype=np.float64)
        if not np.all(np.isfinite(t)):
            try:
                ts = pd.to_datetime(log["time"], errors="raise", utc=True)
            except (ValueError, TypeError):
                raise InputError("time", "not seconds nor date-time text",
                                 "seconds or ISO 8601 date-times") from None
            t = (ts - ts.iloc[0]).dt.total_seconds().to_numpy(dtype=np.float64)
    else:
        raise InputError("time_s", "missing column in the log", "time_s or time")
    if not np.all(np.isfinite(t)):
        raise InputError(name, "non-numeric or NaN time", "finite times")
    if t.size < 2 or np.any(np.diff(t) < 0):
        raise InputError(name, "fewer than 2 rows or time going backwards",
                         ">= 2 rows, non-decreasing time")
    return t


def log_bit_md_m(log: pd.DataFrame) -> np.ndarray:
    """Bit depth of a twin log table in m: ``bit_md_m`` or ``bit_md`` with another length
    suffix (``bit_md_ft``, :data:`drillfatigue.io.names.UNIT_FAMILIES`)."""
    names = [(str(c), UNIT_FAMILIES["_m"][str(c)[len("bit_md"):]]) for c in log.columns
             if str(c).startswith("bit_md_") and str(c)[len("bit_md"):] in UNIT_FAMILIES["_m"]]
    if not names:
        raise InputError("bit_md_m", "missing column in the log", "bit_md_m or bit_md_ft")
    if len(names) > 1:
        raise InputError(names[1][0], f"given together with {names[0][0]}", "one bit depth")
    name, fac = names[0]
    v = pd.to_numeric(log[name], errors="coerce").to_numpy(dtype=np.float64)
    if not np.all(np.isfinite(v)):
        raise InputError(name, "non-numeric or NaN value", "finite depths")
    check_feature_values(name, "bit_md_m", v * fac, fac)
    return v * fac


# --- formats ------------------------------------------------------------------

def _read_las(p: Path) -> _Raw:
    try:
        las = lasio.read(str(p), ignore_header_errors=False, ignore_data_comments="#")
    except (lasio.exceptions.LASHeaderError, lasio.exceptions.LASDataError,
            lasio.exceptions.LASUnknownUnitError, ValueError, KeyError, IndexError,
            UnicodeDecodeError) as exc:
        msg = " ".join(str(exc).split())[:160]
        raise InputError(str(p), f"unreadable LAS file ({type(exc).__name__}: {msg})",
                         "a LAS 2.0 file") from None
    vers = las.version["VERS"].value if "VERS" in las.version else None
    try:
        v = float(str(vers))
    except (TypeError, ValueError):
        v = float("nan")
    if v not in (1.2, 2.0):
        raise InputError(f"{p}:~VERSION", f"LAS version {str(vers)!r}", "LAS 2.0 (or 1.2)")
    if not las.curves:
        raise InputError(str(p), "no curves", "a ~Curve section and data")
    numeric: dict[str, np.ndarray] = {}
    unit: dict[str, str | None] = {}
    text: dict[str, pd.Series] = {}
    for c in las.curves:
        name = c.mnemonic
        if name in numeric or name in text:
            raise InputError(f"{p}:{name}", "curve listed twice", "unique mnemonics")
        data = np.asarray(c.data)
        if data.dtype.kind in "fiu":
            numeric[name] = data.astype(np.float64)
        else:
            num = pd.to_numeric(pd.Series(data), errors="coerce").to_numpy(dtype=np.float64)
            if np.isfinite(num).sum() == np.sum(pd.notna(pd.Series(data))):
                numeric[name] = num
            else:
                text[name] = pd.Series(data)
        unit[name] = c.unit or None
    if numeric:
        n = len(next(iter(numeric.values())))
        if n == 0:
            raise InputError(str(p), "no data rows", ">= 2 rows")
    return _Raw(source=str(p), index_name=las.curves[0].mnemonic, numeric=numeric, unit=unit,
                text=text)


def _local(tag: str) -> str:
    return tag.rsplit("}", 1)[-1]


def _read_witsml(p: Path) -> _Raw:
    try:
        root = ET.parse(p).getroot()
    except ET.ParseError as exc:
        raise InputError(str(p), f"not well-formed XML ({exc})",
                         "a WITSML 1.4.1.1 log file") from None
    logs = [e for e in root.iter() if _local(e.tag) == "log"]
    if _local(root.tag) not in ("logs", "log") or not logs:
        raise InputError(str(p), f"root element {_local(root.tag)!r} holds no log",
                         "a WITSML 1.4.1.1 <logs> with one <log>")
    if len(logs) > 1:
        raise InputError(str(p), f"{len(logs)} log objects", "one log per file")
    version = root.get("version")
    if version is not None and not version.startswith("1.4"):
        raise InputError(str(p), f"WITSML version {version!r}", "1.4.1.1 (or another 1.4.x)")
    log = logs[0]
    kids = {_local(c.tag): c for c in log}
    null_log = (kids["nullValue"].text or "").strip() if "nullValue" in kids else None
    info: dict[str, dict[str, str | None]] = {}
    for c in log:
        if _local(c.tag) != "logCurveInfo":
            continue
        f = {_local(x.tag): (x.text or "").strip() for x in c}
        m = f.get("mnemonic")
        if m:
            info[m] = {"unit": f.get("unit") or None, "null": f.get("nullValue") or None,
                       "type": f.get("typeLogData")}
    data_el = kids.get("logData")
    if data_el is None:
        raise InputError(f"{p}:logData", "missing", "a <logData> with mnemonicList and data")
    dk = {_local(c.tag): c for c in data_el}
    if "mnemonicList" not in dk:
        raise InputError(f"{p}:logData/mnemonicList", "missing", "comma-separated mnemonics")
    mnems = [m.strip() for m in (dk["mnemonicList"].text or "").split(",")]
    if len(set(mnems)) != len(mnems) or not all(mnems):
        raise InputError(f"{p}:logData/mnemonicList", "empty or repeated mnemonic",
                         "unique mnemonics")
    units_list = ([u.strip() for u in (dk["unitList"].text or "").split(",")]
                  if "unitList" in dk else [""] * len(mnems))
    if len(units_list) != len(mnems):
        raise InputError(f"{p}:logData/unitList", f"{len(units_list)} units for {len(mnems)} "
                         "mnemonics", "one unit per mnemonic")
    rows = [d.text or "" for d in data_el if _local(d.tag) == "data"]
    cells = []
    for k, r in enumerate(rows):
        parts = [x.strip() for x in r.split(",")]
        if len(parts) != len(mnems):
            raise InputError(f"{p}:logData/data[{k + 1}]", f"{len(parts)} values",
                             f"{len(mnems)} values (one per mnemonic)")
        cells.append(parts)
    cols = list(zip(*cells, strict=True)) if cells else [() for _ in mnems]
    numeric: dict[str, np.ndarray] = {}
    unit: dict[str, str | None] = {}
    text: dict[str, pd.Series] = {}
    for j, m in enumerate(mnems):
        ci = info.get(m, {})
        u = units_list[j] or ci.get("unit")
        if u and ci.get("unit") and _norm(u) != _norm(str(ci["unit"])):
            raise InputError(f"{p}:{m}", f"unit {u!r} in unitList but {ci['unit']!r} in "
                             "logCurveInfo", "one unit per curve")
        nulls = {"", *(x for x in (null_log, ci.get("null")) if x)}
        vals = [None if x in nulls else x for x in cols[j]]
        s = pd.Series(vals, dtype=object)
        num = pd.to_numeric(s, errors="coerce")
        if int(num.notna().sum()) == int(s.notna().sum()) and ci.get("type") != "date time":
            numeric[m] = num.to_numpy(dtype=np.float64)
        else:
            text[m] = s
        unit[m] = None if (u or "").lower() in ("", "unitless", "none") else u
    index_curve = (kids["indexCurve"].text or "").strip() if "indexCurve" in kids else mnems[0]
    return _Raw(source=str(p), index_name=index_curve, numeric=numeric, unit=unit, text=text)


def _is_value(cell: str) -> bool:
    """Whether a CSV cell is a number or an ISO 8601 date-time (data, not a unit)."""
    try:
        float(cell)
        return True
    except ValueError:
        pass
    return not pd.isna(pd.to_datetime(cell, errors="coerce", utc=True, format="ISO8601"))


def _put(numeric: Mapping[str, Any], text: Mapping[str, Any], label: str, key: str,
         p: Path) -> None:
    """Refuse a second CSV column for one channel (``wob_kN`` and ``WOB (klbf)``)."""
    if label in numeric or label in text:
        raise InputError(f"{p}:{key}", f"a second column for {label!r}", "one column per channel")


def _read_csv(p: Path) -> tuple[_Raw, dict[str, np.ndarray]]:
    # a ragged row or a column named twice is refused naming the row; an empty cell is
    # a null sample (held from the previous one, see _fill)
    table = read_csv_file(p, allow_empty=True, skipinitialspace=True, dtype=str,
                          keep_default_na=False)
    if len(table) == 0:
        raise InputError(str(p), "no rows", ">= 2 rows")
    # a units row under the header ('s, ft, klbf'): no cell of it is a number or a date-time
    first = [str(c).strip() for c in table.iloc[0]]
    units_row = None
    if any(first) and not any(_is_value(c) for c in first if c):
        units_row = table.iloc[0]
        table = table.iloc[1:].reset_index(drop=True)
    numeric: dict[str, np.ndarray] = {}
    unit: dict[str, str | None] = {}
    text: dict[str, pd.Series] = {}
    passthrough: dict[str, np.ndarray] = {}
    origin: dict[str, str] = {}
    for h in table.columns:
        col = table[h].str.strip()
        key = str(h).strip()
        name, u = split_header(key)
        if units_row is not None and str(units_row[h]).strip():
            u = str(units_row[h]).strip().strip("()[]")
        num = pd.to_numeric(col.replace("", np.nan), errors="coerce")
        is_num = int(num.notna().sum()) == int((col != "").sum())
        # a twin-style name with a unit suffix: wob_kN, rop_ft_per_h, bit_md_ft, time_s
        stem = channel_stem(key)
        suffix = key[len(stem):]
        hit = next((s for s, ch in CHANNELS.items() if _norm(stem) in ch.aliases), None)
        if suffix and hit is not None and (units_row is None or not str(units_row[h]).strip()):
            fam = UNIT_FAMILIES.get(_FAMILY_OF.get(CHANNELS[hit].quantity, ""), {}) | \
                CHANNEL_FAMILIES.get(_FAMILY_OF.get(CHANNELS[hit].quantity, ""), {})
            if suffix in fam:
                _put(numeric, text, stem, key, p)
                origin[stem] = key
                numeric[stem] = num.to_numpy(dtype=np.float64) * fam[suffix]
                unit[stem] = {"length": "m", "force": "N", "speed": "m/s", "torque": "N.m",
                              "pressure": "Pa", "flow": "m3/s"}[CHANNELS[hit].quantity]
                continue
        if key in ("time_s", "time") and is_num:
            # the twin's own time columns: seconds
            _put(numeric, text, "time", key, p)
            origin["time"] = key
            numeric["time"] = num.to_numpy(dtype=np.float64)
            unit["time"] = "s"
            continue
        if u is None and key not in ("time",) and _norm(key) not in {a for ch in CHANNELS.values()
                                                                     for a in ch.aliases}:
            # not a field channel: a twin feature column (mud_density_sg, ...), kept as is
            passthrough[key] = (num.to_numpy(dtype=np.float64) if is_num
                                else col.to_numpy(dtype=object))
            continue
        label = name if u is not None else key
        _put(numeric, text, label, key, p)
        if is_num:
            numeric[label] = num.to_numpy(dtype=np.float64)
        else:
            text[label] = col.replace("", None)
        unit[label] = u
    return _Raw(source=str(p), index_name=str(table.columns[0]), numeric=numeric, unit=unit,
                text=text, origin=origin), passthrough


def load_log(path: str | Path, channel_map: Mapping[str, str] | None = None,
             max_fill_s: float = DEFAULT_MAX_FILL_S,
             max_gap_s: float = DEFAULT_MAX_GAP_S) -> LogImport:
    """Read an operating log (``.las``, ``.xml`` WITSML 1.4.1.1 log, ``.csv``) into SI.

    Parameters
    ----------
    path : path-like
    channel_map : mapping, optional
        ``{stem: mnemonic}`` choosing a file's channel for a stem of
        :data:`CHANNELS` (``{"rpm": "SURF_RPM"}``).
    max_fill_s : float
        Longest run of null values held from the previous value, s.
    max_gap_s : float
        Longest step between two samples, s.

    Raises
    ------
    InputError
        See the module docstring; the field names the file and the channel.
    """
    p = Path(path)
    if not p.is_file():
        raise InputError(str(p), "log file not found", "an existing .las, .xml or .csv file")
    suffix = p.suffix.lower()
    cmap = dict(channel_map or {})
    if suffix == ".las":
        return _finish(_read_las(p), cmap, max_fill_s, max_gap_s)
    if suffix == ".xml":
        return _finish(_read_witsml(p), cmap, max_fill_s, max_gap_s)
    if suffix in (".csv", ".txt"):
        raw, extra = _read_csv(p)
        return _finish(raw, cmap, max_fill_s, max_gap_s, passthrough=extra)
    raise InputError(str(p), f"unknown log file type {p.suffix or '(none)'!r}",
                     ".las (LAS 2.0), .xml (WITSML 1.4.1.1 log), .csv")
