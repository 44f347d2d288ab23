"""Ledger ingest speed as a multiple of log time: a 24 h, 1 Hz log of a 300-joint string.

By default the damage comes from the **stand-in** damage function
(:mod:`drillfatigue.ledger.standin`, rate = f(rpm, WOB) per joint, vectorised
numpy), not from the surrogate: this measures the ledger (parsing the log,
the exactly-once bookkeeping, the database writes), not the twin.

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

With ``--model PATH`` (a surrogate model folder written by the pipeline's
train stage) the runs are started with that model, as
``drillfatigue ledger run start --model`` does, so every piece goes through
the digital twin (:func:`drillfatigue.ledger.twin_adapter.twin_increments`,
which calls :func:`drillfatigue.surrogate.twin.replay_log`): the ingest
speed a user sees. The inputs are then put inside the model's domain where
the model allows it (docs/surrogate.md): the well is profile ``profile_1``
of the ``well`` section of ``params.yaml`` (a profile of the training
design), the bit drills from 570 m at 7.5 m/h (the design's bit depths are
560-760 m), RPM and WOB stay within the design's 60-180 rpm and 30-120 kN,
and the friction, mud and lobe amplitude are constants inside their design
ranges. The string keeps 300 joints from the bit up, with a BHA of the
model's component types (near-bit and string stabilisers, 7 collars, 7
HWDP) under drill pipe, so the ledger writes the same 600 rows per piece as
with the stand-in; only the joints within the bit depth of the bit are in
the hole (about 120 locations), and the twin queries only those. The bit is
not covered by the model (recorded with the reason); drill pipe more than
about 540 m behind the bit, and a few BHA locations, lie outside the
distances the model was trained on and are answered with the out-of-domain
flag. The result says how many locations were covered, in the hole and in
domain, and the out-of-domain location-hours. Reported per back-end and
piece size besides the walls: the time spent in the twin (the damage
function, timed around the run's own function) and the ledger's own time
(the rest: parsing, bookkeeping, database); the model's load and first
calls are timed apart, in a warm-up ingest before the measured ones.

Usage: ``python benchmarks/ledger_ingest.py [--quick] [--hours H]``
(``--quick``: a 2 h log) -> ``benchmarks/results/ledger_ingest.json``;
``python benchmarks/ledger_ingest.py --model data/surrogate/model [--hours H]``
-> ``benchmarks/results/ledger_ingest_twin.json``.
"""

from __future__ import annotations

import argparse
import os
import platform
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd
from sqlalchemy import select

from drillfatigue.config import load_params
from drillfatigue.files import atomic_write_json
from drillfatigue.ledger import (
    DamageFunction,
    Ledger,
    RunContext,
    ingest_file,
    init_ledger,
    load_joint_tally,
    read_log_file,
    start_run,
)
from drillfatigue.ledger.ingest import damage_function_for
from drillfatigue.ledger.schema import damage_totals, joints
from drillfatigue.ledger.twin_adapter import model_id

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))
from testkit.pg_server import start_server, stop_server  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
RESULT = Path(__file__).parent / "results" / "ledger_ingest.json"
RESULT_TWIN = Path(__file__).parent / "results" / "ledger_ingest_twin.json"
STANDIN = "python:drillfatigue.ledger.standin:standin_increments"
N_JOINTS = 300
CHUNK_ROWS = (3600, 60)

# the twin's inputs, inside the model's training design (params.yaml: sweep, well)
TWIN_PROFILE = "profile_1"
TWIN_START_MD_M = 570.0
TWIN_ROP_M_PER_H = 7.5
#: the deepest bit of the design (sweep.variables.operation.bit_md_m), m
TWIN_MAX_MD_M = 760.0
TWIN_RPM = (60.0, 180.0)
TWIN_WOB_KN = (30.0, 120.0)
#: friction, mud and lobe amplitude, each inside its design range (--set of ``ledger run start``)
TWIN_CONSTANTS = {"mu_dynamic": "0.28", "mud_density_sg": "1.25", "lobe_amplitude_mm": "1.0"}
#: what the twin result's figures are (written into it)
TWIN_NOTES = ("the twin queries only the locations in the hole (bit depth minus distance from "
              "the bit >= 0): about 120-160 of the 600 here, where the model's design ends at "
              "a 760 m bit depth; a string wholly in a deeper hole would cost the twin more "
              "per piece. damage_sum and max_damage are the model's answers on these synthetic "
              "inputs, a check that the configurations counted the same, not life estimates.")
#: BHA from the bit up (serial, type, length m) at the distances the model was trained on
TWIN_BHA = ([("BIT-1", "bit", 0.3), ("STB-1", "stab", 1.8), ("DC-01", "dc", 9.1),
             ("STB-2", "stab", 1.8)] + [(f"DC-{i:02d}", "dc", 9.1) for i in range(2, 8)]
            + [(f"HW-{i:02d}", "hwdp", 9.3) for i in range(1, 8)])


