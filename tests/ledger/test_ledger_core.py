"""The ledger on SQLite and on a real PostgreSQL server: schema, exactly-once ingest,
damage by serial, serial events, inspections, retire rules, exports.

The damage comes from the stand-in (:mod:`drillfatigue.ledger.standin`, a pure
function of the log rows), so every expected number is computed here by hand.
"""

from __future__ import annotations

import math
import threading
import time
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from alembic.autogenerate import compare_metadata
from alembic.runtime.migration import MigrationContext
from testkit.ledger_logs import STANDIN, export_bytes, make_log, write_log, write_tally

from drillfatigue.errors import InputError
from drillfatigue.ledger import (
    LogChunk,
    RetireRules,
    correct_serial,
    end_run,
    history,
    ingest_chunk,
    init_ledger,
    inventory,
    load_joint_tally,
    migrate_ledger,
    open_ledger,
    record_inspection,
    retire_lists,
    start_run,
    swap_serials,
)
from drillfatigue.ledger.db import HEAD_REVISION, Ledger, script_revisions
from drillfatigue.ledger.ingest import split_rows
from drillfatigue.ledger.schema import metadata
from drillfatigue.ledger.standin import BASE_RATE_PER_H, LOCATION_FACTOR, WOB_SCALE_N



SERIALS = ["B1", "DC1", "DC2", "DP1", "DP2", "DP3"]
REF = "python:" + STANDIN


def _si(log: pd.DataFrame) -> pd.DataFrame:
    out = log.rename(columns={"wob_kN": "wob_N"})
    out["wob_N"] = out["wob_N"] * 1e3
    return out


def _ledger(db: str, tmp_path: Path, serials: list[str] = SERIALS, run: str = "R1") -> Ledger:
    led, created = init_ledger(db)
    assert created
    start_run(led, run, "W-1", load_joint_tally(write_tally(tmp_path / f"{run}.csv", serials)),
              REF, STANDIN)
    return led


def _totals(led: Ledger) -> pd.DataFrame:
    inv = inventory(led).set_index("serial")
    return inv


def test_schema_of_the_migrations_is_the_package_schema(db_url: str) -> None:
    assert script_revisions() == (HEAD_REVISION, {"0001", "0002"})
    led, _ = init_ledger(db_url)
    assert led.revision() == HEAD_REVISION
    with led.engine.connect() as conn:
        diff = compare_metadata(MigrationContext.configure(conn), metadata)
    led.dispose()
    assert diff == []


def test_old_ledger_is_refused_until_migrated(db_url: str, tmp_path: Path, run_cli) -> None:
    led, _ = init_ledger(db_url, revision="0001")
    led.dispose()
    with pytest.raises(InputError, match="drillfatigue ledger migrate"):
        open_ledger(db_url)
    out = run_cli("joints", "--db", db_url)
    assert out.returncode == 2 and out.stderr.count("\n") == 1
    assert "ledger migrate --db" in out.stderr
    assert migrate_ledger(db_url) == ("0001", "0002")
    open_ledger(db_url).dispose()
    assert migrate_ledger(db_url) == ("0002", "0002")


def test_foreign_database_is_never_written(tmp_path: Path) -> None:
    import sqlite3

    p = tmp_path / "other.sqlite"
    with sqlite3.connect(p) as c:
        c.execute("CREATE TABLE notes (x TEXT)")
    before = p.read_bytes()
    with pytest.raises(InputError, match="holds tables but no ledger"):
        init_ledger(str(p))
    assert p.read_bytes() == before
    with pytest.raises(InputError, match="ledger init"):
        open_ledger(str(tmp_path / "missing.sqlite"))


def test_sqlite_file_is_wal_with_foreign_keys(tmp_path: Path) -> None:
    led, _ = init_ledger(str(tmp_path / "l.sqlite"))
    with led.read() as conn:
        assert conn.exec_driver_sql("PRAGMA journal_mode").scalar() == "wal"
        assert conn.exec_driver_sql("PRAGMA foreign_keys").scalar() == 1
    led.dispose()


