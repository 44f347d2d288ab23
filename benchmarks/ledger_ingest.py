"""Ledger ingest speed as a multiple of log time: a 24 h, 1 Hz log of a 300-joint string.

The damage comes from the **stand-in** damage function
(:mod:`drillfatigue.ledger.standin`, rate = f(rpm, WOB) per joint, vectorised
numpy), not from the surrogate: this measures the ledger (parsing the log,
the exactly-once bookkeeping, the database writes), not the twin. The
twin's own cost comes on top (``benchmarks/bench_surrogate.py``).

The log (CSV, rig-style headers: time, bit depth, RPM, WOB) drills from
3000 m with all 300 joints (1 bit, 6 collars, 6 HWDP, 287 drill pipe; 600
tracked locations) in the hole. It is ingested with ``ingest_file`` in
pieces of one hour (3600 samples: what ``ledger ingest`` does by default)
and of one minute (60 samples: what ``ledger follow`` does on a live log),
each piece one transaction, on a SQLite file and on a throwaway PostgreSQL
15 server on a Unix socket (``tests/testkit/pg_server.py``; fsync off, as in
the tests: client-side cost, not the server's disk). Reported per back-end
and piece size: wall time, log time / wall time, pieces per second, rows
written; and the time to parse the CSV once (included in the walls).

Usage: ``python benchmarks/ledger_ingest.py [--quick]`` (``--quick``: a 2 h
log) -> ``benchmarks/results/ledger_ingest.json``.
"""

from __future__ import annotations

import argparse
import os
import platform
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
import pandas as pd

from drillfatigue.files import atomic_write_json
from drillfatigue.ledger import ingest_file, init_ledger, load_joint_tally, read_log_file, start_run

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))
from testkit.pg_server import start_server, stop_server  # noqa: E402

RESULT = Path(__file__).parent / "results" / "ledger_ingest.json"
STANDIN = "python:drillfatigue.ledger.standin:standin_increments"
N_JOINTS = 300


def write_inputs(folder: Path, hours: float, seed: int = 0) -> tuple[Path, Path]:
    """The tally (300 joints from the bit up) and a 1 Hz log CSV of ``hours``."""
    lines = ["Serial,Type,Length (m)", "BIT-1,bit,0.3"]
    lines += [f"DC-{i:02d},dc,9.1" for i in range(1, 7)]
    lines += [f"HW-{i:02d},hwdp,9.3" for i in range(1, 7)]
    lines += [f"DP-{i:03d},dp,9.5" for i in range(1, N_JOINTS - 12)]
    tally = folder / "tally.csv"
    tally.write_text("\n".join(lines) + "\n", encoding="utf-8")
    n = int(hours * 3600) + 1
    rng = np.random.default_rng(seed)
    t = np.arange(n, dtype=np.float64)
    log = pd.DataFrame({
        "Time (s)": t,
        "Bit Depth (m)": np.round(3000.0 + t * 20.0 / 3600.0, 3),
        "RPM (rpm)": np.round(120.0 + 30.0 * np.sin(t / 900.0) + rng.normal(0, 3, n), 1),
        "WOB (kN)": np.round(np.clip(90.0 + rng.normal(0, 10, n), 0, None), 1)})
    path = folder / "log.csv"
    log.to_csv(path, index=False, lineterminator="\n")
    return tally, path


def one(db: str, tally: Path, log: Path, chunk_rows: int) -> dict[str, float]:
    led, _ = init_ledger(db)
    start_run(led, "BENCH", "W-1", load_joint_tally(tally), STANDIN, "standin")
    t0 = time.perf_counter()
    reps = ingest_file(led, "BENCH", log, chunk_rows)
    wall = time.perf_counter() - t0
    led.dispose()
    span = reps[-1].t_last_s - reps[0].t_first_s
    return {"chunk_rows": chunk_rows, "chunks": len(reps), "wall_s": wall,
            "log_time_per_wall_time": span / wall, "chunks_per_s": len(reps) / wall,
            "increment_rows": len(reps) * 2 * N_JOINTS}


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="a 2 h log instead of 24 h")
    args = ap.parse_args(argv)
    hours = 2.0 if args.quick else 24.0
    load0 = os.getloadavg()[0]
    results: dict[str, list[dict[str, float]]] = {"sqlite": [], "postgresql": []}
    with tempfile.TemporaryDirectory(prefix="ledger-bench-") as tmp:
        folder = Path(tmp)
        tally, log = write_inputs(folder, hours)
        t0 = time.perf_counter()
        read_log_file(log)
        parse_s = time.perf_counter() - t0
        server, problem, root = start_server()
        try:
            for k, rows in enumerate((3600, 60)):
                results["sqlite"].append(one(str(folder / f"l{k}.sqlite"), tally, log, rows))
                print("sqlite", results["sqlite"][-1], flush=True)
                if server is not None:
                    results["postgresql"].append(one(server.url(server.new_database()), tally,
                                                     log, rows))
                    print("postgresql", results["postgresql"][-1], flush=True)
        finally:
            stop_server(server, root)
    atomic_write_json(RESULT, {
        "machine": {"cpu_count": os.cpu_count(), "python": platform.python_version(),
                    "load_avg_1min_start": load0, "load_avg_1min_end": os.getloadavg()[0]},
        "damage_function": "stand-in (drillfatigue.ledger.standin), not the surrogate",
        "log": {"hours": hours, "sample_s": 1.0, "rows": int(hours * 3600) + 1,
                "channels": ["time", "bit depth", "rpm", "wob"]},
        "string": {"joints": N_JOINTS, "tracked_locations": 2 * N_JOINTS},
        "csv_parse_s": parse_s,
        "postgresql": ("PostgreSQL 15, Unix socket, fsync off" if not problem else
                       f"not run: {problem}"),
        "results": results,
    })
    print(f"wrote {RESULT}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
