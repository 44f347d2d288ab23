"""Runs, joints, serial events and inspections: the ledger's records other than log data.

Damage follows the joint, not the position: a run's tally links each
position to a joint by its serial; a later run with the stands in another
order links the same joints to other positions, and each joint's totals keep
growing. A joint's serial changes only through a recorded event
(:func:`correct_serial`, :func:`swap_serials`) with its reason.
"""

from __future__ import annotations

import datetime as dt
import json
import math
from collections.abc import Mapping
from typing import Any

import pandas as pd
from sqlalchemy import Connection, Row, and_, func, insert, select, update

from drillfatigue.errors import InputError
from drillfatigue.ledger.db import Ledger
from drillfatigue.ledger.increments import LOCATIONS, RunContext
from drillfatigue.ledger.schema import (
    damage_totals,
    inspections,
    joints,
    run_items,
    runs,
    serial_events,
)

OPEN = "open"
ENDED = "ended"
#: RP 7G-2 classes of used drill pipe (plus new and scrap), and DS-1 categories.
RP7G2_CLASSES: tuple[str, ...] = ("new", "premium", "class2", "class3", "scrap")
DS1_CATEGORIES: tuple[str, ...] = ("1", "2", "3", "4", "5")
STANDARDS: dict[str, tuple[str, ...]] = {"rp7g2": RP7G2_CLASSES, "ds1": DS1_CATEGORIES}
_MAX_NAME = 64


def now_utc() -> str:
    """The current UTC time, ISO 8601 to the second (when a record was written)."""
    return dt.datetime.now(dt.UTC).isoformat(timespec="seconds")


class NotInLedger(InputError):
    """A run or a serial the ledger does not hold (the service answers 404 for a serial)."""


def _name(value: str, field: str) -> str:
    v = str(value).strip()
    if not v or len(v) > _MAX_NAME or any(ord(c) < 32 for c in v):
        raise InputError(field, f"{value!r}", f"1 to {_MAX_NAME} printable characters")
    return v


def run_row(conn: Connection, name: str) -> Row[Any]:
    """The row of run ``name``; InputError if there is none."""
    row = conn.execute(select(runs).where(runs.c.name == name)).first()
    if row is None:
        known = [r[0] for r in conn.execute(select(runs.c.name).order_by(runs.c.name).limit(10))]
        raise NotInLedger("--run", f"no run {name!r} in the ledger",
                         ", ".join(known) if known else "start one: drillfatigue ledger run start")
    return row


def joint_row(conn: Connection, serial: str) -> Row[Any]:
    """The row of the joint that now carries ``serial``; InputError if none."""
    row = conn.execute(select(joints).where(joints.c.serial == serial)).first()
    if row is None:
        raise NotInLedger("SERIAL", f"no joint {serial!r} in the ledger",
                         "a serial from a run's tally (drillfatigue ledger joints)")
    return row


def survey_json(survey: pd.DataFrame | None) -> str | None:
    if survey is None:
        return None
    cols = [c for c in ("md_m", "inc_deg", "dls_deg_per_30m") if c in survey.columns]
    return json.dumps({c: [float(v) for v in survey[c]] for c in cols})


def run_context(conn: Connection, run: Row[Any]) -> RunContext:
    """The :class:`RunContext` a damage function gets for ``run``."""
    q = (select(run_items.c.position, joints.c.serial, joints.c.component_type,
                run_items.c.length_m, run_items.c.s_bottom_m, run_items.c.s_top_m,
                joints.c.od_m, joints.c.id_m, joints.c.grade, run_items.c.joint_id)
         .join(joints, joints.c.id == run_items.c.joint_id)
         .where(run_items.c.run_id == run.id).order_by(run_items.c.position))
    items = pd.DataFrame([dict(r._mapping) for r in conn.execute(q)])
    survey = None
    if run.survey_json:
        survey = pd.DataFrame(json.loads(run.survey_json))
    return RunContext(run=run.name, items=items, model_ref=run.model_ref,
                      constants=json.loads(run.constants_json), survey=survey)