def _standin_by_hand(log: pd.DataFrame, s_from_bit: float, ctype: str, loc: str) -> float:
    """Sum over intervals of rate(row i) * dt_i while in the hole (the stand-in's formula)."""
    total = 0.0
    for i in range(len(log) - 1):
        r = log.iloc[i]
        if r["bit_md_m"] - s_from_bit < 0:
            continue
        dt_h = (log["time_s"].iloc[i + 1] - r["time_s"]) / 3600.0
        total += (BASE_RATE_PER_H[ctype] * LOCATION_FACTOR[loc] * (r["rpm"] / 100) ** 2
                  * (1 + r["wob_N"] / WOB_SCALE_N) * dt_h)
    return total


def test_chunks_count_every_interval_once_with_the_held_value(db_url: str,
                                                              tmp_path: Path) -> None:
    log = _si(make_log(40, seed=1))
    led = _ledger(db_url, tmp_path)
    # three chunks; the intervals 12->13 and 29->30 cross chunk boundaries
    for a, b in ((0, 13), (13, 30), (30, 40)):
        rep = ingest_chunk(led, "R1", LogChunk(log.iloc[a:b].reset_index(drop=True), f"c{a}"))
        assert rep.status == "ingested" and rep.n_new_rows == b - a
    inv = _totals(led)
    for serial, ctype, s_body, s_top in (("DP1", "drill_pipe", 18.5 + 4.75, 28.0),
                                         ("DC1", "collar", 0.5 + 4.5, 9.5)):
        body = _standin_by_hand(log, s_body, ctype, "body")
        conn = _standin_by_hand(log, s_top, ctype, "connection")
        assert inv.loc[serial, "damage"] == pytest.approx(max(body, conn), rel=1e-12)
        assert inv.loc[serial, "damage_upper"] == pytest.approx(2 * max(body, conn), rel=1e-12)
    # revolutions of a joint in the hole all along: sum rpm_i / 60 * dt_i
    revs = float((log["rpm"].to_numpy()[:-1] / 60.0 * np.diff(log["time_s"])).sum())
    assert inv.loc["DC1", "revolutions"] == pytest.approx(revs, rel=1e-12)
    assert inv.loc["DC1", "time_in_hole_h"] == pytest.approx(39 * 5 / 3600, rel=1e-12)
    # the bit is not covered: listed with the reason, no damage
    assert math.isnan(inv.loc["B1", "damage"]) and "no bit model" in inv.loc["B1", "not_covered"]
    led.dispose()


def test_double_and_overlapping_chunks_count_once(db_url: str, new_db, tmp_path: Path) -> None:
    log = _si(make_log(60, seed=2))
    led = _ledger(db_url, tmp_path)
    first = LogChunk(log.iloc[0:30].reset_index(drop=True), "a")
    assert ingest_chunk(led, "R1", first).status == "ingested"
    assert ingest_chunk(led, "R1", first).status == "duplicate"
    # an overlapping chunk: rows 20-59; only 30-59 are new
    rep = ingest_chunk(led, "R1", LogChunk(log.iloc[20:60].reset_index(drop=True), "b"))
    assert (rep.status, rep.n_new_rows, rep.n_rows) == ("ingested", 30, 40)
    # wholly old chunk: nothing new
    assert ingest_chunk(led, "R1", LogChunk(log.iloc[5:25].reset_index(drop=True),
                                            "c")).status == "nothing new"
    led.dispose()
    # the same ledger as chunks [0, 30) and [30, 60) ingested once each
    other = new_db()
    led2 = _ledger(other, tmp_path)
    for a, b in ((0, 30), (30, 60)):
        ingest_chunk(led2, "R1", LogChunk(log.iloc[a:b].reset_index(drop=True), f"x{a}"))
    led2.dispose()
    assert export_bytes(db_url)["damage_totals"] == export_bytes(other)["damage_totals"]


