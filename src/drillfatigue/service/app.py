"""The FastAPI application of ``drillfatigue serve``.

Endpoints (OpenAPI schema at ``/openapi.json``, interactive docs at ``/docs``):

=============================  ===========================================================
``GET  /healthz``              liveness: status and the generation of each model
``GET  /v1/models``            the loaded models
``GET  /v1/model``             a model's card: features, domain ranges, training, metrics
``POST /v1/model/reload``      reload a model (or all) from its folder, swapped atomically
``POST /v1/query``             conditions -> damage rate, life, interval, OOD flag
``POST /v1/twin/replay``       operating log + string -> damage per component, retire list
``POST /v1/plan/rank``         candidate well plans -> ranking by the critical life
``POST /v1/window``            operating-window map: life over a grid of two parameters
``POST /v1/window.png``        the same map as a PNG, out-of-domain cells hatched
``/v1/ledger/...``             the fatigue ledger (:mod:`drillfatigue.service.ledger`)
``GET  /``                     the web page (static files under ``/static``)
``GET  /docs``                 interactive API documentation (Swagger UI, shipped)
=============================  ===========================================================

A server runs with models, a ledger (``--ledger``) or both; an endpoint of a
part it was not started with answers 503. Every refused request is answered
with a JSON body whose ``detail`` is one line ``field: problem (allowed:
...)``: 422 for invalid content, 413 for a body over the size limit, 404 for
an unknown path or serial, 503 for a part not served. An unexpected failure
is a 500 whose ``detail`` names the exception type only; the traceback goes
to the server log, never to the client.
"""

from __future__ import annotations

import json
import logging
import math
from collections.abc import Callable
from dataclasses import asdict, dataclass
from importlib import resources
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
import pandas as pd
import yaml
from fastapi import FastAPI
from fastapi.exceptions import RequestValidationError
from fastapi.openapi.docs import get_swagger_ui_html
from fastapi.responses import FileResponse, HTMLResponse, JSONResponse, Response
from fastapi.staticfiles import StaticFiles
from starlette.exceptions import HTTPException
from starlette.requests import Request as StarletteRequest
from starlette.types import ASGIApp, Message, Receive, Scope, Send

from drillfatigue import __version__
from drillfatigue.config.base import input_error_from_error, validate
from drillfatigue.errors import InputError
from drillfatigue.io.examples import field_example
from drillfatigue.io.logs import log_bit_md_m
from drillfatigue.io.tally import load_tally_text
from drillfatigue.service.errors import NotServed, ServiceRefusal
from drillfatigue.service.ledger import add_ledger_routes
from drillfatigue.service.logs import log_formats, read_csv_table, read_log
from drillfatigue.service.registry import LoadedModel, ModelRegistry
from drillfatigue.service.rows import predict_rows
from drillfatigue.service.schemas import (
    AxisValues,
    ErrorResponse,
    ExampleResponse,
    FeatureInfo,
    HealthResponse,
    ModelCard,
    ModelsResponse,
    ModelSummary,
    PlanRankRequest,
    PlanRankResponse,
    QueryRequest,
    QueryResponse,
    ReloadRequest,
    ReloadResponse,
    ReplayRequest,
    ReplayResponse,
    RetireEntry,
    WindowRequest,
    WindowResponse,
)
from drillfatigue.studies.plan import CandidateFile, check_end_points, predict_candidates
from drillfatigue.surrogate.twin import (
    components_from_string,
    components_from_table,
    replay_log,
    replay_summary,
    retire_list,
    survey_from_well,
)
from drillfatigue.surrogate.window import Axis, WindowMap, operating_window, window_png

if TYPE_CHECKING:
    from drillfatigue.ledger import Ledger

log = logging.getLogger("drillfatigue.service")


@dataclass(frozen=True)
class Limits:
    """Size limits of one request (bigger ones are refused, never truncated)."""

    max_body_bytes: int = 16 * 1024 * 1024
    max_query_rows: int = 10_000
    max_log_rows: int = 200_000
    max_components: int = 5_000
    max_window_nodes: int = 40_000
    max_candidates: int = 50