def start_run(ledger: Ledger, name: str, well: str, tally: pd.DataFrame, model_ref: str,
              model_id: str, constants: Mapping[str, str] | None = None,
              survey: pd.DataFrame | None = None) -> int:
    """Register a run with its tally (from the bit up); return the number of new joints.

    A serial seen before is the same joint (its damage continues); a new one
    is added with the tally's type, dimensions and grade. Refused: a run name
    in use, a serial of another type than recorded, a joint that is in
    another open run (one joint cannot be in two holes).
    """
    name = _name(name, "RUN")
    well = _name(well, "--well")
    if tally.empty:
        raise InputError("--tally", "no joints", ">= 1 joint")
    consts = {str(k): str(v) for k, v in (constants or {}).items()}
    new_joints = 0
    with ledger.write() as conn:
        if conn.execute(select(runs.c.id).where(runs.c.name == name)).first() is not None:
            raise InputError("RUN", f"a run named {name!r} exists", "a new run name")
        run_id = conn.execute(insert(runs).values(
            name=name, well=well, survey_json=survey_json(survey), model_ref=model_ref,
            model_id=model_id, constants_json=json.dumps(consts, sort_keys=True),
            status=OPEN, started_at=now_utc(), chunk_seq=0).returning(runs.c.id)).scalar_one()
        for it in tally.itertuples(index=False):
            j = conn.execute(select(joints).where(joints.c.serial == it.serial)).first()
            if j is None:
                jid = conn.execute(insert(joints).values(
                    serial=it.serial, component_type=it.component_type,
                    description=_text(it.description) or "", od_m=_num(it.od_m), id_m=_num(it.id_m),
                    length_m=float(it.length_m), grade=_text(it.grade),
                    connection=_text(it.connection)).returning(joints.c.id)).scalar_one()
                new_joints += 1
            else:
                if j.component_type != it.component_type:
                    raise InputError(f"--tally:{it.serial}", f"type {it.component_type!r}, "
                                     f"recorded as {j.component_type!r}",
                                     "the recorded type, or correct the serial first "
                                     "(drillfatigue ledger serial correct)")
                jid = j.id
                busy = conn.execute(
                    select(runs.c.name).join(run_items, run_items.c.run_id == runs.c.id)
                    .where(run_items.c.joint_id == jid, runs.c.status == OPEN,
                           runs.c.id != run_id)).first()
                if busy is not None:
                    raise InputError(f"--tally:{it.serial}", f"joint is in open run {busy[0]!r}",
                                     f"end that run first: drillfatigue ledger run end "
                                     f"{busy[0]}")
            conn.execute(insert(run_items).values(
                run_id=run_id, position=int(it.position), joint_id=jid,
                length_m=float(it.length_m), s_bottom_m=float(it.s_bottom_m),
                s_top_m=float(it.s_top_m)))
            for loc in LOCATIONS:
                have = conn.execute(select(damage_totals.c.joint_id).where(
                    damage_totals.c.joint_id == jid, damage_totals.c.location == loc)).first()
                if have is None:
                    conn.execute(insert(damage_totals).values(
                        joint_id=jid, location=loc, damage=0.0, damage_lower=0.0,
                        damage_upper=0.0, time_in_hole_s=0.0, revolutions=0.0, ood_time_s=0.0,
                        not_covered_time_s=0.0, not_covered_reason=None))
    return new_joints


def _num(v: Any) -> float | None:
    if v is None:
        return None
    f = float(v)
    return None if math.isnan(f) else f


def _text(v: Any) -> str | None:
    """A tally cell as text, None where empty (pandas gives NaN for a missing value)."""
    if v is None or (isinstance(v, float) and math.isnan(v)):
        return None
    return str(v)


def end_run(ledger: Ledger, name: str) -> bool:
    """Mark a run ended (no more log data); False if it already was."""
    with ledger.write() as conn:
        run = run_row(conn, name)
        if run.status == ENDED:
            return False
        conn.execute(update(runs).where(runs.c.id == run.id)
                     .values(status=ENDED, ended_at=now_utc()))
    return True


def correct_serial(ledger: Ledger, old: str, new: str, reason: str) -> None:
    """A mistyped or re-tagged serial: the joint ``old`` carries ``new`` from now on.

    Its history stays with it; the event is recorded with ``reason``.
    """
    new = _name(new, "NEW")
    reason = _reason(reason)
    with ledger.write() as conn:
        j = joint_row(conn, old)
        if conn.execute(select(joints.c.id).where(joints.c.serial == new)).first() is not None:
            raise InputError("NEW", f"serial {new!r} belongs to another joint",
                             "a serial not in the ledger (or swap the two: ledger serial swap)")
        conn.execute(update(joints).where(joints.c.id == j.id).values(serial=new))
        conn.execute(insert(serial_events).values(joint_id=j.id, kind="correction",
                                                  old_serial=old, new_serial=new, reason=reason,
                                                  recorded_at=now_utc()))


