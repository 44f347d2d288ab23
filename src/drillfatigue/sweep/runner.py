"""Parallel, resumable sweep engine: run a case function over many cases.

One code path for every scheduler: cases are submitted to a
``concurrent.futures``-compatible executor, at most a few per worker at a
time, and results are collected as they complete.

* ``serial``: in this process (debugging, tiny sweeps).
* ``processes``: ``concurrent.futures.ProcessPoolExecutor`` with the
  ``forkserver`` start method (no fork of a process holding threads).
* ``local-cluster``: Dask ``LocalCluster(processes=True, threads_per_worker=1)``
  through ``Client.get_executor(pure=False)``.
* ``tcp://host:port``: an existing Dask scheduler, same executor interface.

Workers receive the case function by reference (a plain module-level function
of an importable module, pickled by name), never a jitted object.

numba cache: before any worker starts, the warm-up hook (``case_fn.warmup``
or else the module's ``warmup``) is called once in this process with the
inputs of the first case to run (so it compiles the kernels that case's
options select, e.g. on a shortened copy of it). numba's on-disk cache
(``NUMBA_CACHE_DIR`` or ``__pycache__``, shared with local workers) is then
complete and workers only read it: concurrent cache writes can crash. On a
remote Dask cluster each worker first calls
:func:`drillfatigue.numba_cache.scope_numba_cache`, then the hook runs on one
worker at a time for the same reason. ``serial`` needs no warm-up.

Resume: each case runs in ``out_root/.tmp/<id>.<pid>.<attempt>.<rand>/``; when
the case function returns, a ``DONE`` marker holding the case id and the
SHA-256 of the case inputs and of the package source is written and the folder is renamed atomically to
``out_root/<case_id>/``. A case whose marker matches is skipped, so a killed
sweep rerun finishes only what is missing; leftovers in ``.tmp`` are removed
at start. Ctrl-C cancels queued cases and leaves finished ones in place.

The sweep folder carries the ``sweep`` ownership marker
(:class:`drillfatigue.files.OutputFolder`): a folder holding anything else is
refused before any case runs. A sweep folder written without a marker (it
holds ``sweep.json``) is adopted.

Failures: an exception in the case function (or a worker process dying) is
one failed attempt; a case is retried up to ``max_retries`` times. Every case
that failed at least once in a run is appended to ``out_root/failures.parquet``
(error type and text, traceback tail, attempts, ``final`` = still failed at the
end of that run, ``run`` = the number of the sweep run in this folder and
``time_utc`` = when it was recorded); earlier runs' rows are kept, so a worker
that died in a run is not forgotten when a rerun succeeds. The failures of a
run are also printed on stderr.
If the fraction of finally failed cases exceeds ``failure_threshold`` the
sweep raises :class:`SweepFailedError` (the CLI exits with code 1). When a
local worker process dies, every case in flight on that pool is charged one
attempt (the pool cannot tell which one crashed it).
"""

from __future__ import annotations

import contextlib
import functools
import importlib
import json
import logging
import multiprocessing
import os
import shutil
import socket
import sys
import time
import traceback
import uuid
from collections import deque
from collections.abc import Callable, Iterable, Iterator, Mapping, Sequence
from concurrent.futures import FIRST_COMPLETED, Executor, Future, ProcessPoolExecutor, wait
from concurrent.futures.process import BrokenProcessPool
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any

import pandas as pd
from rich.console import Console
from rich.progress import (BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeElapsedColumn,
                           TimeRemainingColumn)

import drillfatigue
from drillfatigue.errors import InputError
from drillfatigue.files import MARKER, OutputFolder, atomic_output, atomic_write_json, atomic_write_text
from drillfatigue.numba_cache import scope_numba_cache
from drillfatigue.sweep.design import inputs_sha256

__all__ = [
    "DONE_NAME",
    "FAILURES_NAME",
    "Case",
    "SweepFailedError",
    "SweepReport",
    "cases_from_frame",
    "claim_sweep_folder",
    "execute_case",
    "is_done",
    "latest_failures",
    "read_failures",
    "run_sweep",
]