def _one_line(exc: InputError, status: int = 422) -> JSONResponse:
    body = ErrorResponse(detail=exc.one_line(), field=exc.field, problem=exc.problem,
                         allowed=exc.allowed)
    return JSONResponse(status_code=status, content=body.model_dump())


#: what a value of a pydantic error type's family may be
_ALLOWED_BY_TYPE = {"float": "a number", "int": "an integer", "string": "text",
                    "bool": "true or false", "dict": "a JSON object", "list": "a JSON array",
                    "missing": "the key with a value (schema: /openapi.json)",
                    "union": "a number or text", "finite": "a finite number"}


def _validation_error(exc: RequestValidationError) -> InputError:
    """The first pydantic error of a request as an InputError (field path without 'body')."""
    err = dict(exc.errors()[0])
    loc = tuple(err.get("loc", ()))
    if loc and loc[0] in ("body", "query", "path"):
        loc = loc[1:]
    if err.get("type") == "json_invalid":
        reason = (err.get("ctx") or {}).get("error", "JSON decode error")
        return InputError("body", f"invalid JSON ({reason})", "a JSON object")
    if not loc and err.get("type") in ("missing", "model_attributes_type", "dict_type"):
        return InputError("body", "missing or not a JSON object", "a JSON object")
    union_branch = False
    while loc and loc[-1] in ("float", "str"):  # a feature value (float | str) of any other type
        loc = loc[:-1]
        union_branch = True
    err["loc"] = loc
    exc1 = input_error_from_error(err)
    if isinstance(err.get("input"), bool):  # schemas.Value / Number: true is not rpm 1
        return InputError(exc1.field, f"{json.dumps(err['input'])} is a JSON boolean, not a "
                          "number", "a number")
    if union_branch:
        return InputError(exc1.field, f"got {err.get('input')!r}", "a number or text")
    if exc1.allowed is None:
        kind = str(err.get("type", "")).split("_")[0]
        allowed = _ALLOWED_BY_TYPE.get(kind, "the request schema at /openapi.json")
        return InputError(exc1.field, exc1.problem, allowed)
    return exc1


class _Guard:
    """ASGI wrapper: refuses bodies over the size limit (413) and turns any
    unexpected exception into a one-line 500 (traceback to the log only)."""

    def __init__(self, app: ASGIApp, max_body_bytes: int) -> None:
        self.app = app
        self.max_body_bytes = max_body_bytes

    async def _send_json(self, send: Send, status: int, detail: str, field: str) -> None:
        body = json.dumps({"detail": detail, "field": field}).encode()
        await send({"type": "http.response.start", "status": status,
                    "headers": [(b"content-type", b"application/json"),
                                (b"content-length", str(len(body)).encode())]})
        await send({"type": "http.response.body", "body": body})

    async def __call__(self, scope: Scope, receive: Receive, send: Send) -> None:
        if scope["type"] != "http":
            await self.app(scope, receive, send)
            return
        limit = self.max_body_bytes
        too_big = f"body: over the size limit (allowed: at most {limit} bytes)"
        for key, value in scope.get("headers", []):
            if key == b"content-length":
                try:
                    n = int(value)
                except ValueError:
                    n = -1
                if n < 0 or n > limit:
                    await self._send_json(send, 413, too_big, "body")
                    return
        seen = 0
        started = False

        async def counted_receive() -> Message:
            nonlocal seen
            msg = await receive()
            if msg["type"] == "http.request":
                seen += len(msg.get("body", b""))
                if seen > limit:
                    raise HTTPException(413, too_big)
            return msg

        async def tracked_send(msg: Message) -> None:
            nonlocal started
            if msg["type"] == "http.response.start":
                started = True
            await send(msg)

        try:
            await self.app(scope, counted_receive, tracked_send)
        except Exception as exc:  # the last line of defence: no traceback to the client
            log.exception("unexpected error on %s %s", scope.get("method"), scope.get("path"))
            if not started:
                await self._send_json(send, 500, f"internal error ({type(exc).__name__}); "
                                      "the server log has the details", "server")


