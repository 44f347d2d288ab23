"""Follow a log while the well is drilled: a growing CSV/LAS file, or a folder of chunks.

Every ``every_s`` seconds the source is polled and what is new is ingested
(:func:`drillfatigue.ledger.ingest.ingest_chunk`); the ledger's cursor is the
only state, so a follow killed at any point and started again resumes where
the ledger stands.

Growing file
    Only complete lines are read (a line being written is left for the next
    poll). The samples after the run's cursor are cut into pieces at fixed
    row positions of the file (multiples of ``chunk_rows``), so a restart
    cuts the same pieces as an uninterrupted follow. A last, incomplete
    piece is ingested once the file has not grown for one poll.
Folder of chunks
    Every ``.xml`` (WITSML 1.4.1.1 log), ``.las`` or ``.csv`` file in the folder
    is one chunk, ingested in the order of its first time stamp. A file that
    does not parse is left for the next poll while it is still changing; one
    that stays the same and still does not parse is refused with one line
    and skipped.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

from drillfatigue.errors import InputError
from drillfatigue.ledger.db import Ledger
from drillfatigue.ledger.increments import DamageFunction
from drillfatigue.ledger.ingest import (
    IngestReport,
    LogChunk,
    ingest_chunk,
    read_log_bytes,
    read_log_file,
)
from drillfatigue.ledger.store import run_row

CHUNK_SUFFIXES = (".xml", ".las", ".csv")
FILE_SUFFIXES = (".csv", ".las", ".txt")


@dataclass
class FollowSummary:
    """What a follow did: polls, chunks ingested, one-line refusals."""

    polls: int = 0
    ingested: int = 0
    refused: list[str] = field(default_factory=list)


@dataclass
class _FileState:
    size: int = -1


def _cursor(ledger: Ledger, run: str) -> float | None:
    with ledger.read() as conn:
        r = run_row(conn, run)
        return None if r.last_t_s is None else float(r.last_t_s)


def _poll_file(ledger: Ledger, run: str, path: Path, chunk_rows: int, state: _FileState,
               damage_fn: DamageFunction | None,
               on_report: Callable[[IngestReport], None]) -> int:
    data = path.read_bytes() if path.is_file() else b""
    complete = data[:data.rfind(b"\n") + 1]
    idle = len(data) == state.size
    state.size = len(data)
    if not complete.strip():
        return 0
    try:
        whole = read_log_bytes(complete, path.suffix.lower(), str(path))
    except InputError:
        if not idle:
            return 0  # still being written: the header or a row may be incomplete
        raise
    t = whole.table["time_s"].to_numpy()
    last = _cursor(ledger, run)
    p = 0 if last is None else int((t <= last).sum())
    n = len(t)
    done = 0
    while p < n:
        block_end = (p // chunk_rows + 1) * chunk_rows
        end = min(block_end, n)
        if end < block_end and not idle:
            break  # an incomplete last piece waits for more rows or a quiet poll
        piece = LogChunk(table=whole.table.iloc[p:end].reset_index(drop=True),
                         source=f"{path}#rows {p + 1}-{end}")
        rep = ingest_chunk(ledger, run, piece, damage_fn)
        on_report(rep)
        done += rep.status == "ingested"
        p = end
    return done


def _poll_folder(ledger: Ledger, run: str, folder: Path, seen: dict[str, tuple[int, int]],
                 failed: dict[str, tuple[int, int]], summary: FollowSummary,
                 damage_fn: DamageFunction | None,
                 on_report: Callable[[IngestReport], None]) -> int:
    ready: list[LogChunk] = []
    for f in sorted(folder.iterdir()):
        if f.suffix.lower() not in CHUNK_SUFFIXES or not f.is_file():
            continue
        st = f.stat()
        sig = (st.st_size, st.st_mtime_ns)
        if seen.get(f.name) == sig:
            continue
        try:
            ready.append(read_log_file(f))
        except InputError as exc:
            if failed.get(f.name) == sig:
                summary.refused.append(f"{f.name}: {exc.one_line()}")
                seen[f.name] = sig
            else:
                failed[f.name] = sig
            continue
        seen[f.name] = sig
    ready.sort(key=lambda c: (float(c.table["time_s"].iloc[0]), c.source))
    done = 0
    for chunk in ready:
        rep = ingest_chunk(ledger, run, chunk, damage_fn)
        on_report(rep)
        done += rep.status == "ingested"
    return done


def follow(ledger: Ledger, run: str, source: str | Path, every_s: float = 10.0,
           chunk_rows: int = 60, max_polls: int | None = None, until_idle: int | None = None,
           damage_fn: DamageFunction | None = None,
           on_report: Callable[[IngestReport], None] | None = None,
           on_refused: Callable[[str], None] | None = None) -> FollowSummary:
    """Poll ``source`` every ``every_s`` s and ingest what is new into ``run``.

    Parameters
    ----------
    source : path
        A growing ``.csv``/``.las`` file, or a folder of chunk files.
    chunk_rows : int
        Samples per piece of a growing file.
    max_polls : int, optional
        Stop after this many polls.
    until_idle : int, optional
        Stop after this many polls in a row that ingested nothing.
    """
    src = Path(source)
    if not (src.is_dir() or src.suffix.lower() in FILE_SUFFIXES):
        raise InputError("SOURCE", f"{str(src)!r}", "a folder of chunk files or a growing "
                         ".csv/.las file")
    if not (every_s >= 0.0):
        raise InputError("--every", f"{every_s}", ">= 0 s")
    if chunk_rows < 2:
        raise InputError("--chunk-rows", f"{chunk_rows}", ">= 2")
    for name, v in (("--max-polls", max_polls), ("--until-idle", until_idle)):
        if v is not None and v < 1:
            raise InputError(name, f"{v}", ">= 1")
    _cursor(ledger, run)  # the run exists
    report = on_report or (lambda _r: None)
    summary = FollowSummary()
    state = _FileState()
    seen: dict[str, tuple[int, int]] = {}
    failed: dict[str, tuple[int, int]] = {}
    idle_polls = 0
    while True:
        if src.is_dir():
            n_refused = len(summary.refused)
            done = _poll_folder(ledger, run, src, seen, failed, summary, damage_fn, report)
            if on_refused is not None:
                for line in summary.refused[n_refused:]:
                    on_refused(line)
        else:
            done = _poll_file(ledger, run, src, chunk_rows, state, damage_fn, report)
        summary.polls += 1
        summary.ingested += done
        idle_polls = 0 if done else idle_polls + 1
        if max_polls is not None and summary.polls >= max_polls:
            break
        if until_idle is not None and idle_polls >= until_idle:
            break
        time.sleep(every_s)
    return summary
