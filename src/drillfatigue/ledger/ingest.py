"""Ingest a run's log into the ledger, each sample interval counted exactly once.

The run keeps a cursor: the time and values of its last ingested sample and
the number of chunks so far. A chunk (a table of samples on the run's time
axis) is handled in three steps:

1. **What is new.** A chunk whose content hash the run has seen is a
   duplicate and changes nothing. Otherwise only its samples after the
   cursor's time are new (an overlapping chunk counts only its new part; a
   chunk wholly at or before the cursor adds nothing). The stretch handed
   to the damage function is the cursor's sample followed by the new
   samples, so the interval from the previous chunk's last sample to this
   chunk's first new one is counted once, at the held previous values (the
   twin's piecewise-constant rule).
2. **Damage.** The run's damage function (the twin, through
   :mod:`drillfatigue.ledger.twin_adapter`, or an injected one) gives the
   per (serial, location) increments; the ledger adds time in hole and
   revolutions (:func:`drillfatigue.ledger.increments.exposure`).
3. **One transaction.** The run's chunk counter is advanced by a
   compare-and-set (``UPDATE runs ... WHERE chunk_seq = <read value>``); the
   chunk row (unique per run by hash and by sequence number), its increments
   and the running totals are written with it. If another ingester advanced
   the run first, the transaction is rolled back and the chunk is
   reconsidered from step 1. No lock file: the database's transactions and
   unique keys decide, on SQLite and PostgreSQL alike.

A chunk that fails to parse or check is refused whole before anything is
written (:class:`~drillfatigue.errors.InputError`, one line).
"""

from __future__ import annotations

import hashlib
import importlib
import json
import math
import tempfile
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd
from sqlalchemy import bindparam, insert, select, update
from sqlalchemy.exc import IntegrityError, OperationalError

from drillfatigue.errors import InputError
from drillfatigue.io.logs import DEFAULT_MAX_FILL_S, DEFAULT_MAX_GAP_S, load_log
from drillfatigue.ledger.db import Ledger
from drillfatigue.ledger.increments import DamageFunction, RunContext, check_increments, exposure
from drillfatigue.ledger.schema import chunks, damage_increments, damage_totals, runs
from drillfatigue.ledger.store import ENDED, now_utc, run_context, run_row
from drillfatigue.ledger.twin_adapter import PYTHON_PREFIX, twin_increments

#: Samples per chunk when a file is ingested in pieces (one hour of a 1 Hz log).
DEFAULT_CHUNK_ROWS = 3600
#: formats of a chunk given as content instead of a file (the service's ``log.format``),
#: with the file suffix its reader (:func:`drillfatigue.io.logs.load_log`) goes by
LOG_FORMATS: dict[str, str] = {"csv": ".csv", "las": ".las", "witsml": ".xml"}
_MAX_ATTEMPTS = 200


@dataclass(frozen=True)
class LogChunk:
    """Samples of a run's log on its time axis.

    ``table``: ``time_s`` (s on the log's own clock: elapsed seconds, or POSIX
    seconds for date-time logs), ``bit_md_m`` and the other channels in SI.
    """

    table: pd.DataFrame
    source: str


@dataclass(frozen=True)
class IngestReport:
    """What one chunk did to the ledger."""

    run: str
    source: str
    status: str            # "ingested", "duplicate" or "nothing new"
    seq: int | None
    n_rows: int
    n_new_rows: int
    t_first_s: float
    t_last_s: float

    def line(self) -> str:
        """One line for the terminal."""
        span = f"t = {self.t_first_s:.6g} .. {self.t_last_s:.6g} s"
        if self.status == "ingested":
            return (f"{self.source}: chunk {self.seq} of run {self.run}: {self.n_new_rows} new "
                    f"of {self.n_rows} samples ({span})")
        if self.status == "duplicate":
            return f"{self.source}: already ingested as chunk {self.seq} of run {self.run}"
        return (f"{self.source}: nothing new for run {self.run}: every sample is at or before "
                f"the last ingested one ({span})")


class _Conflict(Exception):
    """Another ingester advanced the run between our read and our write."""