def _cell(v: Any) -> Any:
    """A JSON-safe cell: numpy scalars to Python, NaN and infinities to None."""
    if isinstance(v, np.generic):
        v = v.item()
    if isinstance(v, float) and not math.isfinite(v):
        return None
    return v


def _records(frame: pd.DataFrame) -> list[dict[str, Any]]:
    cols = [str(c) for c in frame.columns]
    return [{c: _cell(v) for c, v in zip(cols, row, strict=True)}
            for row in frame.itertuples(index=False, name=None)]


def _grid(a: np.ndarray) -> list[list[float | None]]:
    return [[_cell(float(v)) for v in row] for row in a]


def _answer(lm: LoadedModel) -> dict[str, Any]:
    sur = lm.surrogate
    return {"model": lm.name, "generation": lm.generation,
            "criterion": str(sur.metadata.get("criterion", "")), "coverage": sur.coverage}


def _prefixed(exc: InputError, prefix: str) -> InputError:
    return InputError(f"{prefix}.{exc.field}", exc.problem, exc.allowed)


def _table(rows: list[dict[str, Any]], field: str) -> pd.DataFrame:
    table = pd.DataFrame.from_records(rows)
    if table.isna().any().any():
        col = str(table.columns[table.isna().any()][0])
        raise InputError(f"{field}.{col}", "missing in some rows", "the same names in every row")
    return table


def _survey_table(rows: list[dict[str, float]] | None, field: str) -> pd.DataFrame | None:
    if rows is None:
        return None
    return _table(rows, field)


def model_card(lm: LoadedModel, limits: Limits) -> ModelCard:
    """The card of a loaded model (see :class:`ModelCard`)."""
    sur = lm.surrogate
    meta = sur.metadata
    dom = sur.domain
    features = [FeatureInfo(column=c, names=lm.vocab.names_for(c), min=float(dom.min_[j]),
                            max=float(dom.max_[j])) for j, c in enumerate(sur.features)]
    cats = [FeatureInfo(column=c, names=lm.vocab.names_for(c), levels=list(levels))
            for c, levels in sur.categories.items()]
    split = {k: len(v) for k, v in (meta.get("split") or {}).items()}
    metrics = None
    for candidate in (lm.path / "metrics.json", lm.path.parent / "metrics.json"):
        if candidate.is_file():
            try:
                metrics = json.loads(candidate.read_text(encoding="utf-8"))
            except (ValueError, UnicodeDecodeError):
                metrics = None
            break
    return ModelCard(**_answer(lm), path=str(lm.path), loaded_at_utc=lm.loaded_at_utc,
                     target=str(meta.get("target", "")),
                     n_calibration=meta.get("n_calibration"), features=features,
                     categorical=cats, training=dict(meta.get("training") or {}), split=split,
                     architecture=dict(meta.get("architecture") or {}), metrics=metrics,
                     log_formats=log_formats(), limits=asdict(limits))


def _summary(lm: LoadedModel) -> ModelSummary:
    return ModelSummary(name=lm.name, generation=lm.generation,
                        criterion=str(lm.surrogate.metadata.get("criterion", "")),
                        loaded_at_utc=lm.loaded_at_utc)


def _window(registry: ModelRegistry, req: WindowRequest, limits: Limits
            ) -> tuple[LoadedModel, WindowMap]:
    lm = registry.get(req.model)
    x = Axis.linear(req.x.name, req.x.start, req.x.stop, req.x.n, "x")
    y = Axis.linear(req.y.name, req.y.start, req.y.stop, req.y.n, "y")
    try:
        wmap = operating_window(lm.surrogate, x, y, req.fixed,
                                _survey_table(req.survey, "survey"),
                                max_nodes=limits.max_window_nodes)
    except InputError as exc:
        if exc.field.split(".")[0] in ("x", "y", "grid", "survey"):
            raise
        raise _prefixed(exc, "fixed") from None
    return lm, wmap