def test_damage_follows_the_serial_across_re_racked_runs(db_url: str, tmp_path: Path) -> None:
    from drillfatigue.ledger.increments import RunContext
    from drillfatigue.ledger.standin import standin_increments

    orders = [["B1", "DC1", "DC2", "DP1", "DP2", "DP3"],
              ["B1", "DC2", "DC1", "DP3", "DP1", "DP2"],
              ["B1", "DC1", "DC2", "DP2", "DP3", "DP1"]]
    led, _ = init_ledger(db_url)
    expected: dict[tuple[str, str], float] = {}
    for k, order in enumerate(orders):
        run = f"R{k + 1}"
        tally = load_joint_tally(write_tally(tmp_path / f"{run}.csv", order))
        start_run(led, run, "W-1", tally, REF, STANDIN)
        log = _si(make_log(50, seed=10 + k, t0=10_000.0 * k, md0=30.0 + 5 * k))
        for piece in split_rows(LogChunk(log, run), 17):
            ingest_chunk(led, run, piece)
        end_run(led, run)
        # one replay of this run's whole log with this run's order
        inc = standin_increments(log, RunContext(run, tally, REF))
        for r in inc.itertuples():
            if r.covered:
                expected[(r.serial, r.location)] = expected.get((r.serial, r.location), 0.0) \
                    + r.damage
    with led.read() as conn:
        from sqlalchemy import select

        from drillfatigue.ledger.schema import damage_totals, joints
        got = {(s, loc): d for s, loc, d in conn.execute(
            select(joints.c.serial, damage_totals.c.location, damage_totals.c.damage)
            .join(joints, joints.c.id == damage_totals.c.joint_id))}
    for key, value in expected.items():
        assert got[key] == pytest.approx(value, rel=1e-12), key
    # a joint is in one hole at a time: a second open run with DP1 is refused
    start_run(led, "R4", "W-2", load_joint_tally(write_tally(tmp_path / "r4.csv", ["DP1"])),
              REF, STANDIN)
    with pytest.raises(InputError, match="open run 'R4'"):
        start_run(led, "R5", "W-3", load_joint_tally(write_tally(tmp_path / "r5.csv", ["DP1"])),
                  REF, STANDIN)
    h = history(led, "DP1")
    assert list(h.runs["run"].unique()) == ["R1", "R2", "R3", "R4"]
    assert list(h.runs.drop_duplicates("run")["position"]) == [4, 5, 6, 1]
    led.dispose()


def test_serial_events_keep_history_with_the_joint(db_url: str, tmp_path: Path) -> None:
    led = _ledger(db_url, tmp_path)
    ingest_chunk(led, "R1", LogChunk(_si(make_log(20, seed=3)), "a"))
    before = _totals(led)
    correct_serial(led, "DP1", "DP-0001", "tag misread at the rack")
    swap_serials(led, "DP2", "DP3", "RFID tags swapped at the pipe shop")
    after = _totals(led)
    assert after.loc["DP-0001", "damage"] == before.loc["DP1", "damage"]
    assert after.loc["DP3", "damage"] == before.loc["DP2", "damage"]
    assert after.loc["DP2", "damage"] == before.loc["DP3", "damage"]
    ev = history(led, "DP-0001").events
    assert list(ev[["kind", "old_serial", "new_serial"]].iloc[0]) == ["correction", "DP1",
                                                                      "DP-0001"]
    with pytest.raises(InputError, match="belongs to another joint"):
        correct_serial(led, "DP-0001", "DP2", "typo")
    with pytest.raises(InputError, match="--reason"):
        swap_serials(led, "DP2", "DP3", "  ")
    led.dispose()


