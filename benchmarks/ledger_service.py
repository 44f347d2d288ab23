"""The ledger's endpoints under load: ingesters and readers on one ``drillfatigue serve --ledger``.

A real ``drillfatigue serve --ledger DB`` process (uvicorn, one worker, on
the loopback) serves a ledger of ``--runs`` open runs of ``--joints`` joints
each (1 bit, 6 collars, 6 heavy-weight pipe, drill pipe; the stand-in damage
function, :mod:`drillfatigue.ledger.standin`, so this measures the ledger and
the service, not the twin). Each run's log (1 Hz, ``--hours``, rig-style
CSV) is cut into pieces of ``--chunk-rows`` samples. Eight clients, each on
its own keep-alive connection, start together:

* ``--ingesters`` (4) post the pieces of one run each, in time order, to
  ``POST /v1/ledger/ingest``; two ingesters share each run, so every piece
  is posted twice at about the same time (one is ingested, the other
  answered as a duplicate: the exactly-once path under contention);
* ``--readers`` (4) ask, round robin until the ingesters are done, for the
  inventory (``GET /v1/ledger/joints``), the retire and inspect lists
  (``/v1/ledger/retire``), a random joint's history
  (``/v1/ledger/joints/{serial}``) and the runs (``/v1/ledger/runs``).

Reported per back-end (a SQLite file; a throwaway PostgreSQL 15 server on a
Unix socket, fsync off as in the tests: ``tests/testkit/pg_server.py``):
latency per endpoint kind as the client sees it (p50, p99, max; the ingest
also per answer: ingested or duplicate), requests per second per kind and in
all, log time ingested per wall time, and the check that no row was lost or
repeated: the ledger's export, table by table,
equals that of a serial ingest of the same pieces through the ledger's own
functions, and every request answered 200. The clients share the machine's
cores with the server, so the latencies are an upper bound.

Usage: ``python benchmarks/ledger_service.py [--runs 2] [--joints 150] [--hours 3]
[--chunk-rows 60]`` -> ``benchmarks/results/ledger_service.json``.
"""

from __future__ import annotations

import argparse
import io
import os
import platform
import random
import sys
import tempfile
import threading
import time
from collections import defaultdict
from pathlib import Path

import httpx
import numpy as np

from drillfatigue.files import atomic_write_json
from drillfatigue.ledger import export_tables, ingest_chunk, init_ledger, load_joint_tally, start_run
from drillfatigue.ledger.ingest import read_log_bytes

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))
from testkit.pg_server import start_server, stop_server  # noqa: E402
from testkit.served import served  # noqa: E402

from ledger_ingest import rig_log  # noqa: E402  (this folder: the same log as the ingest benchmark)

RESULT = Path(__file__).parent / "results" / "ledger_service.json"
STANDIN = "python:drillfatigue.ledger.standin:standin_increments"
READS = ("joints", "retire", "history", "runs")


def write_tally(path: Path, run: int, n_joints: int) -> list[str]:
    """A tally of ``n_joints`` joints of their own (serials ``R<run>-...``); the serials."""
    serials = [f"R{run}-BIT"] + [f"R{run}-DC{i}" for i in range(1, 7)]
    serials += [f"R{run}-HW{i}" for i in range(1, 7)]
    serials += [f"R{run}-DP{i:03d}" for i in range(1, n_joints - 12)]
    kinds = {"BIT": ("bit", 0.3), "DC": ("dc", 9.1), "HW": ("hwdp", 9.3), "DP": ("dp", 9.5)}
    lines = ["Serial,Type,Length (m)"]
    for s in serials:
        kind, length = next(v for k, v in kinds.items() if s.split("-")[1].startswith(k))
        lines.append(f"{s},{kind},{length}")
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    return serials


def log_pieces(run: int, hours: float, chunk_rows: int) -> list[tuple[str, str]]:
    """A 1 Hz log of ``hours`` as (source, rig-style CSV text) pieces of ``chunk_rows``."""
    log = rig_log(hours, seed=run)
    n = len(log)
    cuts = list(range(0, n, chunk_rows)) + [n]
    if cuts[-1] - cuts[-2] < 2:  # a log file holds >= 2 samples: a last single one joins the piece before
        del cuts[-2]
    out = []
    for a, b in zip(cuts[:-1], cuts[1:], strict=True):
        buf = io.StringIO()
        log.iloc[a:b].to_csv(buf, index=False, lineterminator="\n")
        out.append((f"R{run} rows {a + 1}-{b}", buf.getvalue()))
    return out