def _candidates(req: PlanRankRequest, limits: Limits) -> CandidateFile:
    if (req.candidates is None) == (req.candidates_yaml is None):
        raise InputError("candidates", "give exactly one of candidates and candidates_yaml",
                         "a candidates object or its YAML text")
    if req.candidates is not None:
        cset = req.candidates
    else:
        try:
            data = yaml.safe_load(req.candidates_yaml or "")
        except yaml.YAMLError as exc:
            mark = getattr(exc, "problem_mark", None)
            where = f" at line {mark.line + 1}, column {mark.column + 1}" if mark else ""
            raise InputError("candidates_yaml", f"YAML syntax error{where}",
                             "a candidates file's YAML text") from None
        if not isinstance(data, dict):
            raise InputError("candidates_yaml", "top level is not a mapping",
                             "a candidates file's YAML text")
        cset = validate(CandidateFile, data, "candidates")
    if len(cset.candidates) > limits.max_candidates:
        raise InputError("candidates.candidates", f"{len(cset.candidates)} candidates",
                         f"at most {limits.max_candidates}")
    check_end_points(cset)
    return cset


#: Error answers the model and ledger endpoints document.
ERRORS: dict[int | str, dict[str, Any]] = {
    422: {"model": ErrorResponse, "description": "invalid request, one line"},
    413: {"model": ErrorResponse, "description": "body over the size limit"},
    503: {"model": ErrorResponse, "description": "the server was started without the "
          "model or the ledger this needs"}}


def create_app(registry: ModelRegistry | None, limits: Limits | None = None,
               ledger: Ledger | None = None) -> FastAPI:
    """The service answering with the models of ``registry`` and from ``ledger``.

    Parameters
    ----------
    registry : ModelRegistry or None
        Loaded models; reloads swap its entries. None: the model endpoints
        answer 503 (a server for a ledger alone).
    limits : Limits, optional
        Request size limits (defaults: :class:`Limits`).
    ledger : Ledger, optional
        An open ledger (:func:`drillfatigue.ledger.open_ledger`) for the
        ``/v1/ledger`` endpoints; None: they answer 503.
    """
    lim = limits or Limits()
    app = FastAPI(title="drillfatigue digital twin", version=__version__,
                  description="Fatigue damage of a drill string from the surrogate: "
                  "queries, operating-log replay, operating-window maps, well-plan ranking; "
                  "the fatigue ledger of every joint by serial.",
                  docs_url=None, redoc_url=None)
    app.state.registry = registry
    app.state.limits = lim
    app.state.ledger = ledger

    def models() -> ModelRegistry:
        if registry is None:
            raise NotServed("model", "this server loaded no model",
                            "start it with drillfatigue serve --model FOLDER")
        return registry

    _add_error_handlers(app)

    @app.get("/healthz", response_model=HealthResponse)
    def healthz() -> HealthResponse:
        return HealthResponse(status="ok",
                              models={} if registry is None else
                              {m.name: m.generation for m in registry.all()},
                              ledger=None if ledger is None else ledger.dialect)

    _add_model_routes(app, models, lim)
    _add_twin_routes(app, models, lim)
    add_ledger_routes(app, ledger, lim.max_log_rows, ERRORS)
    _add_pages(app)
    app.add_middleware(_Guard, max_body_bytes=lim.max_body_bytes)
    return app