DONE_NAME = "DONE"
TMP_NAME = ".tmp"
FAILURES_NAME = "failures.parquet"
REPORT_NAME = "sweep.json"
TAIL_CHARS = 2000
FAILURE_COLUMNS = ["case_id", "attempts", "final", "error_type", "error", "traceback_tail",
                   "worker", "inputs_json", "run", "time_utc"]
#: Kind of the ownership marker of a sweep folder.
SWEEP_KIND = "sweep"
#: Failure lines printed on stderr at the end of a run before "... and N more".
PRINT_FAILURES = 10

CaseFn = Callable[[dict[str, Any], Path], Any]


class SweepFailedError(RuntimeError):
    """Too many cases failed; the message gives counts and where the errors are."""


@dataclass(frozen=True)
class Case:
    """One unit of work: an id and the JSON-ready inputs given to the case function."""

    case_id: str
    inputs: dict[str, Any]


@dataclass
class SweepReport:
    """What a sweep did.

    ``n_done`` counts cases completed in this run, ``n_skipped`` those already
    complete from an earlier run, ``n_failed`` those still failed at the end.
    """

    n_cases: int
    n_done: int = 0
    n_skipped: int = 0
    n_failed: int = 0
    n_attempts_failed: int = 0
    failed_ids: list[str] = field(default_factory=list)
    wall_s: float = 0.0
    scheduler: str = "processes"
    n_workers: int = 1
    out_root: str = ""
    run: int = 1

    @property
    def failure_fraction(self) -> float:
        return self.n_failed / self.n_cases if self.n_cases else 0.0

    def to_dict(self) -> dict[str, Any]:
        out = asdict(self)
        out["failure_fraction"] = self.failure_fraction
        return out


def cases_from_frame(frame: pd.DataFrame) -> list[Case]:
    """Cases of a design table (columns ``case_id`` and ``case_json``)."""
    return [Case(str(cid), json.loads(text))
            for cid, text in zip(frame["case_id"], frame["case_json"], strict=True)]


@functools.lru_cache(maxsize=1)
def code_sha256() -> str:
    """SHA-256 over the source of the installed ``drillfatigue`` package (every ``.py``).

    Part of each case's ``DONE`` marker: a folder is reused only when it was
    written by the same inputs *and* the same code. The sweep outputs are
    ``persist``-ed under DVC (to resume a killed sweep), so without this a
    stage that DVC re-runs after a code change would keep results of the old
    code.
    """
    return drillfatigue.source_digest(Path(drillfatigue.__file__).parent)


def _marker(case_id: str, inputs: Mapping[str, Any]) -> dict[str, str]:
    return {"case_id": case_id, "inputs_sha256": inputs_sha256(inputs),
            "code_sha256": code_sha256()}


