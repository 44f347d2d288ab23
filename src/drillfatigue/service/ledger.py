"""The fatigue ledger's endpoints of ``drillfatigue serve --ledger DB``.

=====================================  =====================================================
``GET  /v1/ledger``                    the ledger: back-end, schema revision, counts
``GET  /v1/ledger/runs``               the runs (``ledger run list``)
``POST /v1/ledger/ingest``             one chunk of an open run's log, exactly once
                                       (``ledger ingest``)
``GET  /v1/ledger/joints``             the inventory by remaining life (``ledger joints``)
``GET  /v1/ledger/joints/{serial}``    one joint over its runs (``ledger history``)
``GET  /v1/ledger/retire``             the retire and inspect lists (``ledger retire``)
=====================================  =====================================================

Each endpoint calls the function the command calls
(:mod:`drillfatigue.ledger.queries`, :func:`drillfatigue.ledger.ingest_chunk`)
and adds only transport: the request's names for the command's options
(``retire_at`` for ``--retire-at``) and JSON cells (NaN as null). A server
started without ``--ledger`` answers every one of them 503 with one line; an
unknown serial in the path is a 404, any other refusal a 422 naming the field,
and a refused chunk writes nothing (one chunk, one transaction).
"""

from __future__ import annotations

import math
import re
from dataclasses import asdict
from typing import Any

import numpy as np
import pandas as pd
from fastapi import FastAPI, Query

from drillfatigue.errors import InputError
from drillfatigue.io.display import check_system
from drillfatigue.ledger import (
    Ledger,
    NotInLedger,
    RetireRules,
    history,
    in_units,
    ingest_chunk,
    inventory,
    ledger_summary,
    retire_lists,
    runs_table,
)
from drillfatigue.ledger.ingest import LOG_FORMATS, read_log_bytes
from drillfatigue.service.errors import NotFound, NotServed
from drillfatigue.service.schemas import (
    JointHistoryResponse,
    LedgerCell,
    LedgerIngestRequest,
    LedgerIngestResponse,
    LedgerInfo,
    LedgerJointsResponse,
    LedgerRetireResponse,
    LedgerTable,
    RetireRulesOut,
)

_DEFAULT_RULES = RetireRules()
#: the commands' option names in the ledger's errors -> the request's names
_REQUEST_NAMES = {"--run": "run", "RUN": "run", "SERIAL": "serial", "--units": "units",
                  **{"--" + f.replace("_", "-"): f for f in
                     ("retire_at", "inspect_at", "reinspect_after", "downgraded_retire_at")}}
_OPTION = re.compile(r"(?<![\w-])--[a-z][a-z-]*")


def _request_names(text: str | None) -> str | None:
    """Option names (``--retire-at``) in a message as the request names them."""
    if text is None:
        return None
    return _OPTION.sub(lambda m: _REQUEST_NAMES.get(m.group(0), m.group(0)), text)


def request_error(exc: InputError) -> InputError:
    """``exc`` with the commands' option names replaced by the request's."""
    return InputError(_REQUEST_NAMES.get(exc.field, exc.field),
                      _request_names(exc.problem) or "", _request_names(exc.allowed))


def _cell(v: Any) -> LedgerCell:
    if isinstance(v, np.generic):
        v = v.item()
    if isinstance(v, float) and not math.isfinite(v):
        return None
    if v is pd.NaT or v is pd.NA:
        return None
    return v  # type: ignore[no-any-return]


def _rows(frame: pd.DataFrame) -> list[dict[str, LedgerCell]]:
    cols = [str(c) for c in frame.columns]
    return [{c: _cell(v) for c, v in zip(cols, row, strict=True)}
            for row in frame.itertuples(index=False, name=None)]


def _table(frame: pd.DataFrame) -> LedgerTable:
    return LedgerTable(columns=[str(c) for c in frame.columns], rows=_rows(frame))