def rig_log(hours: float, seed: int) -> pd.DataFrame:
    """A 1 Hz rig log of ``hours`` in field column names: drilling from 3000 m at 20 m/h,
    rpm 120 +- 30 over a 15 min swing with noise, WOB about 90 kN."""
    n = int(hours * 3600) + 1
    rng = np.random.default_rng(seed)
    t = np.arange(n, dtype=np.float64)
    return pd.DataFrame({
        "Time (s)": t,
        "Bit Depth (m)": np.round(3000.0 + t * 20.0 / 3600.0, 3),
        "RPM (rpm)": np.round(120.0 + 30.0 * np.sin(t / 900.0) + rng.normal(0, 3, n), 1),
        "WOB (kN)": np.round(np.clip(90.0 + rng.normal(0, 10, n), 0, None), 1)})


def write_inputs(folder: Path, hours: float, seed: int = 0) -> tuple[Path, Path]:
    """The tally (300 joints from the bit up) and a 1 Hz log CSV of ``hours``."""
    lines = ["Serial,Type,Length (m)", "BIT-1,bit,0.3"]
    lines += [f"DC-{i:02d},dc,9.1" for i in range(1, 7)]
    lines += [f"HW-{i:02d},hwdp,9.3" for i in range(1, 7)]
    lines += [f"DP-{i:03d},dp,9.5" for i in range(1, N_JOINTS - 12)]
    tally = folder / "tally.csv"
    tally.write_text("\n".join(lines) + "\n", encoding="utf-8")
    log = rig_log(hours, seed)
    path = folder / "log.csv"
    log.to_csv(path, index=False, lineterminator="\n")
    return tally, path


def write_twin_inputs(folder: Path, hours: float, seed: int = 0) -> tuple[Path, Path]:
    """The tally (:data:`TWIN_BHA` under drill pipe, 300 joints) and a 1 Hz log CSV of
    ``hours`` drilling from :data:`TWIN_START_MD_M` with RPM and WOB in the design ranges."""
    lines = ["Serial,Type,Length (m)"] + [f"{s},{k},{m}" for s, k, m in TWIN_BHA]
    lines += [f"DP-{i:03d},dp,9.5" for i in range(1, N_JOINTS - len(TWIN_BHA) + 1)]
    tally = folder / "tally.csv"
    tally.write_text("\n".join(lines) + "\n", encoding="utf-8")
    n = int(hours * 3600) + 1
    rng = np.random.default_rng(seed)
    t = np.arange(n, dtype=np.float64)
    rpm = 120.0 + 30.0 * np.sin(t / 900.0) + rng.normal(0, 3, n)
    wob = 75.0 + 15.0 * np.sin(t / 1300.0) + rng.normal(0, 5, n)
    log = pd.DataFrame({
        "Time (s)": t,
        "Bit Depth (m)": np.round(TWIN_START_MD_M + t * TWIN_ROP_M_PER_H / 3600.0, 3),
        "RPM (rpm)": np.round(np.clip(rpm, *TWIN_RPM), 1),
        "WOB (kN)": np.round(np.clip(wob, *TWIN_WOB_KN), 1)})
    path = folder / "log.csv"
    log.to_csv(path, index=False, lineterminator="\n")
    return tally, path


class TimedDamage:
    """A run's damage function with the seconds spent in it summed."""

    def __init__(self, fn: DamageFunction) -> None:
        self.fn = fn
        self.seconds = 0.0
        self.calls = 0

    def __call__(self, log: pd.DataFrame, context: RunContext) -> pd.DataFrame:
        t0 = time.perf_counter()
        out = self.fn(log, context)
        self.seconds += time.perf_counter() - t0
        self.calls += 1
        return out


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


def twin_survey() -> pd.DataFrame:
    """The survey of :data:`TWIN_PROFILE` from ``params.yaml``'s well section."""
    # optional extra [surrogate]: the twin's survey helper imports the surrogate package
    from drillfatigue.surrogate.twin import survey_from_well

    return survey_from_well(load_params(ROOT / "params.yaml").well, TWIN_PROFILE)


def start_twin_run(db: str, tally: Path, model: str, survey: pd.DataFrame) -> Ledger:
    """A ledger with run ``BENCH`` started with ``model``, as ``ledger run start --model``."""
    led, _ = init_ledger(db)
    start_run(led, "BENCH", "W-1", load_joint_tally(tally), model, model_id(model),
              TWIN_CONSTANTS, survey)
    return led