def is_done(case: Case, out_root: str | Path) -> bool:
    """True when ``out_root/<id>/DONE`` exists and matches the case id and inputs."""
    marker = Path(out_root) / case.case_id / DONE_NAME
    try:
        found = json.loads(marker.read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return False
    return found == _marker(case.case_id, case.inputs)


def _tail(text: str) -> str:
    return text if len(text) <= TAIL_CHARS else "..." + text[-TAIL_CHARS:]


def execute_case(case_fn: CaseFn, case_id: str, inputs: dict[str, Any], out_root: str,
                 attempt: int) -> dict[str, Any]:
    """Run one case in a temporary folder and move it into place atomically.

    Runs in the worker. Exceptions of the case function are caught and
    returned as a failure record (so nothing unpicklable crosses back);
    ``KeyboardInterrupt``/``SystemExit`` propagate.

    Returns
    -------
    dict
        ``ok`` (bool), ``case_id``, ``attempt``, ``wall_s``, ``worker`` and,
        on failure, ``error_type``, ``error``, ``traceback_tail``.
    """
    t0 = time.perf_counter()
    root = Path(out_root)
    final = root / case_id
    tmp = root / TMP_NAME / f"{case_id}.{os.getpid()}.{attempt}.{uuid.uuid4().hex[:8]}"
    record: dict[str, Any] = {"case_id": case_id, "attempt": attempt,
                              "worker": f"{socket.gethostname()}:{os.getpid()}"}
    try:
        tmp.mkdir(parents=True)
        case_fn(inputs, tmp)
        (tmp / DONE_NAME).write_text(json.dumps(_marker(case_id, inputs)), encoding="utf-8")
        if final.exists():  # stale output whose marker did not match: replace it
            shutil.rmtree(final)
        os.replace(tmp, final)
        record["ok"] = True
    except Exception as exc:  # noqa: BLE001 - recorded and reported, never dropped
        shutil.rmtree(tmp, ignore_errors=True)
        record.update(ok=False, error_type=type(exc).__name__, error=_tail(str(exc)),
                      traceback_tail=_tail(traceback.format_exc()))
    record["wall_s"] = time.perf_counter() - t0
    return record


class _SerialExecutor(Executor):
    """Runs each call at submit time in this process (``scheduler='serial'``)."""

    def submit(self, fn: Callable[..., Any], /, *args: Any, **kwargs: Any) -> Future:
        fut: Future = Future()
        try:
            fut.set_result(fn(*args, **kwargs))
        except Exception as exc:  # noqa: BLE001 - handed to the caller via the future
            fut.set_exception(exc)
        return fut


def _warmup_hook(case_fn: CaseFn) -> Callable[[dict[str, Any]], Any] | None:
    """``case_fn.warmup`` if set, else the module's ``warmup``; called with a case's inputs."""
    hook = getattr(case_fn, "warmup", None)
    if hook is None:
        module = sys.modules.get(case_fn.__module__) or importlib.import_module(case_fn.__module__)
        hook = getattr(module, "warmup", None)
    return hook if callable(hook) else None


@contextlib.contextmanager
def _open_executor(scheduler: str, n_workers: int, case_fn: CaseFn, first: Case | None
                   ) -> Iterator[tuple[Callable[[], Executor], int, Callable[[], None]]]:
    """Yield (make_executor, max_in_flight, close_current) for a scheduler.

    ``first`` is the first case to run (its inputs warm the compiled kernels up);
    None when every case is already done: nothing is compiled then.
    """
    hook = _warmup_hook(case_fn)
    if scheduler in ("processes", "local-cluster") and hook is not None and first is not None:
        hook(first.inputs)  # fill numba's on-disk cache before any worker exists
    if scheduler == "serial":
        yield (lambda: _SerialExecutor()), 1, (lambda: None)
        return
    if scheduler == "processes":
        ctx = multiprocessing.get_context("forkserver")
        # Workers fork from a server that has already imported the heavy
        # modules, so a (re)started pool is ready in well under a second.
        ctx.set_forkserver_preload([__name__, case_fn.__module__])
        current: list[ProcessPoolExecutor] = []

        def close(wait: bool = False) -> None:
            while current:
                current.pop().shutdown(wait=wait, cancel_futures=True)

        def make() -> Executor:
            close()
            current.append(ProcessPoolExecutor(max_workers=n_workers, mp_context=ctx))
            return current[-1]

        try:
            yield make, n_workers, (lambda: close(wait=True))
        finally:
            close()
        return
    # Dask: a LocalCluster or an existing scheduler
    from distributed import Client, LocalCluster  # optional extra [pipeline]: not for serial/process runs

    cluster = None
    if scheduler == "local-cluster":
        import dask  # optional extra [pipeline]

        # forkserver: worker processes start from a server that has the heavy
        # imports done (about 1/3 faster start-up than spawn on 2 cores).
        with dask.config.set({"distributed.worker.multiprocessing-method": "forkserver"}):
            cluster = LocalCluster(n_workers=n_workers, threads_per_worker=1, processes=True,
                                   dashboard_address=None, silence_logs=logging.ERROR)
        client = Client(cluster)
    else:
        try:
            client = Client(scheduler, timeout="20s")
        except OSError as exc:
            raise InputError("sweep.scheduler", f"cannot reach Dask scheduler {scheduler}: {exc}",
                             "a running scheduler address tcp://host:port") from None
    try:
        workers = client.scheduler_info().get("workers", {})
        slots = sum(int(w.get("nthreads", 1)) for w in workers.values()) or n_workers
        if cluster is None:
            # Remote workers do not inherit this process's environment: key
            # their numba cache by their installed kernels before any case
            # module is unpickled there (local workers inherit NUMBA_CACHE_DIR).
            client.run(scope_numba_cache)
        if cluster is None and hook is not None and first is not None:
            for address in workers:  # one worker at a time: no concurrent cache writes
                client.run(hook, first.inputs, workers=[address])
        executor = client.get_executor(pure=False)
        yield (lambda: executor), 2 * slots, (lambda: None)
    finally:
        client.close()
        if cluster is not None:
            cluster.close()


_FAILURE_DTYPES = {"case_id": "string", "attempts": "int64", "final": "bool",
                   "error_type": "string", "error": "string", "traceback_tail": "string",
                   "worker": "string", "inputs_json": "string", "run": "int64",
                   "time_utc": "string"}


def read_failures(path: str | Path) -> pd.DataFrame:
    """All failure rows of a sweep folder's ``failures.parquet`` (every run), oldest first.

    Rows written before the ``run``/``time_utc`` columns existed get run 0
    and an empty time.
    """
    p = Path(path)
    if not p.is_file():
        return pd.DataFrame({c: pd.Series(dtype=t) for c, t in _FAILURE_DTYPES.items()})
    frame = pd.read_parquet(p)
    if "run" not in frame.columns:
        frame["run"] = 0
    if "time_utc" not in frame.columns:
        frame["time_utc"] = ""
    return frame[FAILURE_COLUMNS].astype(_FAILURE_DTYPES)


def latest_failures(root: str | Path) -> pd.DataFrame:
    """The failure rows of the latest sweep run in ``root`` (per its ``sweep.json``)."""
    r = Path(root)
    frame = read_failures(r / FAILURES_NAME)
    report = r / REPORT_NAME
    if report.is_file():
        try:
            latest = int(json.loads(report.read_text(encoding="utf-8")).get("run", 0))
        except (ValueError, TypeError, AttributeError):
            latest = 0
        if latest > 0:
            return frame[frame["run"] == latest].reset_index(drop=True)
    if frame.empty:
        return frame
    return frame[frame["run"] == frame["run"].max()].reset_index(drop=True)


def _next_run(root: Path) -> int:
    """Number of the sweep run about to start in ``root`` (1 for a new folder)."""
    last = 0
    report = root / REPORT_NAME
    if report.is_file():
        try:
            last = int(json.loads(report.read_text(encoding="utf-8")).get("run", 1))
        except (ValueError, TypeError, AttributeError):
            last = 1
    runs = read_failures(root / FAILURES_NAME)["run"]
    return max(last, int(runs.max()) if len(runs) else 0) + 1


def _write_failures(path: Path, records: dict[str, dict[str, Any]], run: int) -> None:
    """Append this run's failure records to ``path`` (earlier runs' rows are kept)."""
    now = time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime())
    rows = [dict(records[k], run=run, time_utc=now) for k in sorted(records)]
    new = pd.DataFrame(rows, columns=FAILURE_COLUMNS).astype(_FAILURE_DTYPES)
    old = read_failures(path)
    old = old[old["run"] != run]
    frame = pd.concat([old, new], ignore_index=True) if len(old) else new
    with atomic_output(path) as tmp:
        frame.astype(_FAILURE_DTYPES).to_parquet(tmp, index=False)


