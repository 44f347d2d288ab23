"""The ledger's endpoints of ``drillfatigue serve --ledger`` on SQLite and PostgreSQL.

Each endpoint answers what the command it stands beside answers on the same
ledger (the commands' own output, or the function both call); a chunk posted
twice counts once, an overlapping one only its new part, two clients posting
the same chunks at once leave the ledger a serial ingest leaves; a refused
request is one line and writes nothing; a server without a ledger says so in
one line. The damage comes from the stand-in (:mod:`drillfatigue.ledger.standin`).
"""

from __future__ import annotations

import io
import math
import threading
import warnings
from pathlib import Path

import httpx
import numpy as np
import pandas as pd
import pytest
from testkit.service_helpers import assert_one_line, running_server
from testkit.ledger_logs import STANDIN, cli_env, export_bytes, make_log, write_log, write_tally
from testkit.served import served

from drillfatigue.cli import main
from drillfatigue.ledger import (
    Ledger,
    LogChunk,
    RetireRules,
    end_run,
    history,
    in_units,
    ingest_chunk,
    init_ledger,
    inventory,
    load_joint_tally,
    open_ledger,
    record_inspection,
    retire_lists,
    runs_table,
    start_run,
    swap_serials,
)
from drillfatigue.ledger.ingest import read_log_bytes, split_rows
from drillfatigue.service import Limits, create_app

with warnings.catch_warnings():
    # starlette asks for httpx2 in its test client; httpx is what is pinned
    warnings.simplefilter("ignore")
    from fastapi.testclient import TestClient

pytestmark = pytest.mark.filterwarnings("ignore::DeprecationWarning")

SERIALS = ["B1", "DC1", "DC2", "DP1", "DP2", "DP3"]
REF = "python:" + STANDIN
LEDGER_PATHS = ("/v1/ledger", "/v1/ledger/runs", "/v1/ledger/joints", "/v1/ledger/joints/DP1",
                "/v1/ledger/retire")


def _si(log: pd.DataFrame) -> pd.DataFrame:
    return log.rename(columns={"wob_kN": "wob_N"}).assign(wob_N=lambda d: d["wob_N"] * 1e3)


def _csv(log: pd.DataFrame) -> str:
    """A rig-style CSV text of a :func:`make_log` table (what ``ledger ingest`` reads)."""
    buf = io.StringIO()
    log.rename(columns={"time_s": "Time (s)", "bit_md_m": "Bit Depth (m)", "rpm": "RPM (rpm)",
                        "wob_kN": "WOB (kN)"}).to_csv(buf, index=False, lineterminator="\n")
    return buf.getvalue()


def _body(run: str, text: str, source: str, fmt: str = "csv") -> dict[str, object]:
    return {"run": run, "log": {"format": fmt, "text": text}, "source": source}


def _new_run(db: str, tmp_path: Path, run: str = "R1", serials: list[str] = SERIALS) -> Ledger:
    led, _ = init_ledger(db)
    start_run(led, run, "W-1", load_joint_tally(write_tally(tmp_path / f"{run}.csv", serials)),
              REF, STANDIN)
    return led


def _two_runs(db: str, tmp_path: Path) -> Ledger:
    """Two runs of the same joints re-racked between them, an inspection, a tag swap."""
    led, _ = init_ledger(db)
    orders = [SERIALS, ["B1", "DC2", "DC1", "DP3", "DP1", "DP2"]]
    for k, order in enumerate(orders):
        run = f"R{k + 1}"
        start_run(led, run, "W-1", load_joint_tally(write_tally(tmp_path / f"{run}.csv", order)),
                  REF, STANDIN)
        log = _si(make_log(90, seed=30 + k, t0=10_000.0 * k, step_s=60.0))
        for piece in split_rows(LogChunk(log, run), 30):
            ingest_chunk(led, run, piece)
        if k == 0:
            end_run(led, run)
    record_inspection(led, "DC1", "2026-03-20", "UT", "rp7g2", "class2", wall_m=0.02, od_m=0.17)
    swap_serials(led, "DP2", "DP3", "RFID tags swapped at the pipe shop")
    return led


