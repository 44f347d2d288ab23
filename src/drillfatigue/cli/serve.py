"""``drillfatigue serve``: the digital twin as a service.

::

    drillfatigue serve --model data/surrogate/model [--model other=PATH] [--port 8000] \
        [--ledger ledger.sqlite]

``serve`` loads every model once, answers on ``http://HOST:PORT/`` (web page)
and ``/v1/...`` (API, schema at ``/openapi.json``); SIGHUP or
``POST /v1/model/reload`` reloads the models from their folders without
dropping requests. ``--ledger`` opens a fatigue ledger (SQLite file or
PostgreSQL URL) for the ``/v1/ledger`` endpoints and the page's inventory;
a server may run with a ledger and no model.
"""

from __future__ import annotations

import signal
import threading
import typer

from drillfatigue.cli.app import app
from drillfatigue.errors import InputError


@app.command("serve")
def serve(model: list[str] = typer.Option([], "--model", help="model folder, or NAME=FOLDER; "
                                          "repeat for several (the first is the default)"),
          ledger: str | None = typer.Option(None, "--ledger", help="fatigue ledger to serve: "
                                            "SQLite file or postgresql+psycopg://USER@HOST/DB"),
          host: str = typer.Option("127.0.0.1", "--host", help="address to listen on"),
          port: int = typer.Option(8000, "--port", help="TCP port"),
          max_body_mb: float = typer.Option(16.0, "--max-body-mb",
                                            help="largest request body (MiB)"),
          max_query_rows: int = typer.Option(10_000, "--max-query-rows",
                                             help="most rows of one /v1/query"),
          torch_threads: int = typer.Option(1, "--torch-threads",
                                            help="torch threads per request (concurrent "
                                            "requests already run in parallel)")) -> None:
    """Serve the HTTP API and the web page of the digital twin.

    Requests are answered concurrently by a thread pool; torch runs each
    request's network on ``--torch-threads`` threads (default 1): the
    parallelism comes from concurrent requests, and intra-op threads that
    wait for each other at every operator make single queries several times
    slower on a busy machine. Served latency and throughput:
    ``benchmarks/results/service.json``.
    """
    if not 0 < port < 65536:
        raise InputError("--port", f"got {port}", "1 <= port <= 65535")
    if not 0.001 <= max_body_mb <= 1024:
        raise InputError("--max-body-mb", f"got {max_body_mb:g}", "0.001 to 1024")
    if not 1 <= max_query_rows <= 10_000_000:
        raise InputError("--max-query-rows", f"got {max_query_rows}", "1 to 10000000")
    if not 1 <= torch_threads <= 256:
        raise InputError("--torch-threads", f"got {torch_threads}", "1 to 256")
    if not model and ledger is None:
        raise InputError("--model", "no model and no ledger to serve",
                         "--model FOLDER, --ledger PATH_OR_URL, or both")
    try:  # optional extra [service]: uvicorn, FastAPI (and torch through the surrogate)
        import uvicorn

        from drillfatigue.service import Limits, ModelRegistry, create_app, parse_model_spec
    except ImportError as exc:
        raise InputError("serve", f"missing package {exc.name!r}",
                         "pip install 'drillfatigue[service]'") from None
    specs = dict(parse_model_spec(s) for s in model)
    if len(specs) != len(model):
        raise InputError("--model", "two models with the same name", "distinct NAME=FOLDER")
    led = None
    if ledger is not None:
        # optional extra [ledger]: SQLAlchemy, Alembic, psycopg
        from drillfatigue.ledger import open_ledger

        try:
            led = open_ledger(ledger)
        except InputError as exc:
            raise InputError("--ledger", exc.problem, exc.allowed) from None
    registry = None
    if specs:
        import torch  # optional extra [surrogate]

        torch.set_num_threads(torch_threads)
        registry = ModelRegistry(specs)
    limits = Limits(max_body_bytes=int(max_body_mb * 1024 * 1024),
                    max_query_rows=max_query_rows)
    server_app = create_app(registry, limits, ledger=led)

    def on_hup(signum: int, frame: object) -> None:
        if registry is None:
            return
        def work() -> None:
            try:
                registry.reload()
                print("reloaded every model", flush=True)
            except Exception as exc:  # keep serving the old models; say why
                print(f"reload failed, old models kept: {exc}", flush=True)
        threading.Thread(target=work, daemon=True).start()

    if hasattr(signal, "SIGHUP"):
        signal.signal(signal.SIGHUP, on_hup)
    parts = [] if registry is None else [", ".join(registry.names)]
    if led is not None:
        parts.append(f"the ledger {led.shown_name()}")
    print(f"serving {' and '.join(parts)} on http://{host}:{port}/", flush=True)
    try:
        uvicorn.run(server_app, host=host, port=port, log_level="warning")
    finally:
        if led is not None:
            led.dispose()