def _print_failures(records: dict[str, dict[str, Any]], run: int, path: Path) -> None:
    """One line per case that failed in this run, on stderr."""
    if not records:
        return
    ids = sorted(records)
    n_final = sum(1 for k in ids if records[k]["final"])
    print(f"sweep run {run}: {len(ids)} case(s) failed at least once, {n_final} still failed "
          f"(details in {path}):", file=sys.stderr)
    for k in ids[:PRINT_FAILURES]:
        r = records[k]
        state = "failed" if r["final"] else "recovered on retry"
        text = " ".join(str(r["error"]).split())[:160]
        print(f"  {k}: {state} after {r['attempts']} attempt(s); {r['error_type']}: {text}",
              file=sys.stderr)
    if len(ids) > PRINT_FAILURES:
        print(f"  ... and {len(ids) - PRINT_FAILURES} more", file=sys.stderr)


def _write_json(path: Path, data: Any) -> None:
    atomic_write_text(path, json.dumps(data, indent=2, sort_keys=True) + "\n")


def _progress(enabled: bool, total: int) -> Any:
    if not enabled:
        return contextlib.nullcontext(None)
    return Progress(TextColumn("{task.description}"), BarColumn(), MofNCompleteColumn(),
                    TextColumn("[red]failed {task.fields[failed]}"), TimeElapsedColumn(),
                    TextColumn("ETA"), TimeRemainingColumn(),
                    console=Console(stderr=True), transient=False)