def _frame(columns: list[str], rows: list[dict[str, object]]) -> pd.DataFrame:
    return pd.DataFrame([[r[c] for c in columns] for r in rows], columns=columns)


def _assert_same_table(got: pd.DataFrame, want: pd.DataFrame) -> None:
    """Cell for cell: numbers equal to the last bit (NaN where null), text equal (missing
    and empty alike, as a CSV writes both)."""
    assert list(got.columns) == list(want.columns)
    assert len(got) == len(want)
    for col in want.columns:
        w, g = want[col], got[col]
        if pd.api.types.is_numeric_dtype(w) and not pd.api.types.is_bool_dtype(w):
            np.testing.assert_array_equal(pd.to_numeric(g).to_numpy(dtype=float),
                                          w.to_numpy(dtype=float), err_msg=col)
        else:
            text = lambda s: ["" if v is None or (isinstance(v, float) and math.isnan(v))  # noqa: E731
                              else str(v) for v in s]
            assert text(g) == text(w), col


@pytest.fixture
def ledger2(db_url: str, tmp_path: Path):  # noqa: ANN201
    led = _two_runs(db_url, tmp_path)
    yield led
    led.dispose()


def test_endpoints_answer_what_the_commands_answer(ledger2: Ledger, db_url: str,
                                                   tmp_path: Path, run_cli) -> None:
    led = ledger2
    client = TestClient(create_app(None, ledger=led))
    # the inventory, in SI and in field units, as `ledger joints --out` writes it
    for units in ("si", "field"):
        res = client.get("/v1/ledger/joints", params={"units": units})
        assert res.status_code == 200, res.text
        got = _frame(res.json()["columns"], res.json()["rows"])
        _assert_same_table(got, in_units(inventory(led), units))
        out = tmp_path / f"joints_{units}.csv"
        assert run_cli("joints", "--units", units, "--out", str(out), "--db", db_url
                       ).returncode == 0
        _assert_same_table(got, pd.read_csv(out, keep_default_na=True))
    assert "length_ft" in res.json()["columns"] and res.json()["units"] == "field"
    # a joint's history over both runs, its tag swap and (for DC1) its inspection
    h = client.get("/v1/ledger/joints/DP3").json()
    want = history(led, "DP3")
    assert (h["serial"], h["component_type"]) == ("DP3", "drill_pipe")
    _assert_same_table(_frame(h["runs"]["columns"], h["runs"]["rows"]), in_units(want.runs))
    _assert_same_table(_frame(h["events"]["columns"], h["events"]["rows"]), want.events)
    assert [r["run"] for r in h["runs"]["rows"]] == ["R1", "R1", "R2", "R2"]
    assert h["events"]["rows"][0]["reason"] == "RFID tags swapped at the pipe shop"
    cli = run_cli("history", "DP3", "--db", db_url).stdout
    for r in h["runs"]["rows"]:
        assert f"{r['damage']:.4g}" in cli and f"{r['damage_upper']:.4g}" in cli
    ins = client.get("/v1/ledger/joints/DC1", params={"units": "field"}).json()["inspections"]
    _assert_same_table(_frame(ins["columns"], ins["rows"]),
                       in_units(history(led, "DC1").inspections, "field"))
    assert ins["rows"][0]["wall_in"] == pytest.approx(0.02 / 0.0254, rel=1e-15)
    # the retire and inspect lists under rules given as the command's options
    d = float(inventory(led)["damage"].max())
    rules = RetireRules(retire_at=0.999 * d, inspect_at=0.4 * d, reinspect_after=0.5 * d,
                        downgraded_retire_at=0.2 * d)
    res = client.get("/v1/ledger/retire", params={
        "retire_at": rules.retire_at, "inspect_at": rules.inspect_at,
        "reinspect_after": rules.reinspect_after,
        "downgraded_retire_at": rules.downgraded_retire_at}).json()
    lists = in_units(retire_lists(led, rules))
    for action in ("retire", "inspect"):
        part = lists[lists["action"] == action].reset_index(drop=True)
        assert len(part) > 0
        _assert_same_table(_frame(res["columns"], res[action]), part)
    assert res["rules"]["retire_at"] == rules.retire_at
    cli = run_cli("retire", "--retire-at", repr(rules.retire_at), "--inspect-at",
                  repr(rules.inspect_at), "--reinspect-after", repr(rules.reinspect_after),
                  "--downgraded-retire-at", repr(rules.downgraded_retire_at),
                  "--db", db_url).stdout
    assert f"retire ({len(res['retire'])}):" in cli and f"inspect ({len(res['inspect'])}):" in cli
    # the runs, and the ledger's counts
    runs = client.get("/v1/ledger/runs").json()
    _assert_same_table(_frame(runs["columns"], runs["rows"]), runs_table(led))
    assert [(r["run"], r["status"], r["chunks"]) for r in runs["rows"]] == [
        ("R1", "ended", 3), ("R2", "open", 3)]
    listed = run_cli("run", "list", "--db", db_url).stdout
    assert "R1" in listed and "ended" in listed and "R2" in listed
    info = client.get("/v1/ledger").json()
    assert info["backend"] == led.dialect and info["schema_revision"] == "0002"
    assert (info["joints"], info["runs"], info["open_runs"], info["chunks"],
            info["inspections"]) == (6, 2, 1, 6, 1)
    assert client.get("/healthz").json() == {"status": "ok", "models": {},
                                             "ledger": led.dialect}