def _add_error_handlers(app: FastAPI) -> None:
    """Every refusal as one JSON line: bad input 422, a refusal its status, 404 naming the path."""

    @app.exception_handler(InputError)
    async def _input_error(request: StarletteRequest, exc: InputError) -> JSONResponse:
        return _one_line(exc)

    @app.exception_handler(ServiceRefusal)
    async def _refusal(request: StarletteRequest, exc: ServiceRefusal) -> JSONResponse:
        body = ErrorResponse(detail=exc.one_line(), field=exc.field, problem=exc.problem,
                             allowed=exc.allowed)
        return JSONResponse(status_code=exc.status, content=body.model_dump())

    @app.exception_handler(RequestValidationError)
    async def _invalid(request: StarletteRequest, exc: RequestValidationError) -> JSONResponse:
        return _one_line(_validation_error(exc))

    @app.exception_handler(HTTPException)
    async def _http(request: StarletteRequest, exc: HTTPException) -> JSONResponse:
        detail = exc.detail if isinstance(exc.detail, str) else json.dumps(exc.detail)
        if exc.status_code == 404:
            detail = f"{request.url.path}: not found (allowed: the paths of /openapi.json)"
        return JSONResponse(status_code=exc.status_code,
                            content={"detail": " ".join(detail.split())},
                            headers=getattr(exc, "headers", None))


def _add_model_routes(app: FastAPI, models: Callable[[], ModelRegistry], lim: Limits) -> None:
    """The model endpoints: list, card, reload, query, and the field example."""

    @app.get("/v1/models", response_model=ModelsResponse, responses=ERRORS)
    def models_list() -> ModelsResponse:
        reg = models()
        return ModelsResponse(default=reg.default, models=[_summary(m) for m in reg.all()])

    @app.get("/v1/model", response_model=ModelCard, responses=ERRORS)
    def model(name: str | None = None) -> ModelCard:
        return model_card(models().get(name, "name"), lim)

    @app.post("/v1/model/reload", response_model=ReloadResponse, responses=ERRORS)
    def reload(req: ReloadRequest | None = None) -> ReloadResponse:
        fresh = models().reload(req.model if req is not None else None)
        log.info("reloaded %s", ", ".join(f"{m.name} (generation {m.generation})"
                                          for m in fresh))
        return ReloadResponse(reloaded=[_summary(m) for m in fresh])

    @app.post("/v1/query", response_model=QueryResponse, responses=ERRORS)
    def query(req: QueryRequest) -> QueryResponse:
        lm = models().get(req.model)
        if len(req.rows) > lim.max_query_rows:
            raise InputError("rows", f"{len(req.rows)} rows", f"at most {lim.max_query_rows}")
        columns, rows = predict_rows(lm, req.rows)
        return QueryResponse(**_answer(lm), columns=columns, rows=rows)

    @app.get("/v1/example", response_model=ExampleResponse)
    def example() -> ExampleResponse:
        """The field example (data/examples/field): the rig day's LAS log, the tally and
        the survey (SI rows), as a replay request takes them."""
        return ExampleResponse(**field_example())