def damage_function_for(model_ref: str) -> DamageFunction:
    """The damage function of a run: the twin, or ``python:MODULE:FUNCTION``."""
    if not model_ref.startswith(PYTHON_PREFIX):
        return twin_increments
    spec = model_ref[len(PYTHON_PREFIX):]
    mod, _, attr = spec.partition(":")
    try:
        fn = getattr(importlib.import_module(mod), attr)
    except (ImportError, AttributeError, ValueError):
        raise InputError("--damage-function", f"cannot import {spec!r}",
                         "MODULE:FUNCTION of an importable damage function") from None
    if not callable(fn):
        raise InputError("--damage-function", f"{spec!r} is not callable", "a function")
    return fn  # type: ignore[no-any-return]


def read_log_file(path: str | Path, channel_map: dict[str, str] | None = None,
                  max_fill_s: float = DEFAULT_MAX_FILL_S,
                  max_gap_s: float = DEFAULT_MAX_GAP_S) -> LogChunk:
    """A log file (LAS, WITSML XML, CSV) as a chunk on its own clock (:class:`LogChunk`).

    Raises
    ------
    InputError
        The reader's errors (:func:`drillfatigue.io.logs.load_log`), or a
        depth-indexed log (the ledger needs times to place chunks).
    """
    imp = load_log(path, channel_map, max_fill_s, max_gap_s)
    if imp.index != "time":
        raise InputError(str(path), "a depth-indexed log without time",
                         "a log with a time channel (chunks are placed on the run's time axis)")
    table = imp.table.copy()
    table["time_s"] = table["time_s"].to_numpy(dtype=np.float64) + imp.time_origin_s
    return LogChunk(table=table, source=str(path))


def read_log_bytes(data: bytes, suffix: str, source: str,
                   channel_map: dict[str, str] | None = None) -> LogChunk:
    """:func:`read_log_file` of file content held in memory (a growing file's complete lines)."""
    with tempfile.TemporaryDirectory(prefix="ledger-chunk-") as tmp:
        p = Path(tmp) / f"chunk{suffix}"
        p.write_bytes(data)
        try:
            chunk = read_log_file(p, channel_map)
        except InputError as exc:
            raise InputError(source, exc.problem, exc.allowed) from None
    return LogChunk(table=chunk.table, source=source)


def split_rows(chunk: LogChunk, rows: int, start_row: int = 0) -> Iterator[LogChunk]:
    """Pieces of ``rows`` samples, cut at fixed row positions of the file (so a
    restart cuts the same pieces); the source names the rows (1-based)."""
    if rows < 2:
        raise InputError("--chunk-rows", f"{rows}", ">= 2")
    n = len(chunk.table)
    for a in range(0, n, rows):
        b = min(a + rows, n)
        yield LogChunk(table=chunk.table.iloc[a:b].reset_index(drop=True),
                       source=f"{chunk.source}#rows {start_row + a + 1}-{start_row + b}")


def table_sha256(table: pd.DataFrame) -> str:
    """Hash of a chunk's content: its column names and values (float64 bytes for
    numbers, text otherwise), independent of the file format it came in."""
    h = hashlib.sha256()
    for col in table.columns:
        h.update(str(col).encode() + b"\x00")
        v = table[col]
        if pd.api.types.is_numeric_dtype(v) and not pd.api.types.is_bool_dtype(v):
            h.update(np.ascontiguousarray(v.to_numpy(dtype=np.float64)).tobytes())
        else:
            h.update("\x1f".join(map(str, v.tolist())).encode())
    return h.hexdigest()


def check_chunk(table: pd.DataFrame, source: str) -> pd.DataFrame:
    """A chunk's table with checked time and bit depth (InputError naming the source)."""
    for col in ("time_s", "bit_md_m"):
        if col not in table.columns:
            raise InputError(f"{source}:{col}", "missing column", "time_s and bit_md_m (SI)")
    t = pd.to_numeric(table["time_s"], errors="coerce").to_numpy(dtype=np.float64)
    if len(t) == 0:
        raise InputError(source, "no samples", ">= 1 sample")
    if not np.all(np.isfinite(t)) or np.any(np.diff(t) <= 0):
        raise InputError(f"{source}:time_s", "non-finite or not strictly increasing time",
                         "strictly increasing finite times")
    md = pd.to_numeric(table["bit_md_m"], errors="coerce").to_numpy(dtype=np.float64)
    if not np.all(np.isfinite(md)) or np.any(md < 0):
        raise InputError(f"{source}:bit_md_m", "negative, NaN or non-numeric bit depth",
                         "bit depth >= 0 m")
    out = table.reset_index(drop=True).copy()
    out["time_s"] = t
    out["bit_md_m"] = md
    return out