def test_a_chunk_posted_twice_counts_once(db_url: str, new_db, tmp_path: Path,
                                          run_cli) -> None:
    log = make_log(60, seed=2)
    led = _new_run(db_url, tmp_path)
    client = TestClient(create_app(None, ledger=led))
    first = _body("R1", _csv(log.iloc[0:30]), "a.csv")
    r1 = client.post("/v1/ledger/ingest", json=first).json()
    assert (r1["status"], r1["seq"], r1["n_new_rows"]) == ("ingested", 1, 30)
    r2 = client.post("/v1/ledger/ingest", json={**first, "source": "a again"}).json()
    assert (r2["status"], r2["seq"], r2["n_new_rows"]) == ("duplicate", 1, 0)
    assert r2["line"] == "a again: already ingested as chunk 1 of run R1"
    # rows 20-59 overlap the first chunk: only 30-59 are new
    r3 = client.post("/v1/ledger/ingest", json=_body("R1", _csv(log.iloc[20:60]), "b.csv")).json()
    assert (r3["status"], r3["seq"], r3["n_rows"], r3["n_new_rows"]) == ("ingested", 2, 40, 30)
    r4 = client.post("/v1/ledger/ingest", json=_body("R1", _csv(log.iloc[5:25]), "c.csv")).json()
    assert (r4["status"], r4["seq"]) == ("nothing new", None)
    led.dispose()
    # the same as `ledger ingest` of the two files, each counted once
    other = new_db()
    _new_run(other, tmp_path).dispose()
    for name, part in (("a.csv", log.iloc[0:30]), ("b.csv", log.iloc[20:60])):
        out = run_cli("ingest", str(write_log(tmp_path / name, part)), "--run", "R1",
                      "--db", other)
        assert out.returncode == 0, out.stderr
    got, want = export_bytes(db_url), export_bytes(other)
    for table in ("damage_totals", "damage_increments", "runs"):
        assert got[table] == want[table], table
    # a piece `ledger ingest` recorded is the same content when posted: a duplicate
    whole = write_log(tmp_path / "whole.csv", make_log(40, seed=3, t0=1000.0))
    led = open_ledger(other)
    assert run_cli("ingest", str(whole), "--run", "R1", "--chunk-rows", "20",
                   "--db", other).returncode == 0
    text = whole.read_text().splitlines(keepends=True)
    again = TestClient(create_app(None, ledger=led)).post(
        "/v1/ledger/ingest", json=_body("R1", "".join(text[:21]), "first 20 rows")).json()
    assert (again["status"], again["seq"]) == ("duplicate", 3)
    led.dispose()