def new_ledger(db: str, folder: Path, runs: int, joints: int) -> list[str]:
    """A ledger with the open runs ``R0``, ``R1``, ...; every serial."""
    led, _ = init_ledger(db)
    serials = []
    for r in range(runs):
        tally = folder / f"tally_{r}.csv"
        serials += write_tally(tally, r, joints)
        start_run(led, f"R{r}", "W-1", load_joint_tally(tally), STANDIN, "standin")
    led.dispose()
    return serials


def export_csv(db: str) -> dict[str, bytes]:
    from drillfatigue.ledger import open_ledger

    led = open_ledger(db)
    try:
        return {k: v.to_csv(index=False, lineterminator="\n").encode()
                for k, v in export_tables(led).items()}
    finally:
        led.dispose()


def serial_reference(db: str, folder: Path, runs: int, joints: int,
                     pieces: dict[int, list[tuple[str, str]]]) -> dict[str, bytes]:
    """The export after a serial ingest of the same pieces (the ledger's own functions)."""
    from drillfatigue.ledger import open_ledger

    new_ledger(db, folder, runs, joints)
    led = open_ledger(db)
    for r in range(runs):
        for source, text in pieces[r]:
            ingest_chunk(led, f"R{r}", read_log_bytes(text.encode(), ".csv", source))
    led.dispose()
    return export_csv(db)


def load(url: str, serials: list[str], pieces: dict[int, list[tuple[str, str]]],
         ingesters: int, readers: int, runs: int) -> dict[str, object]:
    """Run the clients against the server at ``url``; latencies and answers."""
    lat: dict[str, list[float]] = defaultdict(list)
    by_answer: dict[str, list[float]] = defaultdict(list)  # ingest latency per answer
    statuses: dict[str, int] = defaultdict(int)
    failures: list[str] = []
    lock = threading.Lock()
    done = threading.Event()
    left = [ingesters]
    start = threading.Barrier(ingesters + readers + 1)

    def record(kind: str, t: float, r: httpx.Response | None, why: str = "") -> None:
        dt = time.perf_counter() - t
        with lock:
            lat[kind].append(dt)
            if r is None or r.status_code != 200:
                failures.append(f"{kind}: {why or (r.text[:200] if r is not None else '')}")
            elif kind == "ingest":
                answer = r.json()["status"]
                statuses[answer] += 1
                by_answer[answer].append(dt)

    def ingester(i: int) -> None:
        run = i % runs
        with httpx.Client(base_url=url, timeout=120.0) as c:
            c.get("/healthz")  # open the connection before the clock starts
            start.wait()
            for source, text in pieces[run]:
                t = time.perf_counter()
                try:
                    r = c.post("/v1/ledger/ingest", json={
                        "run": f"R{run}", "log": {"format": "csv", "text": text},
                        "source": source})
                except httpx.HTTPError as exc:
                    record("ingest", t, None, repr(exc))
                    continue
                record("ingest", t, r)
        with lock:
            left[0] -= 1
            if left[0] == 0:
                done.set()

    def reader(i: int) -> None:
        rng = random.Random(i)
        k = i
        with httpx.Client(base_url=url, timeout=120.0) as c:
            c.get("/healthz")
            start.wait()
            while not done.is_set():
                kind = READS[k % len(READS)]
                k += 1
                path = {"joints": "/v1/ledger/joints", "retire": "/v1/ledger/retire",
                        "runs": "/v1/ledger/runs",
                        "history": f"/v1/ledger/joints/{rng.choice(serials)}"}[kind]
                t = time.perf_counter()
                try:
                    r = c.get(path)
                except httpx.HTTPError as exc:
                    record(kind, t, None, repr(exc))
                    continue
                record(kind, t, r)

    threads = ([threading.Thread(target=ingester, args=(i,)) for i in range(ingesters)]
               + [threading.Thread(target=reader, args=(i,)) for i in range(readers)])
    for th in threads:
        th.start()
    start.wait()
    t0 = time.perf_counter()
    for th in threads:
        th.join()
    wall = time.perf_counter() - t0
    def stats(v: list[float]) -> dict[str, float]:
        ms = np.asarray(v) * 1e3
        return {"requests": len(v), "per_s": len(v) / wall,
                "p50_ms": float(np.percentile(ms, 50)), "p99_ms": float(np.percentile(ms, 99)),
                "max_ms": float(ms.max())}

    n_req = sum(len(v) for v in lat.values())
    return {"wall_s": wall, "requests": n_req, "throughput_per_s": n_req / wall,
            "endpoints": {k: stats(v) for k, v in sorted(lat.items())},
            "ingest_by_answer": {k: stats(v) for k, v in sorted(by_answer.items())},
            "ingest_answers": dict(statuses),
            "failed": len(failures), "failure_examples": failures[:5]}


