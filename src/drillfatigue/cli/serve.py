"""``drillfatigue serve`` and ``drillfatigue window``: the twin as a service, the window map.

::

    drillfatigue serve --model data/surrogate/model [--model other=PATH] [--port 8000] \
        [--ledger ledger.sqlite]
    drillfatigue window --model data/surrogate/model --x rpm=60:180:25 --y wob_kN=30:120:19 \\
        --set md_m=1500 --set s_from_bit_m=8 --set component_type=collar ... --out map.png

``serve`` loads every model once, answers on ``http://HOST:PORT/`` (web page)
and ``/v1/...`` (API, schema at ``/openapi.json``); SIGHUP or
``POST /v1/model/reload`` reloads the models from their folders without
dropping requests. ``--ledger`` opens a fatigue ledger (SQLite file or
PostgreSQL URL) for the ``/v1/ledger`` endpoints and the page's inventory;
a server may run with a ledger and no model. ``window`` writes the operating-window map
(:mod:`drillfatigue.surrogate.window`) as a PNG and, with ``--csv``, the grid.
"""

from __future__ import annotations

import signal
import threading
from pathlib import Path

import typer

from drillfatigue.cli.app import app
from drillfatigue.cli.twin import _read_csv, parse_settings
from drillfatigue.errors import InputError
from drillfatigue.files import atomic_output, check_output_file


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


@app.command("window")
def window(model: Path = typer.Option(..., "--model", help="surrogate model folder"),
           x: str = typer.Option("rpm", "--x", help="x axis NAME=START:STOP:NODES, or NAME "
                                 "alone: 31 nodes over the model's domain"),
           y: str = typer.Option("wob_kN", "--y", help="y axis NAME=START:STOP:NODES, or NAME "
                                 "alone: 31 nodes over the model's domain (wob_kN, ...)"),
           settings: list[str] = typer.Option([], "--set", help="fixed input NAME=VALUE, user "
                                              "units (md_m, s_from_bit_m, component_type, ...)"),
           survey: Path | None = typer.Option(None, "--survey", help="survey CSV (md_m, "
                                              "dls_deg_per_30m, inc_deg): hole geometry at "
                                              "md_m and the bit"),
           out: Path = typer.Option(..., "--out", help="PNG file to write"),
           csv: Path | None = typer.Option(None, "--csv", help="also write the grid as CSV"),
           title: str | None = typer.Option(None, "--title", help="figure title")) -> None:
    """Operating-window map: predicted life over rpm x WOB (or x ROP), OOD cells hatched."""
    # optional extra [surrogate]: torch
    from drillfatigue.surrogate import Surrogate
    from drillfatigue.surrogate.window import Axis, operating_window, plot_window

    if out.suffix.lower() != ".png":
        raise InputError("--out", f"{str(out)!r} is not a .png file", "FILE.png")
    if out.is_dir():
        raise InputError("--out", f"{str(out)!r} is a folder", "FILE.png")
    if csv is not None and (csv.suffix.lower() != ".csv" or csv.is_dir()):
        raise InputError("--csv", f"{str(csv)!r} is not a .csv file", "FILE.csv")
    inputs = [("--model", model), ("--survey", survey)]
    check_output_file(out, "--out", inputs)
    if csv is not None:
        check_output_file(csv, "--csv", [*inputs, ("--out", out)])
    fixed = parse_settings(list(settings))
    survey_t = _read_csv(survey, "--survey") if survey is not None else None
    if not (model / "metadata.json").is_file():
        raise InputError("--model", f"{str(model)!r} is not a surrogate model folder",
                         "a folder written by the train stage")
    sur = Surrogate.load(model)
    ax_x, ax_y = (Axis.parse(spec, opt) if "=" in spec
                  else Axis.in_domain(spec.strip().replace("-", "_"), sur, field=opt)
                  for spec, opt in ((x, "--x"), (y, "--y")))
    wmap = operating_window(sur, ax_x, ax_y, fixed, survey_t)
    plot_window(wmap, out, title)
    if csv is not None:
        with atomic_output(csv) as tmp:
            wmap.to_frame().to_csv(tmp, index=False)
    best = wmap.best_in_domain()
    print(f"wrote {out}" + (f" and {csv}" if csv is not None else "")
          + f"; {100 * wmap.ood.mean():.0f} % of the grid out of domain")
    if best is not None:
        print(f"longest life in domain: {best[ax_x.name]:.4g} {ax_x.name}, "
              f"{best[ax_y.name]:.4g} {ax_y.name}: {best['life_h']:.3g} h "
              f"(lower bound {best['life_h_lower']:.3g} h)")