def add_ledger_routes(app: FastAPI, ledger: Ledger | None, max_log_rows: int,
                      errors: dict[int | str, dict[str, Any]]) -> None:
    """Add the ``/v1/ledger`` endpoints to ``app``, answering from ``ledger`` (None: 503)."""
    errs = errors
    unknown: dict[int | str, dict[str, Any]] = {
        404: {"model": errors[422]["model"], "description": "no joint with this serial"}}

    def served() -> Ledger:
        if ledger is None:
            raise NotServed("ledger", "this server opened no ledger",
                            "start it with drillfatigue serve --ledger PATH_OR_URL")
        return ledger

    def units_of(units: str) -> str:
        return check_system(units, "units")  # before the ledger is read

    @app.get("/v1/ledger", response_model=LedgerInfo, responses=errs)
    def ledger_info() -> LedgerInfo:
        return LedgerInfo(**ledger_summary(served()))  # type: ignore[arg-type]

    @app.get("/v1/ledger/runs", response_model=LedgerTable, responses=errs)
    def ledger_runs() -> LedgerTable:
        return _table(runs_table(served()))

    @app.post("/v1/ledger/ingest", response_model=LedgerIngestResponse, responses=errs)
    def ledger_ingest(req: LedgerIngestRequest) -> LedgerIngestResponse:
        led = served()
        suffix = LOG_FORMATS.get(req.log.format)
        if suffix is None:
            raise InputError("log.format", f"unknown log format {req.log.format!r}",
                             ", ".join(LOG_FORMATS))
        try:
            chunk = read_log_bytes(req.log.text.encode("utf-8"), suffix, req.source)
            if len(chunk.table) > max_log_rows:
                raise InputError("log.text", f"{len(chunk.table)} rows",
                                 f"at most {max_log_rows} per chunk")
            report = ingest_chunk(led, req.run, chunk)
        except InputError as exc:
            # the ledger names a chunk by its source (a file for the command): here the text
            field = exc.field
            if field == req.source or field.startswith(req.source + ":"):
                field = "log.text" + field[len(req.source):]
            raise request_error(InputError(field, exc.problem, exc.allowed)) from None
        return LedgerIngestResponse(**asdict(report), line=report.line())

    @app.get("/v1/ledger/joints", response_model=LedgerJointsResponse, responses=errs)
    def ledger_joints(units: str = Query("si", description="si or field: lengths (m or ft) "
                                         "and diameters (mm or in) in column names")
                      ) -> LedgerJointsResponse:
        u = units_of(units)
        table = in_units(inventory(served()), u, "units")
        return LedgerJointsResponse(units=u, columns=[str(c) for c in table.columns],
                                    rows=_rows(table))

    @app.get("/v1/ledger/joints/{serial}", response_model=JointHistoryResponse,
             responses={**errs, **unknown})
    def ledger_history(serial: str, units: str = Query("si", description="si or field")
                       ) -> JointHistoryResponse:
        u = units_of(units)
        try:
            h = history(served(), serial)
        except NotInLedger as exc:
            raise NotFound("serial", exc.problem, _request_names(exc.allowed)) from None
        return JointHistoryResponse(serial=h.serial, component_type=h.component_type, units=u,
                                    runs=_table(in_units(h.runs, u, "units")),
                                    events=_table(h.events),
                                    inspections=_table(in_units(h.inspections, u, "units")))

    @app.get("/v1/ledger/retire", response_model=LedgerRetireResponse, responses=errs)
    def ledger_retire(
            retire_at: float = Query(_DEFAULT_RULES.retire_at, description="retire when the "
                                     "damage reaches this fraction"),
            inspect_at: float = Query(_DEFAULT_RULES.inspect_at, description="inspect when the "
                                      "upper bound of damage reaches this fraction"),
            reinspect_after: float = Query(_DEFAULT_RULES.reinspect_after, description="inspect "
                                           "again once the upper bound grew this much since "
                                           "the last inspection"),
            downgraded_retire_at: float = Query(_DEFAULT_RULES.downgraded_retire_at,
                                                description="retire_at for a joint last "
                                                "inspected as RP 7G-2 class 2 or 3"),
            units: str = Query("si", description="si or field")) -> LedgerRetireResponse:
        u = units_of(units)
        try:
            rules = RetireRules(retire_at=retire_at, inspect_at=inspect_at,
                                reinspect_after=reinspect_after,
                                downgraded_retire_at=downgraded_retire_at)
        except InputError as exc:
            raise request_error(exc) from None
        lists = in_units(retire_lists(served(), rules), u, "units")
        return LedgerRetireResponse(
            rules=RetireRulesOut(**{**asdict(rules),
                                    "retire_results": list(rules.retire_results)}),
            units=u, columns=[str(c) for c in lists.columns],
            retire=_rows(lists[lists["action"] == "retire"]),
            inspect=_rows(lists[lists["action"] == "inspect"]))