def one_backend(name: str, db: str, ref_db: str, folder: Path, args: argparse.Namespace,
                pieces: dict[int, list[tuple[str, str]]]) -> dict[str, object]:
    serials = new_ledger(db, folder, args.runs, args.joints)
    with served(["--ledger", db]) as (url, _server):
        res = load(url, serials, pieces, args.ingesters, args.readers, args.runs)
    got = export_csv(db)
    want = serial_reference(ref_db, folder, args.runs, args.joints, pieces)
    n_pieces = sum(len(p) for p in pieces.values())
    n_chunks = got["chunks"].count(b"\n") - 1
    n_inc = got["damage_increments"].count(b"\n") - 1
    log_s = args.runs * args.hours * 3600.0
    res["log_time_per_wall_time"] = log_s / float(res["wall_s"])  # type: ignore[arg-type]
    res["check"] = {
        "export_equals_serial_ingest": got == want,
        "tables_differing": sorted(k for k in want if got.get(k) != want[k]),
        "chunks": n_chunks, "chunks_expected": n_pieces,
        "increment_rows": n_inc, "increment_rows_expected": n_pieces * args.joints * 2,
        "ingested_answers_expected": n_pieces,
        "duplicate_answers_expected": n_pieces * (args.ingesters // args.runs - 1)}
    print(name, {k: res[k] for k in ("wall_s", "throughput_per_s", "failed", "check")},
          flush=True)
    return res


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--runs", type=int, default=2, help="open runs, each of its own joints")
    ap.add_argument("--joints", type=int, default=150, help="joints per run (>= 14)")
    ap.add_argument("--hours", type=float, default=3.0, help="log length per run, 1 Hz")
    ap.add_argument("--chunk-rows", type=int, default=60, help="samples per posted piece")
    ap.add_argument("--ingesters", type=int, default=4)
    ap.add_argument("--readers", type=int, default=4)
    ap.add_argument("--out", default=str(RESULT))
    args = ap.parse_args(argv)
    if args.joints < 14 or args.runs < 1 or args.ingesters % args.runs or args.chunk_rows < 2:
        ap.error("--joints >= 14, --chunk-rows >= 2, --ingesters a multiple of --runs")
    load0 = os.getloadavg()[0]
    pieces = {r: log_pieces(r, args.hours, args.chunk_rows) for r in range(args.runs)}
    results: dict[str, object] = {}
    with tempfile.TemporaryDirectory(prefix="ledger-service-bench-") as tmp:
        folder = Path(tmp)
        results["sqlite"] = one_backend("sqlite", str(folder / "bench.sqlite"),
                                        str(folder / "ref.sqlite"), folder, args, pieces)
        server, problem, root = start_server()
        try:
            if server is not None:
                results["postgresql"] = one_backend(
                    "postgresql", server.url(server.new_database()),
                    server.url(server.new_database()), folder, args, pieces)
        finally:
            stop_server(server, root)
    n_pieces = sum(len(p) for p in pieces.values())
    atomic_write_json(args.out, {
        "machine": {"cpu_count": os.cpu_count(), "python": platform.python_version(),
                    "load_avg_1min_start": load0, "load_avg_1min_end": os.getloadavg()[0]},
        "size": {"runs": args.runs, "joints_per_run": args.joints,
                 "tracked_locations": 2 * args.runs * args.joints, "log_hours_per_run":
                 args.hours, "sample_s": 1.0, "chunk_rows": args.chunk_rows,
                 "pieces": n_pieces, "ingest_posts": n_pieces * (args.ingesters // args.runs)},
        "clients": {"ingesters": args.ingesters, "readers": args.readers,
                    "readers_ask": "joints, retire, history of a random serial, runs; round "
                    "robin until the ingesters are done"},
        "server": "drillfatigue serve --ledger (uvicorn, 1 worker), loopback, keep-alive",
        "damage_function": "stand-in (drillfatigue.ledger.standin), not the surrogate",
        "postgresql": ("PostgreSQL 15, Unix socket, fsync off" if not problem else
                       f"not run: {problem}"),
        "results": results,
    })
    print(f"wrote {args.out}")
    ok = all(r["failed"] == 0 and r["check"]["export_equals_serial_ingest"]  # type: ignore[index]
             for r in results.values())
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
