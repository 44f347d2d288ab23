"""Real processes on one ledger: two concurrent ingesters, ``kill -9`` of an ingest and of
a follow at random points, then a restart: the export equals an uninterrupted run's,
byte for byte, on SQLite and on PostgreSQL.
"""

from __future__ import annotations

import os
import random
import signal
import subprocess
import time
from collections.abc import Callable
from pathlib import Path

import pytest
from testkit.ledger_logs import (
    STANDIN,
    cli_env,
    export_bytes,
    ledger_cmd,
    make_log,
    write_log,
    write_tally,
)

from drillfatigue.cli import main
from drillfatigue.io.examples import LOG_CURVES, synthetic_day, witsml_log_text
from drillfatigue.ledger import open_ledger
from drillfatigue.ledger.schema import chunks

SERIALS = ["B1", "DC1", "DC2", "DP1", "DP2", "DP3", "DP4"]
#: kills that hit a running process, per test: 5 of an ingest, 3 of a follow of a
#: growing file and 2 of a follow of a WITSML chunk folder: 10 per back-end
KILLS = {"ingest": 5, "file": 3, "folder": 2}
ROWS = 320
CHUNK = 4


def _setup(db: str, tmp_path: Path) -> None:
    tally = write_tally(tmp_path / "tally.csv", SERIALS)
    assert main(["ledger", "init", "--db", db]) == 0
    assert main(["ledger", "run", "start", "R1", "--well-name", "W-1", "--tally", str(tally),
                 "--damage-function", STANDIN, "--db", db]) == 0


def _n_chunks(db: str) -> int:
    led = open_ledger(db)
    try:
        with led.read() as conn:
            return len(conn.execute(chunks.select()).fetchall())
    finally:
        led.dispose()


def _kill_and_restart(args: list[str], db: str, rng: random.Random,
                      done: Callable[[], bool], n_kills: int) -> list[int]:
    """Start ``ledger ARGS`` and kill -9 it at random points until ``n_kills`` hit a running
    process; then run it to the end. Returns the chunk counts seen after each kill.

    Most kills land a random moment after the process reported its first chunk (mid-ingest);
    some during its start (before it touched the ledger, or while opening it)."""
    seen = []
    kills = 0
    for _ in range(4 * n_kills):
        if kills >= n_kills or done():
            break
        proc = subprocess.Popen(ledger_cmd(*args), env=cli_env(), stdout=subprocess.PIPE,
                                stderr=subprocess.DEVNULL, text=True)
        if rng.random() < 0.25:
            time.sleep(rng.uniform(0.2, 0.9))
        else:
            assert proc.stdout is not None
            proc.stdout.readline()          # the first chunk is in (or the process ended)
            time.sleep(rng.uniform(0.0, 0.3))
        if proc.poll() is None:
            os.kill(proc.pid, signal.SIGKILL)
            kills += 1
        proc.wait()
        if proc.returncode == -signal.SIGKILL:
            seen.append(_n_chunks(db))
        else:
            assert proc.returncode == 0
    final = subprocess.run(ledger_cmd(*args), env=cli_env(), capture_output=True, text=True,
                           timeout=120)
    assert final.returncode == 0, final.stderr
    assert kills >= n_kills, f"only {kills} kills hit a running process"
    return seen


def _assert_same_exports(a: str, b: str) -> None:
    ea, eb = export_bytes(a), export_bytes(b)
    assert ea.keys() == eb.keys()
    for name in ea:
        assert ea[name] == eb[name], name