def _add_twin_routes(app: FastAPI, models: Callable[[], ModelRegistry], lim: Limits) -> None:
    """The endpoints that answer from a model: log replay, plan ranking, window maps."""

    @app.post("/v1/twin/replay", response_model=ReplayResponse, responses=ERRORS)
    def twin_replay(req: ReplayRequest) -> ReplayResponse:
        lm = models().get(req.model)
        log_t = read_log(req.log.format, req.log.text.encode("utf-8"))
        if len(log_t) > lim.max_log_rows:
            raise InputError("log.text", f"{len(log_t)} rows", f"at most {lim.max_log_rows}")
        comp_t = _replay_components(req, lim)
        if req.survey is not None and req.well is not None:
            raise InputError("well", "given together with survey", "at most one of them")
        survey_t = (survey_from_well(req.well) if req.well is not None
                    else _survey_table(req.survey, "survey"))
        res = replay_log(log_t, comp_t, lm.surrogate, req.constants, survey_t)
        c = res.components
        retire = [RetireEntry(**{k: _cell(v) if isinstance(v, float) else v
                                 for k, v in e.items()})
                  for e in retire_list(res, req.retire_at_damage, req.retire_within_h)]
        return ReplayResponse(**_answer(lm), **replay_summary(res),
                              last_bit_md_m=float(log_bit_md_m(log_t)[-1]),
                              columns=[str(k) for k in c.columns], components=_records(c),
                              retire=retire)

    @app.post("/v1/plan/rank", response_model=PlanRankResponse, responses=ERRORS)
    def plan_rank(req: PlanRankRequest) -> PlanRankResponse:
        lm = models().get(req.model)
        cset = _candidates(req, lim)
        table = predict_candidates(cset, lm.surrogate)
        table = table.sort_values("life_windows_surrogate", ascending=False, kind="stable")
        table.insert(0, "rank_surrogate", np.arange(1, len(table) + 1))
        table = table.reset_index(drop=True)
        return PlanRankResponse(**_answer(lm), best=str(table["candidate"].iloc[0]),
                                window_s=float(cset.window.window_s),
                                columns=[str(k) for k in table.columns], rows=_records(table))

    @app.post("/v1/window", response_model=WindowResponse, responses=ERRORS)
    def window(req: WindowRequest) -> WindowResponse:
        lm, wmap = _window(models(), req, lim)
        return WindowResponse(**_answer(lm),
                              x=AxisValues(name=wmap.x.name, values=wmap.x.values.tolist()),
                              y=AxisValues(name=wmap.y.name, values=wmap.y.values.tolist()),
                              life_h=_grid(wmap.life_h), life_h_lower=_grid(wmap.life_h_lower),
                              life_h_upper=_grid(wmap.life_h_upper),
                              ood=wmap.ood.tolist(), ood_fraction=float(wmap.ood.mean()),
                              best_in_domain=wmap.best_in_domain(),
                              fixed={k: _cell(v) for k, v in wmap.fixed.items()})

    @app.post("/v1/window.png", response_class=Response, responses={
        **ERRORS, 200: {"content": {"image/png": {}}, "description": "the map as PNG"}})
    def window_image(req: WindowRequest) -> Response:
        _, wmap = _window(models(), req, lim)
        return Response(content=window_png(wmap), media_type="image/png")


def _replay_components(req: ReplayRequest, lim: Limits) -> pd.DataFrame:
    """The component table of a replay request, from exactly one of its four forms."""
    given = [k for k in ("components", "components_csv", "string", "tally_csv")
             if getattr(req, k) is not None]
    if len(given) != 1:
        raise InputError("components", f"given {len(given)} of components, "
                         "components_csv, string, tally_csv", "exactly one of them")
    if req.string is not None:
        comp_t = components_from_string(req.string)
    elif req.tally_csv is not None:
        try:
            tally = load_tally_text(req.tally_csv, "tally_csv")
        except InputError as exc:
            raise _prefixed(exc, "tally_csv") from None
        comp_t = components_from_string(tally.string, kinds=tally.kinds)
    elif req.components is not None:
        comp_t = _table(req.components, "components")
    else:
        try:
            comp_t = read_csv_table((req.components_csv or "").encode("utf-8"),
                                    "component list")
        except InputError as exc:
            raise _prefixed(exc, "components_csv") from None
    if len(comp_t) == 0 or len(comp_t) > lim.max_components:
        raise InputError(given[0], f"{len(comp_t)} components",
                         f"1 to {lim.max_components}")
    try:
        components_from_table(comp_t)
    except InputError as exc:
        raise _prefixed(exc, given[0]) from None
    return comp_t


def _add_pages(app: FastAPI) -> None:
    """The web page, the API docs page (Swagger UI from the package) and its static files."""
    static = Path(str(resources.files("drillfatigue.service") / "static"))

    @app.get("/", include_in_schema=False)
    def index() -> FileResponse:
        return FileResponse(static / "index.html", media_type="text/html")

    @app.get("/docs", include_in_schema=False)
    def docs() -> HTMLResponse:
        # Swagger UI from the package (FastAPI's default page loads it from a CDN)
        return get_swagger_ui_html(openapi_url="/openapi.json",
                                   title="drillfatigue digital twin: API",
                                   swagger_js_url="/static/vendor/swagger-ui-bundle.js",
                                   swagger_css_url="/static/vendor/swagger-ui.css",
                                   swagger_favicon_url="data:,")

    app.mount("/static", StaticFiles(directory=static), name="static")