def test_inspections_and_retire_rules(db_url: str, tmp_path: Path) -> None:
    led = _ledger(db_url, tmp_path)
    ingest_chunk(led, "R1", LogChunk(_si(make_log(200, seed=4, step_s=600.0)), "a"))
    inv = _totals(led)
    d = inv.loc["DP1", "damage"]          # drill pipe: the largest stand-in rate
    assert d > 0
    # retire at 0.9 d: the pipe joints that reached it; inspect where the upper bound reaches d
    rules = RetireRules(retire_at=min(1.0, 0.999 * d), inspect_at=min(1.0, 0.999 * d),
                        reinspect_after=min(1.0, 0.5 * d), downgraded_retire_at=min(1.0, 0.4 * d))
    lists = retire_lists(led, rules).set_index("serial")
    assert lists.loc["DP1", "action"] == "retire"
    dc = inv.loc["DC1"]
    assert dc["damage"] < 0.999 * d <= dc["damage_upper"] or dc["damage_upper"] < 0.999 * d
    # a class 2 inspection lowers the retire threshold for that joint
    assert record_inspection(led, "DC1", "2026-03-20", "UT", "rp7g2", "class2", wall_m=0.008,
                             od_m=0.17)
    assert not record_inspection(led, "DC1", "2026-03-20", "UT", "rp7g2", "class2")
    if dc["damage"] >= 0.4 * d:
        assert retire_lists(led, rules).set_index("serial").loc["DC1", "action"] == "retire"
    # scrap retires whatever the damage
    record_inspection(led, "DP3", "2026-03-21", "EMI", "rp7g2", "scrap")
    assert retire_lists(led, rules).set_index("serial").loc["DP3", "action"] == "retire"
    for bad, match in ((dict(standard="api"), "--standard"), (dict(result="class9"), "--result"),
                       (dict(wall_m=0.2, od_m=0.1), "--wall"), (dict(od_m=-1.0), "--od"),
                       (dict(inspected_on="20/03/2026"), "--date")):
        kw = dict(serial="DP2", inspected_on="2026-03-22", method="UT", standard="rp7g2",
                  result="premium") | bad
        with pytest.raises(InputError, match=match):
            record_inspection(led, **kw)  # type: ignore[arg-type]
    with pytest.raises(InputError, match="--retire-at"):
        RetireRules(retire_at=1.5)
    led.dispose()


def test_chunk_that_fails_to_parse_is_refused_whole(db_url: str, tmp_path: Path, run_cli) -> None:
    _ledger(db_url, tmp_path).dispose()
    bad = write_log(tmp_path / "bad.csv", make_log(30, seed=5))
    lines = bad.read_text().splitlines()
    lines[25] = lines[25].replace(",", ",abc,", 1)
    bad.write_text("\n".join(lines) + "\n")
    out = run_cli("ingest", str(bad), "--run", "R1", "--chunk-rows", "10", "--db", db_url)
    assert out.returncode == 2, out.stderr
    assert out.stderr.startswith("error: ") and out.stderr.count("\n") == 1
    exp = export_bytes(db_url)
    assert exp["chunks"].count(b"\n") == 1 and exp["damage_increments"].count(b"\n") == 1
    # physically impossible input: negative RPM, one line naming the field
    neg = make_log(10, seed=6)
    neg.loc[3, "rpm"] = -5.0
    out = run_cli("ingest", str(write_log(tmp_path / "neg.csv", neg)), "--run", "R1", "--db",
                  db_url)
    assert out.returncode == 2 and "rpm" in out.stderr.lower() and out.stderr.count("\n") == 1


def test_cli_walkthrough_and_export_formats(db_url: str, tmp_path: Path, run_cli) -> None:
    tally = write_tally(tmp_path / "t.csv", SERIALS)
    log = write_log(tmp_path / "log.csv", make_log(80, seed=7))
    assert run_cli("init", "--db", db_url).returncode == 0
    out = run_cli("run", "start", "R1", "--well-name", "W-1", "--tally", str(tally),
                  "--damage-function", STANDIN, "--db", db_url)
    assert out.returncode == 0, out.stderr
    out = run_cli("ingest", str(log), "--run", "R1", "--chunk-rows", "25", "--db", db_url)
    assert out.returncode == 0 and out.stdout.count("chunk") == 4, out.stderr
    out = run_cli("joints", "--units", "field", "--db", db_url)
    assert out.returncode == 0 and "length_ft" in out.stdout and "DP1" in out.stdout
    out = run_cli("history", "DP1", "--db", db_url)
    assert out.returncode == 0 and "R1" in out.stdout
    out = run_cli("inspect", "DP1", "--date", "2026-03-20", "--method", "UT", "--standard",
                  "rp7g2", "--result", "premium", "--wall", "0.36", "--units", "field",
                  "--db", db_url)
    assert out.returncode == 0, out.stderr
    out = run_cli("retire", "--inspect-at", "0.0001", "--retire-at", "0.5", "--db", db_url)
    assert out.returncode == 0 and "inspect (" in out.stdout, out.stderr
    for fmt in ("csv", "parquet"):
        a, b = tmp_path / f"a_{fmt}", tmp_path / f"b_{fmt}"
        for folder in (a, b):
            res = run_cli("export", "--out", str(folder), "--format", fmt, "--db", db_url)
            assert res.returncode == 0, res.stderr
        for f in sorted(a.glob(f"*.{fmt}")):
            assert f.read_bytes() == (b / f.name).read_bytes()
        assert len(list(a.glob(f"*.{fmt}"))) == 8
    ins = pd.read_csv(tmp_path / "a_csv" / "inspections.csv")
    assert ins.loc[0, "wall_m"] == pytest.approx(0.36 * 0.0254)
    # a folder with foreign files is refused
    (tmp_path / "foreign").mkdir()
    (tmp_path / "foreign" / "mine.txt").write_text("x")
    out = run_cli("export", "--out", str(tmp_path / "foreign"), "--db", db_url)
    assert out.returncode == 2 and (tmp_path / "foreign" / "mine.txt").read_text() == "x"