def run_sweep(cases: Iterable[Case], case_fn: CaseFn, out_root: str | Path, *,
              scheduler: str = "processes", n_workers: int = 2, max_retries: int = 1,
              failure_threshold: float = 0.1, progress: bool = False) -> SweepReport:
    """Run ``case_fn`` on every case not already done; see the module doc.

    Parameters
    ----------
    cases : iterable of Case
        Unique ids. ``inputs`` must be JSON-ready (they are hashed).
    case_fn : callable ``(inputs: dict, case_dir: Path) -> Any``
        Module-level function of an importable module; writes its outputs
        into ``case_dir``; raises on failure. A warm-up hook
        ``warmup(inputs)`` (attribute of the function, or of its module)
        is called once before workers start.
    out_root : path
        Sweep folder: ``<case_id>/`` per finished case, ``failures.parquet``
        and ``sweep.json`` (the report).
    scheduler : str
        ``serial``, ``processes``, ``local-cluster`` or ``tcp://host:port``.
    n_workers : int
        Worker processes for ``processes`` / ``local-cluster``.
    max_retries : int
        Extra attempts per failed case.
    failure_threshold : float
        Allowed fraction of finally failed cases.
    progress : bool
        Show a rich progress bar (cases done/failed, ETA) on stderr.

    Returns
    -------
    SweepReport

    Raises
    ------
    InputError
        Duplicate case ids or bad settings.
    SweepFailedError
        More than ``failure_threshold`` of the cases failed (after writing
        ``failures.parquet``).
    """
    cases = list(cases)
    if n_workers < 1:
        raise InputError("sweep.n_workers", f"must be >= 1, got {n_workers}", ">= 1")
    if max_retries < 0:
        raise InputError("sweep.max_retries", f"must be >= 0, got {max_retries}", ">= 0")
    if not 0.0 <= failure_threshold <= 1.0:
        raise InputError("sweep.failure_threshold", f"got {failure_threshold}", "0 ... 1")
    ids = [c.case_id for c in cases]
    if len(set(ids)) != len(ids):
        dup = sorted({i for i in ids if ids.count(i) > 1})[:3]
        raise InputError("cases", f"duplicate case ids {dup}", "unique case ids")
    t0 = time.perf_counter()
    root = Path(out_root)
    claim_sweep_folder(root)
    shutil.rmtree(root / TMP_NAME, ignore_errors=True)  # leftovers of a killed run
    report = SweepReport(n_cases=len(cases), scheduler=scheduler, n_workers=n_workers,
                         out_root=str(root), run=_next_run(root))
    todo: deque[Case] = deque(c for c in cases if not is_done(c, root))
    report.n_skipped = len(cases) - len(todo)
    failures: dict[str, dict[str, Any]] = {}
    attempts: dict[str, int] = {}

    def handle(case: Case, record: dict[str, Any]) -> None:
        attempts[case.case_id] = attempts.get(case.case_id, 0) + 1
        if record.get("ok"):
            report.n_done += 1
            if case.case_id in failures:
                failures[case.case_id].update(final=False, attempts=attempts[case.case_id])
            return
        report.n_attempts_failed += 1
        final = attempts[case.case_id] > max_retries
        failures[case.case_id] = {
            "case_id": case.case_id, "attempts": attempts[case.case_id], "final": final,
            "error_type": record.get("error_type", "Error"), "error": record.get("error", ""),
            "traceback_tail": record.get("traceback_tail", ""),
            "worker": record.get("worker", ""), "inputs_json": json.dumps(case.inputs,
                                                                          sort_keys=True)}
        if final:
            report.n_failed += 1
        else:
            todo.append(case)

    def died(case: Case, exc: BaseException) -> dict[str, Any]:
        return {"ok": False, "error_type": type(exc).__name__,
                "error": _tail(f"worker failed while running the case: {exc!r}"),
                "traceback_tail": _tail("".join(traceback.format_exception(exc)))}

    try:
        first = todo[0] if todo else None
        with _open_executor(scheduler, n_workers, case_fn, first) as (make, in_flight, close), \
                _progress(progress and bool(todo), len(cases)) as bar:
            task = None
            if bar is not None:
                task = bar.add_task("sweep", total=len(cases), completed=report.n_skipped,
                                    failed=0)
            executor = make() if todo else None
            pending: dict[Future, Case] = {}
            while todo or pending:
                while todo and len(pending) < in_flight:
                    case = todo.popleft()
                    fut = executor.submit(  # type: ignore[union-attr]
                        execute_case, case_fn, case.case_id, case.inputs, str(root),
                        attempts.get(case.case_id, 0) + 1)
                    pending[fut] = case
                finished, _ = wait(list(pending), return_when=FIRST_COMPLETED)
                broken = False
                for fut in finished:
                    case = pending.pop(fut)
                    try:
                        record = fut.result()
                    except BrokenProcessPool as exc:
                        broken = True
                        record = died(case, exc)
                    except Exception as exc:  # noqa: BLE001 - e.g. Dask KilledWorker
                        record = died(case, exc)
                    handle(case, record)
                if broken:  # the pool is dead: charge the cases in flight, start a new one
                    for case in list(pending.values()):
                        handle(case, died(case, BrokenProcessPool("worker process died")))
                    pending.clear()
                    executor = make()
                if bar is not None:
                    bar.update(task, completed=report.n_skipped + report.n_done + report.n_failed,
                               failed=report.n_failed)
            close()  # all work finished: wait for the workers to exit
        # Only now no worker can still write into .tmp (after Ctrl-C it is
        # left for the next run, which removes it before starting workers).
        shutil.rmtree(root / TMP_NAME, ignore_errors=True)
    finally:
        report.failed_ids = sorted(k for k, v in failures.items() if v["final"])
        report.wall_s = time.perf_counter() - t0
        _write_failures(root / FAILURES_NAME, failures, report.run)
        _write_json(root / REPORT_NAME, report.to_dict())
        _print_failures(failures, report.run, root / FAILURES_NAME)
    if report.n_failed and report.failure_fraction > failure_threshold:
        raise SweepFailedError(
            f"{report.n_failed} of {report.n_cases} cases failed "
            f"({report.failure_fraction:.1%} > failure_threshold {failure_threshold:.1%}); "
            f"errors in {root / FAILURES_NAME}")
    return report