def _sample_json(row: pd.Series) -> str:
    return json.dumps({str(k): (v.item() if hasattr(v, "item") else v) for k, v in row.items()})


def _increments(seg: pd.DataFrame, ctx: RunContext, fn: DamageFunction,
                source: str) -> pd.DataFrame:
    loc = ctx.locations()
    inc = check_increments(fn(seg, ctx), loc, source)
    exp = exposure(seg, loc, ctx.constants)
    inc["time_in_hole_s"] = exp["time_in_hole_s"].to_numpy()
    inc["revolutions"] = exp["revolutions"].to_numpy()
    ids = dict(zip(ctx.items["serial"].astype(str), ctx.items["joint_id"].astype(int),
                   strict=True))
    inc["joint_id"] = [ids[str(s)] for s in inc["serial"]]
    return inc


def _f(v: Any) -> float | None:
    f = float(v)
    return None if math.isnan(f) else f


_TOTALS_COVERED = (
    update(damage_totals)
    .where(damage_totals.c.joint_id == bindparam("j"), damage_totals.c.location == bindparam("l"))
    .values(damage=damage_totals.c.damage + bindparam("d"),
            damage_lower=damage_totals.c.damage_lower + bindparam("dl"),
            damage_upper=damage_totals.c.damage_upper + bindparam("du"),
            time_in_hole_s=damage_totals.c.time_in_hole_s + bindparam("th"),
            revolutions=damage_totals.c.revolutions + bindparam("rv"),
            ood_time_s=damage_totals.c.ood_time_s + bindparam("od")))
_TOTALS_NOT_COVERED = (
    update(damage_totals)
    .where(damage_totals.c.joint_id == bindparam("j"), damage_totals.c.location == bindparam("l"))
    .values(time_in_hole_s=damage_totals.c.time_in_hole_s + bindparam("th"),
            revolutions=damage_totals.c.revolutions + bindparam("rv"),
            not_covered_time_s=damage_totals.c.not_covered_time_s + bindparam("th"),
            not_covered_reason=bindparam("why")))


def ingest_chunk(ledger: Ledger, run: str, chunk: LogChunk,
                 damage_fn: DamageFunction | None = None) -> IngestReport:
    """Ingest one chunk into ``run`` exactly once (see the module docstring).

    Parameters
    ----------
    ledger : Ledger
    run : str
        Run name.
    chunk : LogChunk
    damage_fn : callable, optional
        Overrides the run's damage function (tests inject a stand-in here).
    """
    table = check_chunk(chunk.table, chunk.source)
    sha = table_sha256(table)
    t = table["time_s"].to_numpy()

    def report(status: str, seq: int | None, n_new: int) -> IngestReport:
        return IngestReport(run=run, source=chunk.source, status=status, seq=seq,
                            n_rows=len(table), n_new_rows=n_new, t_first_s=float(t[0]),
                            t_last_s=float(t[-1]))

    for _ in range(_MAX_ATTEMPTS):
        with ledger.read() as conn:
            r = run_row(conn, run)
            if r.status == ENDED:
                raise InputError("--run", f"run {run!r} has ended", "an open run")
            dup = conn.execute(select(chunks.c.seq).where(
                chunks.c.run_id == r.id, chunks.c.content_sha256 == sha)).first()
            if dup is not None:
                return report("duplicate", int(dup[0]), 0)
            new = table if r.last_t_s is None else table[table["time_s"] > r.last_t_s]
            if new.empty:
                return report("nothing new", None, 0)
            ctx = run_context(conn, r)
        if r.last_sample_json is not None:
            prev = json.loads(r.last_sample_json)
            if set(prev) != set(map(str, table.columns)):
                diff = sorted(set(prev) ^ set(map(str, table.columns)))
                raise InputError(chunk.source, f"channels differ from the run's earlier chunks "
                                 f"({', '.join(diff)})", "the same channels in every chunk")
            seg = pd.concat([pd.DataFrame([prev])[list(table.columns)], new], ignore_index=True)
        else:
            seg = new.reset_index(drop=True)
        fn = damage_fn if damage_fn is not None else damage_function_for(r.model_ref)
        inc = _increments(seg, ctx, fn, chunk.source) if len(seg) >= 2 else None
        try:
            with ledger.write() as conn:
                res = conn.execute(
                    update(runs).where(runs.c.id == r.id, runs.c.chunk_seq == r.chunk_seq)
                    .values(chunk_seq=r.chunk_seq + 1, last_t_s=float(new["time_s"].iloc[-1]),
                            last_sample_json=_sample_json(new.iloc[-1]),
                            first_t_s=r.first_t_s if r.first_t_s is not None
                            else float(seg["time_s"].iloc[0])))
                if res.rowcount != 1:
                    raise _Conflict
                seq = r.chunk_seq + 1
                chunk_id = conn.execute(insert(chunks).values(
                    run_id=r.id, seq=seq, source=chunk.source, content_sha256=sha,
                    t_first_s=float(t[0]), t_last_s=float(t[-1]),
                    counted_from_s=float(seg["time_s"].iloc[0]), n_rows=len(table),
                    n_new_rows=len(new), ingested_at=now_utc()).returning(chunks.c.id)).scalar_one()
                if inc is not None:
                    _write_increments(conn, chunk_id, inc)
        except (_Conflict, IntegrityError):
            continue
        except OperationalError as exc:
            if _retryable(exc):
                continue
            raise
        return report("ingested", seq, len(new))
    raise RuntimeError(f"{chunk.source}: run {run!r} kept changing under {_MAX_ATTEMPTS} attempts "
                       "to ingest this chunk")