def test_two_clients_posting_the_same_chunks_leave_a_serial_ingest(db_url: str, new_db,
                                                                   tmp_path: Path) -> None:
    """Two HTTP clients post every chunk of one run at once, each in time order; the
    ledger is byte for byte the one a serial ingest of those chunks gives."""
    log = make_log(160, seed=4)
    pieces = [(f"rows {a}-{a + 20}", _csv(log.iloc[a:a + 20])) for a in range(0, 160, 20)]
    led = _new_run(db_url, tmp_path)
    statuses: list[str] = []
    failures: list[str] = []
    with running_server(create_app(None, ledger=led)) as url:
        start = threading.Barrier(2)

        def client() -> None:
            with httpx.Client(base_url=url, timeout=60.0) as c:
                start.wait()
                for source, text in pieces:
                    r = c.post("/v1/ledger/ingest", json=_body("R1", text, source))
                    if r.status_code != 200:
                        failures.append(r.text)
                        return
                    statuses.append(r.json()["status"])

        threads = [threading.Thread(target=client) for _ in range(2)]
        for t in threads:
            t.start()
        for t in threads:
            t.join()
    led.dispose()
    assert failures == []
    assert sorted(statuses) == sorted(["ingested"] * 8 + ["duplicate"] * 8)
    ref = new_db()
    led = _new_run(ref, tmp_path)
    for source, text in pieces:
        ingest_chunk(led, "R1", read_log_bytes(text.encode(), ".csv", source))
    led.dispose()
    got, want = export_bytes(db_url), export_bytes(ref)
    assert got == want


def test_refused_requests_are_one_line_and_write_nothing(db_url: str, tmp_path: Path) -> None:
    log = make_log(40, seed=5)
    led = _new_run(db_url, tmp_path)
    start_run(led, "R0", "W-0", load_joint_tally(write_tally(tmp_path / "r0.csv", ["DP9"])),
              REF, STANDIN)
    end_run(led, "R0")
    client = TestClient(create_app(None, Limits(max_log_rows=30), ledger=led))
    assert client.post("/v1/ledger/ingest",
                       json=_body("R1", _csv(log.iloc[:20]), "a")).status_code == 200
    before = export_bytes(db_url)
    lines = _csv(log.iloc[20:30]).splitlines(keepends=True)
    cells = lines[5].split(",")
    lines[5] = ",".join([cells[0], cells[1], "abc", *cells[3:]])  # RPM not a number
    bad_number = "".join(lines)
    negative_rpm = log.iloc[20:30].copy()
    negative_rpm.iloc[4, negative_rpm.columns.get_loc("rpm")] = -5.0
    backwards = log.iloc[20:30].copy()
    backwards.iloc[6, 0] = backwards.iloc[2, 0]
    repeated = log.iloc[20:30].copy()
    repeated.iloc[6, 0] = repeated.iloc[5, 0]
    ok = _csv(log.iloc[20:30])
    ingest_cases = [
        (_body("R9", ok, "a"), "run", "no run 'R9'"),
        (_body("R0", ok, "a"), "run", "has ended"),
        (_body("R1", ok, "a", fmt="xls"), "log.format", "csv, las, witsml"),
        (_body("R1", bad_number, "a"), "log.text", ""),
        (_body("R1", _csv(negative_rpm), "a"), "rpm", "rev/min >= 0"),
        (_body("R1", _csv(backwards), "a"), "log.text", "non-decreasing time"),
        (_body("R1", _csv(repeated), "a"), "log.text", "one row per time stamp"),
        (_body("R1", _csv(log.iloc[:40]), "a"), "log.text", "at most 30 per chunk"),
        ({"log": {"format": "csv", "text": ok}}, "run", ""),
        ({**_body("R1", ok, "a"), "extra": 1}, "extra", ""),
        ({**_body("R1", ok, "a"), "source": ""}, "source", ""),
    ]
    for body, field, allowed in ingest_cases:
        r = client.post("/v1/ledger/ingest", json=body)
        assert r.status_code == 422, (field, r.text)
        assert_one_line(r.json()["detail"])
        assert r.json()["field"].startswith(field) and allowed in r.json()["detail"], r.json()
    query_cases = [
        ({"retire_at": 1.5}, "retire_at", "0 < fraction <= 1"),
        ({"inspect_at": 0}, "inspect_at", "0 < fraction <= 1"),
        ({"reinspect_after": "nan"}, "reinspect_after", "0 < fraction <= 1"),
        ({"retire_at": "abc"}, "retire_at", "a number"),
        ({"downgraded_retire_at": 0.9}, "downgraded_retire_at", "<= retire_at"),
        ({"units": "imperial"}, "units", "si, field"),
    ]
    for params, field, allowed in query_cases:
        r = client.get("/v1/ledger/retire", params=params)
        assert r.status_code == 422, (params, r.text)
        detail = r.json()["detail"]
        assert_one_line(detail)
        assert detail.startswith(f"{field}: ") and allowed in detail and "--" not in detail
    r = client.get("/v1/ledger/joints", params={"units": "imperial"})
    assert r.status_code == 422 and r.json()["field"] == "units"
    r = client.get("/v1/ledger/joints/NOPE")
    assert r.status_code == 404
    assert_one_line(r.json()["detail"])
    assert r.json()["detail"].startswith("serial: no joint 'NOPE' in the ledger")
    assert export_bytes(db_url) == before
    led.dispose()