def test_follow_a_file_while_it_grows(db_url: str, new_db, tmp_path: Path) -> None:
    from drillfatigue.ledger import follow
    from drillfatigue.ledger.schema import chunks

    log = make_log(90, seed=8)
    path = tmp_path / "growing.csv"
    text = write_log(tmp_path / "whole.csv", log).read_text()
    lines = text.splitlines(keepends=True)
    path.write_text("".join(lines[:5]))            # header and 4 samples so far

    def writer() -> None:
        k = 5
        while k < len(lines):
            # a burst of 9 rows, the last one cut in the middle of a line at first
            burst = "".join(lines[k:k + 9])
            with path.open("a") as fh:
                fh.write(burst[:-4])
                fh.flush()
                time.sleep(0.03)
                fh.write(burst[-4:])
            k += 9
            time.sleep(0.05)

    led = _ledger(db_url, tmp_path)
    th = threading.Thread(target=writer)
    th.start()
    summary = follow(led, "R1", path, every_s=0.02, chunk_rows=10, until_idle=15)
    th.join()
    follow(led, "R1", path, every_s=0.0, chunk_rows=10, until_idle=2)
    assert summary.ingested > 0
    with led.read() as conn:
        rows = conn.execute(chunks.select().order_by(chunks.c.seq)).fetchall()
    # contiguous: every chunk counts from the previous chunk's last sample, to the log's end
    assert rows[-1].t_last_s == float(log["time_s"].iloc[-1])
    for prev, cur in zip(rows, rows[1:], strict=False):
        assert cur.counted_from_s == prev.t_last_s
    got = inventory(led).set_index("serial")
    led.dispose()
    ref = new_db()
    led2 = _ledger(ref, tmp_path)
    ingest_chunk(led2, "R1", LogChunk(_si(log), "whole"))
    want = inventory(led2).set_index("serial")
    led2.dispose()
    for s in SERIALS[1:]:
        assert got.loc[s, "damage"] == pytest.approx(want.loc[s, "damage"], rel=1e-12)
        assert got.loc[s, "revolutions"] == pytest.approx(want.loc[s, "revolutions"], rel=1e-12)


def test_follow_refuses_a_broken_chunk_file_and_goes_on(db_url: str, tmp_path: Path,
                                                        run_cli) -> None:
    _ledger(db_url, tmp_path).dispose()
    folder = tmp_path / "chunks"
    folder.mkdir()
    log = make_log(30, seed=9)
    write_log(folder / "a.csv", log.iloc[:15])
    write_log(folder / "c.csv", log.iloc[15:])
    (folder / "b.csv").write_text("Time (s),Bit Depth (m)\n1,abc\n")
    out = run_cli("follow", str(folder), "--run", "R1", "--every", "0", "--until-idle", "3",
                  "--db", db_url)
    assert out.returncode == 2
    assert out.stderr.count("\n") == 1 and out.stderr.startswith("refused b.csv: ")
    assert out.stdout.count(": chunk ") == 2


def test_an_empty_ledger_answers_empty_tables(db_url: str) -> None:
    led, _ = init_ledger(db_url)
    assert inventory(led).empty and retire_lists(led).empty
    with pytest.raises(InputError, match="no joint 'X'"):
        history(led, "X")
    led.dispose()
