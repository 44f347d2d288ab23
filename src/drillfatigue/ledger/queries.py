"""Questions to the ledger: the inventory, one joint's history, what to retire or inspect,
the runs, exports.

Plain functions returning DataFrames (SI: m, s; damage as a Miner fraction),
for the CLI and for the service's endpoints alike (:func:`in_units` shows
lengths and diameters in field units for both). A joint's damage is that of
its governing location (the largest best estimate over body and
connection, with that location's interval); remaining life is
``1 - damage`` with the interval ``[1 - upper, 1 - lower]``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pandas as pd
from sqlalchemy import Connection, func, select

from drillfatigue.errors import InputError
from drillfatigue.files import OutputFolder, atomic_output
from drillfatigue.io.display import Display, check_system
from drillfatigue.ledger.db import Ledger
from drillfatigue.ledger.schema import (
    chunks,
    damage_increments,
    damage_totals,
    inspections,
    joints,
    run_items,
    runs,
    serial_events,
)
from drillfatigue.ledger.store import OPEN, RP7G2_CLASSES, joint_row

EXPORT_KIND = "ledger-export"
EXPORT_FORMATS = ("csv", "parquet")


def _frame(conn: Connection, stmt: object) -> pd.DataFrame:
    res = conn.execute(stmt)  # type: ignore[call-overload]
    return pd.DataFrame(res.fetchall(), columns=list(res.keys()))


def in_units(frame: pd.DataFrame, units: str = "si", option: str = "--units") -> pd.DataFrame:
    """``frame`` with its lengths and diameters shown in ``units`` (``si`` or ``field``).

    A column ``NAME_m`` becomes ``NAME_<unit>``: diameters and walls (``od_m``,
    ``id_m``, ``wall_m``) in mm or in, other lengths in m or ft. Other columns
    are left as they are. ``option`` names the setting in the error of an
    unknown unit system (``--units`` for the CLI, ``units`` for the service).
    """
    display = Display(check_system(units, option))
    out = frame.copy()
    for col in list(out.columns):
        if col.endswith("_m") and col.startswith(("od", "id", "wall")):
            q, base = "diameter", col[:-2]
        elif col.endswith("_m"):
            q, base = "length", col[:-2]
        else:
            continue
        unit = display.unit(q).replace(" ", "_").replace("/", "_per_")
        out[f"{base}_{unit}"] = display.value(q, pd.to_numeric(out.pop(col)).to_numpy(float))
    return out


def _last_inspections(conn: Connection) -> pd.DataFrame:
    ins = _frame(conn, select(inspections.c.joint_id, inspections.c.inspected_on,
                              inspections.c.method, inspections.c.standard,
                              inspections.c.result, inspections.c.damage_upper_at_record,
                              inspections.c.id))
    if ins.empty:
        return ins
    ins = ins.sort_values(["joint_id", "inspected_on", "id"])
    return ins.groupby("joint_id", as_index=False).tail(1).set_index("joint_id")


def inventory(ledger: Ledger) -> pd.DataFrame:
    """Every joint by remaining life (least first), with intervals.

    Returns
    -------
    DataFrame
        ``serial``, ``component_type``, ``grade``, ``od_m``, ``length_m``,
        ``governing_location``, ``damage``, ``damage_lower``,
        ``damage_upper``, ``remaining_life``, ``remaining_life_lower``,
        ``remaining_life_upper``, ``time_in_hole_h``, ``revolutions``,
        ``ood_h`` (time out of the model's domain), ``not_covered``
        (reason, empty if covered everywhere), ``runs`` (number of runs),
        ``last_inspection`` and ``last_result``. Damage is NaN for a joint
        the model covers nowhere it has been.
    """
    with ledger.read() as conn:
        j = _frame(conn, select(joints.c.id, joints.c.serial, joints.c.component_type,
                                joints.c.grade, joints.c.od_m, joints.c.length_m))
        tot = _frame(conn, select(damage_totals))
        n_runs = _frame(conn, select(run_items.c.joint_id, run_items.c.run_id))
        last = _last_inspections(conn)
    by = tot.groupby("joint_id")
    # governing location: the largest best estimate among locations the model covered
    cov = tot[(tot["not_covered_time_s"] < tot["time_in_hole_s"]) | (tot["time_in_hole_s"] == 0)]
    gov = (cov.sort_values(["joint_id", "damage", "location"], ascending=[True, False, True],
                           kind="stable")
           .drop_duplicates("joint_id").set_index("joint_id"))
    reasons = by["not_covered_reason"].agg(lambda r: "; ".join(sorted({str(x) for x in r.dropna()})))
    runs_of = n_runs["joint_id"].value_counts() if len(n_runs) else pd.Series(dtype=int)
    ids = j["id"]
    g = gov.reindex(ids)
    d = g["damage"].to_numpy(dtype=float)
    lo = g["damage_lower"].to_numpy(dtype=float)
    hi = g["damage_upper"].to_numpy(dtype=float)
    li = last.reindex(ids) if len(last) else pd.DataFrame(index=ids,
                                                          columns=["inspected_on", "result"])
    frame = pd.DataFrame({
        "serial": j["serial"].to_numpy(), "component_type": j["component_type"].to_numpy(),
        "grade": j["grade"].to_numpy(), "od_m": j["od_m"].to_numpy(),
        "length_m": j["length_m"].to_numpy(),
        "governing_location": g["location"].fillna("").to_numpy(),
        "damage": d, "damage_lower": lo, "damage_upper": hi,
        "remaining_life": 1.0 - d, "remaining_life_lower": 1.0 - hi,
        "remaining_life_upper": 1.0 - lo,
        "time_in_hole_h": by["time_in_hole_s"].max().reindex(ids).fillna(0.0).to_numpy() / 3600.0,
        "revolutions": by["revolutions"].max().reindex(ids).fillna(0.0).to_numpy(),
        "ood_h": by["ood_time_s"].max().reindex(ids).fillna(0.0).to_numpy() / 3600.0,
        "not_covered": reasons.reindex(ids).fillna("").to_numpy(),
        "runs": runs_of.reindex(ids).fillna(0).astype(int).to_numpy(),
        "last_inspection": li["inspected_on"].to_numpy(),
        "last_result": li["result"].to_numpy(),
    })
    return frame.sort_values(["remaining_life", "serial"], na_position="last",
                           kind="stable").reset_index(drop=True)


def runs_table(ledger: Ledger) -> pd.DataFrame:
    """Every run, in the order it was started.

    Returns
    -------
    DataFrame
        ``run``, ``well``, ``status`` (open or ended), ``joints`` (tally
        length), ``chunks`` (log chunks ingested), ``first_t_s`` and
        ``last_t_s`` (the ingested log's time span on its own clock, s; NaN
        before the first chunk), ``log_h`` (that span in hours), ``model``
        (model folder or ``python:MODULE:FUNCTION``), ``model_id``,
        ``started_at`` and ``ended_at`` (UTC, when recorded).
    """
    with ledger.read() as conn:
        r = _frame(conn, select(runs.c.id, runs.c.name, runs.c.well, runs.c.status,
                                runs.c.chunk_seq, runs.c.first_t_s, runs.c.last_t_s,
                                runs.c.model_ref, runs.c.model_id, runs.c.started_at,
                                runs.c.ended_at).order_by(runs.c.id))
        n: dict[int, int] = {int(i): int(c) for i, c in conn.execute(
            select(run_items.c.run_id, func.count()).group_by(run_items.c.run_id))}
    first = pd.to_numeric(r["first_t_s"]).to_numpy(dtype=float)
    last = pd.to_numeric(r["last_t_s"]).to_numpy(dtype=float)
    return pd.DataFrame({
        "run": r["name"].to_numpy(), "well": r["well"].to_numpy(),
        "status": r["status"].to_numpy(),
        "joints": np.array([n.get(int(i), 0) for i in r["id"]], dtype=np.int64),
        "chunks": r["chunk_seq"].to_numpy(dtype=int), "first_t_s": first, "last_t_s": last,
        "log_h": (last - first) / 3600.0, "model": r["model_ref"].to_numpy(),
        "model_id": r["model_id"].to_numpy(), "started_at": r["started_at"].to_numpy(),
        "ended_at": r["ended_at"].to_numpy()})


def ledger_summary(ledger: Ledger) -> dict[str, object]:
    """What the ledger holds: back-end, where (password hidden), schema revision and the
    number of joints, runs, open runs, log chunks and inspections."""
    with ledger.read() as conn:
        def count(stmt: object) -> int:
            return int(conn.execute(stmt).scalar_one())  # type: ignore[call-overload]

        counts = {"joints": count(select(func.count()).select_from(joints)),
                  "runs": count(select(func.count()).select_from(runs)),
                  "open_runs": count(select(func.count()).select_from(runs)
                                     .where(runs.c.status == OPEN)),
                  "chunks": count(select(func.count()).select_from(chunks)),
                  "inspections": count(select(func.count()).select_from(inspections))}
    return {"backend": ledger.dialect, "database": ledger.shown_name(),
            "schema_revision": ledger.revision(), **counts}


@dataclass(frozen=True)
class JointHistory:
    """One joint over its runs: ``runs`` (per run and location: position,
    distance from the bit, damage with interval, hours, revolutions, time out
    of domain, not covered), ``events`` (serial corrections and swaps) and
    ``inspections``."""

    serial: str
    component_type: str
    runs: pd.DataFrame
    events: pd.DataFrame
    inspections: pd.DataFrame


def history(ledger: Ledger, serial: str) -> JointHistory:
    """The history of the joint that now carries ``serial``."""
    with ledger.read() as conn:
        j = joint_row(conn, serial)
        items = _frame(conn, select(runs.c.id.label("run_id"), runs.c.name.label("run"),
                                    runs.c.well, runs.c.first_t_s, runs.c.last_t_s,
                                    run_items.c.position, run_items.c.s_bottom_m,
                                    run_items.c.s_top_m)
                       .join(run_items, run_items.c.run_id == runs.c.id)
                       .where(run_items.c.joint_id == j.id).order_by(runs.c.id))
        inc = _frame(conn, select(chunks.c.run_id, chunks.c.seq, damage_increments)
                     .join(chunks, chunks.c.id == damage_increments.c.chunk_id)
                     .where(damage_increments.c.joint_id == j.id))
        ev = _frame(conn, select(serial_events.c.kind, serial_events.c.old_serial,
                                 serial_events.c.new_serial, serial_events.c.reason,
                                 serial_events.c.recorded_at)
                    .where(serial_events.c.joint_id == j.id).order_by(serial_events.c.id))
        ins = _frame(conn, select(inspections.c.inspected_on, inspections.c.method,
                                  inspections.c.standard, inspections.c.result,
                                  inspections.c.wall_m, inspections.c.od_m,
                                  inspections.c.connection_condition,
                                  inspections.c.damage_upper_at_record)
                     .where(inspections.c.joint_id == j.id)
                     .order_by(inspections.c.inspected_on, inspections.c.id))
    rows = []
    for it in items.itertuples(index=False):
        part = inc[inc["run_id"] == it.run_id].sort_values("seq") if len(inc) else inc
        locs = sorted(set(part["location"])) if len(part) else []
        for loc in locs:
            p = part[part["location"] == loc]
            cov = p[p["covered"].astype(bool)]
            rows.append({
                "run": it.run, "well": it.well, "position": int(it.position),
                "s_bottom_m": it.s_bottom_m, "s_top_m": it.s_top_m, "location": loc,
                "damage": math.fsum(cov["damage"]), "damage_lower": math.fsum(cov["damage_lower"]),
                "damage_upper": math.fsum(cov["damage_upper"]),
                "time_in_hole_h": math.fsum(p["time_in_hole_s"]) / 3600.0,
                "revolutions": math.fsum(p["revolutions"]),
                "ood_h": math.fsum(p["ood_time_s"]) / 3600.0,
                "not_covered": "; ".join(sorted({str(r) for r in
                                                 p["not_covered_reason"].dropna()})),
                "chunks": int(p["seq"].nunique())})
        if not locs:
            rows.append({"run": it.run, "well": it.well, "position": int(it.position),
                         "s_bottom_m": it.s_bottom_m, "s_top_m": it.s_top_m, "location": "",
                         "damage": 0.0, "damage_lower": 0.0, "damage_upper": 0.0,
                         "time_in_hole_h": 0.0, "revolutions": 0.0, "ood_h": 0.0,
                         "not_covered": "", "chunks": 0})
    return JointHistory(serial=j.serial, component_type=j.component_type,
                        runs=pd.DataFrame(rows), events=ev, inspections=ins)


@dataclass(frozen=True)
class RetireRules:
    """When a joint is listed to retire or to inspect.

    Attributes
    ----------
    retire_at : float
        Retire when the best-estimate damage reaches this fraction.
    inspect_at : float
        Inspect when the upper bound of damage reaches this fraction.
    reinspect_after : float
        After an inspection, list again once the upper bound has grown by
        this much since it was recorded.
    downgraded_retire_at : float
        ``retire_at`` for a joint whose last RP 7G-2 inspection gave class 2
        or class 3 (less wall left: less life left).
    retire_results : tuple of str
        Inspection results that retire a joint whatever its damage.
    """

    retire_at: float = 0.8
    inspect_at: float = 0.5
    reinspect_after: float = 0.1
    downgraded_retire_at: float = 0.5
    retire_results: tuple[str, ...] = ("scrap",)

    def __post_init__(self) -> None:
        for name in ("retire_at", "inspect_at", "reinspect_after", "downgraded_retire_at"):
            v = getattr(self, name)
            if not (math.isfinite(v) and 0.0 < v <= 1.0):
                raise InputError("--" + name.replace("_", "-"), f"{v!r}", "0 < fraction <= 1")
        if self.downgraded_retire_at > self.retire_at:
            raise InputError("--downgraded-retire-at", f"{self.downgraded_retire_at!r} above "
                             f"--retire-at {self.retire_at!r}", "<= --retire-at")
        for r in self.retire_results:
            if r not in RP7G2_CLASSES:
                raise InputError("retire_results", f"{r!r}", ", ".join(RP7G2_CLASSES))


DOWNGRADED = ("class2", "class3")


def retire_lists(ledger: Ledger, rules: RetireRules | None = None) -> pd.DataFrame:
    """Joints to retire and to inspect under ``rules``: the inventory's rows with
    ``action`` (``retire`` or ``inspect``) and ``reason``; others are left out."""
    rules = rules or RetireRules()
    inv = inventory(ledger)
    with ledger.read() as conn:
        last = _last_inspections(conn)
        ids = {s: i for s, i in conn.execute(select(joints.c.serial, joints.c.id))}
    out = []
    for row in inv.to_dict("records"):
        li = last.loc[ids[row["serial"]]] if len(last) and ids[row["serial"]] in last.index else None
        result = None if li is None else str(li["result"])
        day = "" if li is None else str(li["inspected_on"])
        d, hi = row["damage"], row["damage_upper"]
        at = rules.downgraded_retire_at if result in DOWNGRADED else rules.retire_at
        action = reason = None
        if result in rules.retire_results:
            action, reason = "retire", f"last inspection {day}: {result}"
        elif np.isfinite(d) and d >= at:
            action = "retire"
            reason = f"damage {d:.3g} >= {at:g}" + (f" (last inspection: {result})"
                                                     if result in DOWNGRADED else "")
        elif np.isfinite(hi) and hi >= rules.inspect_at:
            since = None if li is None else float(li["damage_upper_at_record"])
            if since is None or hi - since >= rules.reinspect_after:
                action = "inspect"
                reason = (f"upper bound {hi:.3g} >= {rules.inspect_at:g}" if since is None else
                          f"upper bound {hi:.3g} grew {hi - since:.3g} since the inspection of "
                          f"{day}")
        elif not np.isfinite(d) and row["time_in_hole_h"] > 0:
            action, reason = "inspect", f"damage unknown: not covered ({row['not_covered']})"
        if action is not None:
            out.append({**row, "action": action, "reason": reason})
    cols = [*inv.columns, "action", "reason"]
    res = pd.DataFrame(out, columns=cols)
    return res.sort_values(["action", "remaining_life", "serial"], ascending=[False, True, True],
                           na_position="last", kind="stable").reset_index(drop=True)


def export_tables(ledger: Ledger) -> dict[str, pd.DataFrame]:
    """The ledger as tables with natural keys, in a fixed row order.

    Database ids and the wall-clock times records were written at are left
    out, so two ledgers that recorded the same things export the same bytes.
    """
    with ledger.read() as conn:
        jn = _frame(conn, select(joints.c.id, joints.c.serial))
        serial_of = dict(zip(jn["id"], jn["serial"], strict=True))
        rn = _frame(conn, select(runs.c.id, runs.c.name))
        run_of = dict(zip(rn["id"], rn["name"], strict=True))
        tables = {
            "joints": _frame(conn, select(joints).order_by(joints.c.serial)),
            "runs": _frame(conn, select(runs).order_by(runs.c.name)),
            "run_items": _frame(conn, select(run_items)),
            "chunks": _frame(conn, select(chunks)),
            "damage_increments": _frame(conn, select(chunks.c.run_id, chunks.c.seq,
                                                     damage_increments)
                                        .join(chunks, chunks.c.id == damage_increments.c.chunk_id)),
            "damage_totals": _frame(conn, select(damage_totals)),
            "inspections": _frame(conn, select(inspections)),
            "serial_events": _frame(conn, select(serial_events).order_by(serial_events.c.id)),
        }
    drop = {"id", "chunk_id", "ingested_at", "recorded_at", "started_at", "ended_at"}
    keys = {"joints": ["serial"], "runs": ["run"], "run_items": ["run", "position"],
            "chunks": ["run", "seq"], "damage_increments": ["run", "seq", "serial", "location"],
            "damage_totals": ["serial", "location"],
            "inspections": ["serial", "inspected_on", "method"], "serial_events": []}
    out = {}
    for name, df in tables.items():
        df = df.copy()
        if name == "runs":
            df = df.rename(columns={"name": "run"})
        if "run_id" in df.columns:
            df.insert(0, "run", df.pop("run_id").map(run_of))
        if "joint_id" in df.columns:
            df.insert(1 if "run" in df.columns else 0, "serial", df.pop("joint_id").map(serial_of))
        df = df.drop(columns=[c for c in drop if c in df.columns])
        if keys[name]:
            df = df.sort_values(keys[name], kind="stable")
        out[name] = df.reset_index(drop=True)
    return out


def export_ledger(ledger: Ledger, out: str | Path, fmt: str = "csv") -> list[Path]:
    """Write :func:`export_tables` into folder ``out`` (``NAME.csv`` or ``NAME.parquet``).

    The folder is claimed with a ``ledger-export`` marker: a folder holding
    other files is refused, and only files this command wrote are replaced.
    """
    if fmt not in EXPORT_FORMATS:
        raise InputError("--format", f"{fmt!r}", ", ".join(EXPORT_FORMATS))
    tables = export_tables(ledger)
    names = [f"{n}.{fmt}" for n in tables]
    folder = OutputFolder(out, EXPORT_KIND, "--out", names=names)
    written = []
    for name, df in tables.items():
        path = folder.file(f"{name}.{fmt}")
        with atomic_output(path) as tmp:
            if fmt == "csv":
                df.to_csv(tmp, index=False, lineterminator="\n")
            else:
                df.to_parquet(tmp, index=False)
        written.append(path)
    return written