def domain_figures(led: Ledger) -> dict[str, Any]:
    """Coverage and out-of-domain time of the ledger's locations after a run."""
    with led.read() as conn:
        rows = conn.execute(select(
            joints.c.component_type, damage_totals.c.location, damage_totals.c.damage,
            damage_totals.c.time_in_hole_s, damage_totals.c.ood_time_s,
            damage_totals.c.not_covered_time_s, damage_totals.c.not_covered_reason)
            .join(joints, joints.c.id == damage_totals.c.joint_id)).all()
    t = pd.DataFrame(rows, columns=["component_type", "location", "damage", "hole_s", "ood_s",
                                    "nc_s", "reason"])
    covered = t["reason"].isna()
    in_hole = t["hole_s"] > 0
    in_domain = covered & (t["hole_s"] - t["ood_s"] > 0)
    groups = []
    for (ct, loc), g in t.groupby(["component_type", "location"], sort=True):
        cov = g["reason"].isna()
        groups.append({"component_type": ct, "location": loc, "locations": len(g),
                       "covered": int(cov.sum()), "in_hole": int((g["hole_s"] > 0).sum()),
                       "in_domain": int((cov & (g["hole_s"] - g["ood_s"] > 0)).sum()),
                       "hole_location_h": float(g["hole_s"].sum()) / 3600.0,
                       "ood_location_h": float(g["ood_s"].sum()) / 3600.0})
    hole_h = float(t.loc[covered, "hole_s"].sum()) / 3600.0
    ood_h = float(t.loc[covered, "ood_s"].sum()) / 3600.0
    return {
        "locations_tracked": len(t),
        "locations_covered": int(covered.sum()),
        "locations_in_hole": int(in_hole.sum()),
        "locations_covered_in_hole": int((covered & in_hole).sum()),
        "locations_in_domain": int(in_domain.sum()),
        "covered_location_hours_in_hole": hole_h,
        "ood_location_hours": ood_h,
        "ood_fraction_of_covered_hours": ood_h / hole_h if hole_h > 0 else None,
        "not_covered_location_hours": float(t["nc_s"].sum()) / 3600.0,
        "not_covered_reasons": sorted(set(t.loc[~covered, "reason"].astype(str))),
        "max_damage": float(t.loc[covered, "damage"].max()),
        "damage_sum": float(t.loc[covered, "damage"].sum()),
        "per_group": groups}


def one_twin(db: str, tally: Path, log: Path, chunk_rows: int, model: str,
             survey: pd.DataFrame) -> tuple[dict[str, float], dict[str, Any]]:
    led = start_twin_run(db, tally, model, survey)
    twin = TimedDamage(damage_function_for(model))
    t0 = time.perf_counter()
    reps = ingest_file(led, "BENCH", log, chunk_rows, damage_fn=twin)
    wall = time.perf_counter() - t0
    dom = domain_figures(led)
    led.dispose()
    span = reps[-1].t_last_s - reps[0].t_first_s
    return ({"chunk_rows": chunk_rows, "chunks": len(reps), "wall_s": wall,
             "log_time_per_wall_time": span / wall, "chunks_per_s": len(reps) / wall,
             "twin_s": twin.seconds, "ledger_own_s": wall - twin.seconds,
             "twin_share": twin.seconds / wall,
             "log_time_per_twin_time": span / twin.seconds,
             "log_time_per_ledger_own_time": span / (wall - twin.seconds),
             "increment_rows": len(reps) * 2 * N_JOINTS}, dom)


def machine(load0: float) -> dict[str, Any]:
    return {"cpu_count": os.cpu_count(), "python": platform.python_version(),
            "load_avg_1min_start": load0, "load_avg_1min_end": os.getloadavg()[0]}