def test_two_concurrent_ingesters_count_once(db_url: str, new_db, tmp_path: Path) -> None:
    n = ROWS // 4
    log = write_log(tmp_path / "log.csv", make_log(n, seed=21))
    _setup(db_url, tmp_path)
    args = ["ingest", str(log), "--run", "R1", "--chunk-rows", str(CHUNK), "--db", db_url]
    procs = [subprocess.Popen(ledger_cmd(*args), env=cli_env(), stdout=subprocess.PIPE,
                              stderr=subprocess.PIPE, text=True) for _ in range(2)]
    outs = [p.communicate(timeout=120) for p in procs]
    assert all(p.returncode == 0 for p in procs), [o[1] for o in outs]
    ingested = sum(o[0].count(": chunk ") for o in outs)
    assert ingested == n // CHUNK      # every piece recorded by exactly one of the two
    ref = new_db()
    _setup(ref, tmp_path)
    assert main(["ledger", "ingest", str(log), "--run", "R1", "--chunk-rows", str(CHUNK),
                 "--db", ref]) == 0
    _assert_same_exports(db_url, ref)
    # an ingester cutting other pieces at the same time: intervals still counted once
    # (each chunk counts from where the previous one stopped)
    other = new_db()
    _setup(other, tmp_path)
    procs = [subprocess.Popen(ledger_cmd("ingest", str(log), "--run", "R1", "--chunk-rows", str(n),
                                         "--db", other), env=cli_env(),
                              stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
             for n in (CHUNK, 7)]
    for p in procs:
        assert p.wait(timeout=120) == 0
    led = open_ledger(other)
    with led.read() as conn:
        rows = conn.execute(chunks.select().order_by(chunks.c.seq)).fetchall()
    led.dispose()
    assert rows[0].counted_from_s == 0.0 and rows[-1].t_last_s == 5.0 * (n - 1)
    for prev, cur in zip(rows, rows[1:], strict=False):
        assert cur.counted_from_s == prev.t_last_s


def test_kill9_during_ingest_then_restart(db_url: str, new_db, tmp_path: Path) -> None:
    log = write_log(tmp_path / "log.csv", make_log(ROWS, seed=22))
    _setup(db_url, tmp_path)
    ref = new_db()
    _setup(ref, tmp_path)
    args = ["ingest", str(log), "--run", "R1", "--chunk-rows", str(CHUNK)]
    assert main(["ledger", *args, "--db", ref]) == 0
    total = ROWS // CHUNK
    seen = _kill_and_restart([*args, "--db", db_url], db_url, random.Random(1),
                             lambda: _n_chunks(db_url) == total, KILLS["ingest"])
    assert any(0 < n < total for n in seen), seen   # some kills landed mid-ingest
    _assert_same_exports(db_url, ref)


@pytest.mark.parametrize("mode", ["file", "folder"])
def test_kill9_during_follow_then_restart(mode: str, db_url: str, new_db,
                                          tmp_path: Path) -> None:
    if mode == "file":
        source = write_log(tmp_path / "growing.csv", make_log(ROWS, seed=23))
        n_chunks = -(-ROWS // CHUNK)
    else:
        # WITSML 1.4.1.1 chunks of the synthetic rig day (date-time index), 6 rows each
        day = synthetic_day().iloc[:150].reset_index(drop=True)
        source = tmp_path / "witsml"
        source.mkdir()
        for k in range(0, len(day), 6):
            (source / f"log_{k // 6:03d}.xml").write_text(
                witsml_log_text(day.iloc[k:k + 6], LOG_CURVES), encoding="utf-8")
        n_chunks = len(day) // 6
    _setup(db_url, tmp_path)
    ref = new_db()
    _setup(ref, tmp_path)
    args = ["follow", str(source), "--run", "R1", "--every", "0.05", "--chunk-rows", str(CHUNK),
            "--until-idle", "3"]
    assert main(["ledger", *args, "--db", ref]) == 0
    assert _n_chunks(ref) == n_chunks
    seen = _kill_and_restart([*args, "--db", db_url], db_url, random.Random(2),
                             lambda: _n_chunks(db_url) == n_chunks, KILLS[mode])
    assert any(0 < n < n_chunks for n in seen), seen
    _assert_same_exports(db_url, ref)