def test_without_a_ledger_every_ledger_endpoint_says_so(tmp_path: Path, run_cli) -> None:
    client = TestClient(create_app(None))
    for path in LEDGER_PATHS:
        r = client.get(path)
        assert r.status_code == 503, path
        assert r.json()["detail"] == ("ledger: this server opened no ledger (allowed: start it "
                                      "with drillfatigue serve --ledger PATH_OR_URL)")
    r = client.post("/v1/ledger/ingest", json=_body("R1", "Time (s)\n1\n", "a"))
    assert r.status_code == 503 and r.json()["field"] == "ledger"
    # and a server for a ledger alone says it has no model
    r = client.get("/v1/models")
    assert r.status_code == 503 and r.json()["field"] == "model"
    assert_one_line(r.json()["detail"])
    assert client.get("/healthz").json() == {"status": "ok", "models": {}, "ledger": None}
    paths = client.get("/openapi.json").json()["paths"]
    assert {*LEDGER_PATHS[:3], "/v1/ledger/joints/{serial}", "/v1/ledger/retire",
            "/v1/ledger/ingest"} <= set(paths)


def test_serve_opens_the_ledger_or_says_why_not(tmp_path: Path,
                                                capsys: pytest.CaptureFixture[str]) -> None:
    """``drillfatigue serve --ledger`` as a real process on the loopback; a missing
    ledger, or neither a model nor a ledger, is one line and exit code 2."""
    for args, field in (([], "--model"), (["--ledger", str(tmp_path / "none.sqlite")],
                                          "--ledger")):
        assert main(["serve", *args]) == 2
        err = capsys.readouterr().err
        assert err.count("\n") == 1 and err.startswith(f"error: {field}: "), err
    db = str(tmp_path / "ledger.sqlite")
    led = _new_run(db, tmp_path)
    ingest_chunk(led, "R1", LogChunk(_si(make_log(30, seed=6)), "a"))
    want = len(inventory(led))
    led.dispose()
    with served(["--ledger", db], start_s=60.0, env=cli_env()) as (url, proc):
        assert len(httpx.get(url + "/v1/ledger/joints").json()["rows"]) == want
        assert httpx.get(url + "/v1/models").status_code == 503
    assert f"serving the ledger {db} on {url}/" in (proc.stdout.read() if proc.stdout else "")