def run_standin(hours: float) -> None:
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
            for k, rows in enumerate(CHUNK_ROWS):
                results["sqlite"].append(one(str(folder / f"l{k}.sqlite"), tally, log, rows))
                print("sqlite", results["sqlite"][-1], flush=True)
                if server is not None:
                    results["postgresql"].append(one(server.url(server.new_database()), tally,
                                                     log, rows))
                    print("postgresql", results["postgresql"][-1], flush=True)
        finally:
            stop_server(server, root)
    atomic_write_json(RESULT, {
        "machine": machine(load0),
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


def run_twin(model_path: Path, hours: float) -> None:
    if not (model_path / "metadata.json").is_file():
        raise ValueError(f"--model: {str(model_path)!r} is not a surrogate model folder "
                         "(allowed: a folder written by the train stage, with metadata.json)")
    model = str(model_path.resolve())
    load0 = os.getloadavg()[0]
    survey = twin_survey()
    results: dict[str, list[dict[str, float]]] = {"sqlite": [], "postgresql": []}
    domains: list[dict[str, Any]] = []
    with tempfile.TemporaryDirectory(prefix="ledger-bench-") as tmp:
        folder = Path(tmp)
        tally, log = write_twin_inputs(folder, hours)
        t0 = time.perf_counter()
        read_log_file(log)
        parse_s = time.perf_counter() - t0
        # warm-up: the model's load and the first calls (numba caches, torch), timed apart
        short = folder / "warm.csv"
        pd.read_csv(log, nrows=121).to_csv(short, index=False, lineterminator="\n")
        led = start_twin_run(str(folder / "warm.sqlite"), tally, model, survey)
        t0 = time.perf_counter()
        ingest_file(led, "BENCH", short, 60)
        warm_s = time.perf_counter() - t0
        led.dispose()
        print(f"warm-up {warm_s:.2f} s", flush=True)
        server, problem, root = start_server()
        try:
            for k, rows in enumerate(CHUNK_ROWS):
                res, dom = one_twin(str(folder / f"l{k}.sqlite"), tally, log, rows, model, survey)
                results["sqlite"].append(res)
                domains.append(dom)
                print("sqlite", res, flush=True)
                if server is not None:
                    res, dom = one_twin(server.url(server.new_database()), tally, log, rows,
                                        model, survey)
                    results["postgresql"].append(res)
                    domains.append(dom)
                    print("postgresql", res, flush=True)
        finally:
            stop_server(server, root)
    dom = domains[0]
    # every configuration counted the same log: the same locations and times, and the
    # same damage to the float32 network's batch round-off (docs/ledger.md)
    for d in domains[1:]:
        same = {k: d[k] for k in dom if k.startswith("locations")}
        if same != {k: dom[k] for k in same} or not np.isclose(
                d["ood_location_hours"], dom["ood_location_hours"], rtol=1e-9) or not np.isclose(
                d["damage_sum"], dom["damage_sum"], rtol=1e-5):
            raise RuntimeError(f"the configurations counted different things: {d} vs {dom}")
    atomic_write_json(RESULT_TWIN, {
        "machine": machine(load0),
        "damage_function": "digital twin (drillfatigue.ledger.twin_adapter.twin_increments: "
                           "surrogate.twin.replay_log)",
        "model": {"path": str(model_path), "model_id": model_id(model)},
        "log": {"hours": hours, "sample_s": 1.0, "rows": int(hours * 3600) + 1,
                "channels": ["time", "bit depth", "rpm", "wob"],
                "bit_md_m": [TWIN_START_MD_M, TWIN_START_MD_M + hours * TWIN_ROP_M_PER_H],
                "rpm_range": list(TWIN_RPM), "wob_kN_range": list(TWIN_WOB_KN)},
        "well": {"params": "params.yaml", "profile": TWIN_PROFILE,
                 "td_m": float(survey["md_m"].max())},
        "constants": TWIN_CONSTANTS,
        "string": {"joints": N_JOINTS, "tracked_locations": 2 * N_JOINTS,
                   "bha": [f"{s} {k} {m} m" for s, k, m in TWIN_BHA]},
        "domain": dom,
        "csv_parse_s": parse_s,
        "warm_up_s": warm_s,
        "warm_up": "model load and first calls: an ingest of 120 s of the log in 2 pieces "
                   "into a throwaway SQLite ledger, before the measured runs (not in the walls)",
        "timing": "twin_s: seconds inside the run's damage function (twin_increments); "
                  "ledger_own_s = wall_s - twin_s (log parse, bookkeeping, database)",
        "postgresql": ("PostgreSQL 15, Unix socket, fsync off" if not problem else
                       f"not run: {problem}"),
        "notes": TWIN_NOTES,
        "results": results,
    })
    print(f"wrote {RESULT_TWIN}")


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="a 2 h log instead of 24 h")
    ap.add_argument("--hours", type=float, default=None,
                    help="log length in hours (default 24, 2 with --quick)")
    ap.add_argument("--model", type=Path, default=None,
                    help="surrogate model folder: the runs use the digital twin "
                    f"(result in {RESULT_TWIN.name})")
    args = ap.parse_args(argv)
    hours = args.hours if args.hours is not None else 2.0 if args.quick else 24.0
    if args.model is None:
        if not hours > 0:
            raise ValueError(f"--hours: {hours} (allowed: > 0)")
        run_standin(hours)
        return 0
    top = (TWIN_MAX_MD_M - TWIN_START_MD_M) / TWIN_ROP_M_PER_H
    if not 0 < hours <= top:
        raise ValueError(f"--hours: {hours} with --model (allowed: 0 < hours <= {top:g}: the "
                         f"bit drills from {TWIN_START_MD_M:g} m at {TWIN_ROP_M_PER_H:g} m/h "
                         f"and the model's design ends at {TWIN_MAX_MD_M:g} m)")
    run_twin(args.model, hours)
    return 0


if __name__ == "__main__":
    sys.exit(main())