def _retryable(exc: OperationalError) -> bool:
    # PostgreSQL serialization failures and deadlocks; SQLite "database is locked"
    code = getattr(exc.orig, "sqlstate", None)
    return code in ("40001", "40P01") or "database is locked" in str(exc.orig)


def _write_increments(conn: Any, chunk_id: int, inc: pd.DataFrame) -> None:
    rows = []
    cov_rows = []
    nc_rows = []
    for it in inc.itertuples(index=False):
        covered = bool(it.covered)
        th, rv, od = float(it.time_in_hole_s), float(it.revolutions), float(it.ood_time_s)
        rows.append({"chunk_id": chunk_id, "joint_id": int(it.joint_id),
                     "location": str(it.location), "covered": covered,
                     "not_covered_reason": None if covered else str(it.not_covered_reason),
                     "damage": _f(it.damage), "damage_lower": _f(it.damage_lower),
                     "damage_upper": _f(it.damage_upper), "time_in_hole_s": th,
                     "revolutions": rv, "ood_time_s": od})
        key = {"j": int(it.joint_id), "l": str(it.location), "th": th, "rv": rv}
        if covered:
            cov_rows.append({**key, "d": float(it.damage), "dl": float(it.damage_lower),
                             "du": float(it.damage_upper), "od": od})
        else:
            nc_rows.append({**key, "why": str(it.not_covered_reason)})
    conn.execute(insert(damage_increments), rows)
    if cov_rows:
        conn.execute(_TOTALS_COVERED, cov_rows)
    if nc_rows:
        conn.execute(_TOTALS_NOT_COVERED, nc_rows)


def ingest_file(ledger: Ledger, run: str, path: str | Path, chunk_rows: int = DEFAULT_CHUNK_ROWS,
                damage_fn: DamageFunction | None = None,
                channel_map: dict[str, str] | None = None,
                on_report: Callable[[IngestReport], None] | None = None) -> list[IngestReport]:
    """Ingest a log file into ``run`` in pieces of ``chunk_rows`` samples.

    The whole file is parsed first: a file that fails to parse is refused
    before anything is recorded. Each piece is one transaction, so a process
    killed part-way leaves whole pieces; running the same command again
    skips them as duplicates and goes on.
    """
    chunk = read_log_file(path, channel_map)
    reports = []
    for piece in split_rows(chunk, chunk_rows):
        rep = ingest_chunk(ledger, run, piece, damage_fn)
        reports.append(rep)
        if on_report is not None:
            on_report(rep)
    return reports