def swap_serials(ledger: Ledger, a: str, b: str, reason: str) -> None:
    """Two joints' tags were swapped: joint ``a`` becomes ``b`` and ``b`` becomes ``a``.

    What was recorded under each serial stays with the physical joint; two
    events are recorded with ``reason``.
    """
    reason = _reason(reason)
    if a == b:
        raise InputError("B", "the same serial twice", "two different serials")
    with ledger.write() as conn:
        ja, jb = joint_row(conn, a), joint_row(conn, b)
        tmp = f"\x01swap{ja.id}"  # no serial has a control character: the unique key holds
        conn.execute(update(joints).where(joints.c.id == ja.id).values(serial=tmp))
        conn.execute(update(joints).where(joints.c.id == jb.id).values(serial=a))
        conn.execute(update(joints).where(joints.c.id == ja.id).values(serial=b))
        t = now_utc()
        for jid, old, new in ((ja.id, a, b), (jb.id, b, a)):
            conn.execute(insert(serial_events).values(joint_id=jid, kind="swap", old_serial=old,
                                                      new_serial=new, reason=reason,
                                                      recorded_at=t))


def _reason(reason: str) -> str:
    r = " ".join(str(reason).split())
    if not r:
        raise InputError("--reason", "empty", "why the serial changes (a tag swap, a typo, ...)")
    return r


def joint_damage_upper(conn: Connection, joint_id: int) -> float:
    """The joint's governing (largest over locations) upper bound of damage."""
    v = conn.execute(select(func.max(damage_totals.c.damage_upper))
                     .where(damage_totals.c.joint_id == joint_id)).scalar()
    return float(v or 0.0)


def record_inspection(ledger: Ledger, serial: str, inspected_on: str, method: str,
                      standard: str, result: str, wall_m: float | None = None,
                      od_m: float | None = None, connection_condition: str | None = None) -> bool:
    """Record an inspection of joint ``serial``; False if that day's inspection by
    that method was recorded already (the record is written once).

    ``standard`` is ``rp7g2`` (result: one of :data:`RP7G2_CLASSES`) or
    ``ds1`` (result: a category of :data:`DS1_CATEGORIES`).
    """
    try:
        day = dt.date.fromisoformat(str(inspected_on))
    except ValueError:
        raise InputError("--date", f"{inspected_on!r}", "a date YYYY-MM-DD") from None
    std = str(standard).lower().replace("-", "").replace(" ", "")
    if std not in STANDARDS:
        raise InputError("--standard", f"{standard!r}", ", ".join(STANDARDS))
    res = str(result).lower().replace(" ", "").replace("-", "")
    if res not in STANDARDS[std]:
        raise InputError("--result", f"{result!r} for {std}", ", ".join(STANDARDS[std]))
    meth = _name(method, "--method")
    for name, v, hi in (("--od", od_m, 1.0), ("--wall", wall_m, 0.5)):
        if v is not None and not (math.isfinite(v) and 0.0 < v < hi):
            raise InputError(name, f"{v!r} m", f"0 < {name[2:]} < {hi:g} m")
    if wall_m is not None and od_m is not None and wall_m >= od_m / 2:
        raise InputError("--wall", f"{wall_m:.4g} m is not below half the OD {od_m:.4g} m",
                         "0 < wall < OD / 2")
    with ledger.write() as conn:
        j = joint_row(conn, serial)
        j_od = j.od_m
        if wall_m is not None and od_m is None and j_od is not None and wall_m >= j_od / 2:
            raise InputError("--wall", f"{wall_m:.4g} m is not below half the joint's OD "
                             f"{j_od:.4g} m", "0 < wall < OD / 2")
        have = conn.execute(select(inspections.c.id).where(and_(
            inspections.c.joint_id == j.id, inspections.c.inspected_on == day.isoformat(),
            inspections.c.method == meth))).first()
        if have is not None:
            return False
        conn.execute(insert(inspections).values(
            joint_id=j.id, inspected_on=day.isoformat(), method=meth, standard=std, result=res,
            wall_m=wall_m, od_m=od_m, connection_condition=connection_condition,
            damage_upper_at_record=joint_damage_upper(conn, j.id), recorded_at=now_utc()))
    return True