def claim_sweep_folder(root: str | Path, option: str = "sweep folder") -> OutputFolder:
    """Claim ``root`` as a sweep folder (marker ``sweep``); InputError if it is not one.

    Accepted: a new or empty folder, one with a ``sweep`` marker, or one
    written without a marker that holds a sweep report (``sweep.json``),
    which is adopted. The report, failures table and per-case folders are
    the sweep's; nothing else in the folder is touched.
    """
    p = Path(root)
    if p.is_dir() and not (p / MARKER).exists() and (p / REPORT_NAME).is_file():
        atomic_write_json(p / MARKER, {"kind": SWEEP_KIND, "files": sorted(
            n for n in (FAILURES_NAME, REPORT_NAME) if (p / n).is_file())})
    folder = OutputFolder(p, SWEEP_KIND, option)
    for name in (FAILURES_NAME, REPORT_NAME):
        folder.file(name)
    return folder


def run_sweep_from_frame(frame: pd.DataFrame, case_fn: CaseFn, out_root: str | Path,
                         **kwargs: Any) -> SweepReport:
    """Convenience: :func:`run_sweep` on the cases of a design table."""
    return run_sweep(cases_from_frame(frame), case_fn, out_root, **kwargs)


def completed_case_ids(cases: Sequence[Case], out_root: str | Path) -> list[str]:
    """Ids of the cases whose output folder is complete (matching DONE marker)."""
    return [c.case_id for c in cases if is_done(c, out_root)]
