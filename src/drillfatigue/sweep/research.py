"""The research sweep: a large training and held-out design whose rows survive any stop.

``drillfatigue dataset research`` (docs/pipeline.md#generating-the-research-dataset)
designs the training cases (``sweep.seed``) and the held-out cases
(``heldout.seed``, cases shared with training left out) with the sweep's
ranges, boundaries and window rule, and runs every case in a worker process
as the pipeline's stages would (:func:`drillfatigue.sweep.window.run_case_converged`,
:func:`drillfatigue.sweep.cases.fatigue_case`,
:func:`drillfatigue.sweep.dataset.build_dataset`), in a temporary folder that
is removed after the case: only the case's dataset rows are kept. Layout::

    <out>/design/{train,heldout}.parquet   case tables (design.json beside them)
    <out>/cases/{train,heldout}/<case_id>.parquet
                                           one finished case's rows; its schema
                                           metadata holds the marker (below)
    <out>/histories/{train,heldout}/<case_id>/  run folders (``--histories`` only)
    <out>/failures.parquet                 cases that failed in the latest run
    <out>/dataset/{train,heldout}.parquet  assembled: every case's rows sorted by
                                           case_id, joint, location, plus ``split``

A case file is written to a temporary name in its folder and renamed into
place, so a stop at any instant leaves finished cases whole and nothing else
under a final name. Its marker holds the case's inputs hash (case, window
rule, fatigue settings, criteria) and the *physics digest*: SHA-256 over the
modules that decide the rows (:data:`PHYSICS_MODULES`; the command line, the
service, the ledger and the surrogate are not among them). A case whose
marker matches is skipped on the next run; files made with other inputs, or with
a digest not found equal to this code's (``digests.json``, written by
:mod:`drillfatigue.sweep.restamp` after it re-ran a sample of cases bit for bit),
are refused (exit code 2) with the commit they were made at, never mixed. The
assembled files depend only on the case files, so a run stopped and continued (here
or from a fresh clone) assembles the same bytes.

A case runs in a worker process (:mod:`drillfatigue.sweep.research_case`, one of
the physics digest's modules); this module designs, schedules, checks and assembles,
and is not among them: an edit here leaves the committed case files valid.
"""

from __future__ import annotations

import functools
import hashlib
import json
import math
import subprocess
import sys
import time
from collections.abc import Callable, Sequence
from concurrent.futures import FIRST_COMPLETED, Future, wait
from concurrent.futures.process import BrokenProcessPool
from pathlib import Path
from typing import Any

import pandas as pd
import pyarrow as pa
import pyarrow.parquet as pq

import drillfatigue
from drillfatigue.config import Params
from drillfatigue.errors import InputError
from drillfatigue.files import OutputFolder, atomic_output, atomic_write_text
from drillfatigue.sweep.dataset import split_constants
from drillfatigue.sweep.design import (base_case_from_params, design_cases,
                                       inputs_sha256, read_cases, write_cases)
from drillfatigue.sweep.runner import Case, _open_executor
from drillfatigue.sweep.research_case import (LAYOUT_KEY, META_KEY, research_case)
from drillfatigue.sweep.window import window_inputs

__all__ = ["LINEAGE_FILE", "PHYSICS_MODULES", "RESEARCH_KIND", "SPLITS", "assemble_research",
           "equivalent_digests", "physics_digest", "read_lineage",
           "research_case", "research_design", "run_research"]

#: Ownership marker kind of the research folder.
RESEARCH_KIND = "research"
#: The two splits, in the order they run.
SPLITS = ("train", "heldout")
#: Paths under the package root whose source decides a case's rows: a folder
#: stands for every module under it. Running one case imports no module of the
#: package outside these (tests/research/test_research.py checks it).
PHYSICS_MODULES: tuple[str, ...] = (
    "__init__.py", "errors.py", "files.py", "limits.py", "numba_cache.py", "plotting.py",
    "rundir.py", "status.py", "units.py",
    "config/", "dynamics/", "fatigue/", "string/", "well/",
    # a well from a survey file: its reader parses the file's unit headers
    "io/__init__.py", "io/display.py", "io/headers.py",
    "sweep/__init__.py", "sweep/cases.py", "sweep/dataset.py", "sweep/design.py",
    "sweep/research_case.py", "sweep/runner.py", "sweep/window.py",
)
#: Design-table and run-record files of the research folder (owned by its marker).
DESIGN_FILES = ("design/train.parquet", "design/heldout.parquet", "design/design.json")
DATASET_FILES = ("dataset/train.parquet", "dataset/heldout.parquet", "dataset/constants.json")
FAILURES_FILE = "failures.parquet"
#: Digests whose case files were found equal (:mod:`drillfatigue.sweep.restamp`).
LINEAGE_FILE = "digests.json"


def physics_digest(root: Path | None = None) -> str:
    """SHA-256 (hex) over the modules of :data:`PHYSICS_MODULES` (paths and contents)."""
    root = Path(drillfatigue.__file__).parent if root is None else Path(root)
    digest = hashlib.sha256()
    files: set[Path] = set()
    for item in PHYSICS_MODULES:
        p = root / item
        files.update(p.rglob("*.py") if item.endswith("/") else [p])
    for path in sorted(files):
        digest.update(path.relative_to(root).as_posix().encode() + b"\0" + path.read_bytes())
    return digest.hexdigest()


def read_lineage(root: Path) -> list[dict[str, Any]]:
    """The entries of ``<root>/digests.json`` (empty when there is none)."""
    path = Path(root) / LINEAGE_FILE
    if not path.is_file():
        return []
    try:
        return list(json.loads(path.read_text(encoding="utf-8"))["equivalent_digests"])
    except (ValueError, KeyError, TypeError) as exc:
        raise InputError(str(path), f"not a digests file ({exc})",
                         "the file drillfatigue dataset restamp writes") from None


def equivalent_digests(root: Path, digest: str) -> set[str]:
    """The physics digests whose case files this code accepts: those of ``digests.json``
    when ``digest`` is among them (their rows were re-run equal), else ``digest`` alone."""
    listed = {e["physics_digest"] for e in read_lineage(root)}
    return listed if digest in listed else {digest}


def _commit() -> str | None:
    """The git commit of the checkout the package is imported from, or None."""
    try:
        res = subprocess.run(["git", "-C", str(Path(drillfatigue.__file__).parent), "rev-parse",
                              "HEAD"], capture_output=True, text=True, timeout=10)
    except (OSError, subprocess.SubprocessError):
        return None
    return res.stdout.strip() or None if res.returncode == 0 else None


# --- design -------------------------------------------------------------------------
def research_design(params: Params, n_cases: int, heldout_cases: int
                    ) -> dict[str, pd.DataFrame]:
    """The training design (``sweep`` section, ``n_cases``) and the held-out design
    (:func:`drillfatigue.sweep.stages.heldout_params`, ``heldout_cases``; cases shared with
    training left out)."""
    # a worker imports this module: the stages (and the adaptive design they import) stay out
    # start-up: a case imports only the physics digest's modules
    from drillfatigue.sweep.stages import heldout_params

    if n_cases < 1:
        raise InputError("--n-cases", f"must be >= 1, got {n_cases}", ">= 1")
    if heldout_cases < 0:
        raise InputError("--heldout-cases", f"must be >= 0, got {heldout_cases}", ">= 0")
    if heldout_cases and params.heldout.seed == params.sweep.seed:
        raise InputError("heldout.seed", f"equals sweep.seed ({params.sweep.seed})",
                         "a seed other than sweep.seed")
    p = params.model_copy(update={"sweep": params.sweep.model_copy(update={"n_cases": n_cases})})
    train = design_cases(p.sweep, base_case_from_params(p))
    out = {"train": train}
    if heldout_cases:
        hp = heldout_params(params)
        hp = hp.model_copy(update={"sweep": hp.sweep.model_copy(
            update={"n_cases": heldout_cases})})
        held = design_cases(hp.sweep, base_case_from_params(hp))
        out["heldout"] = held[~held["case_id"].isin(set(train["case_id"]))].reset_index(
            drop=True)
    else:
        out["heldout"] = train.iloc[:0]
    return out


# --- one case ---------------------------------------------------------------------------
def _case_inputs(params: Params, row: dict[str, Any], variables: Sequence[str]
                 ) -> dict[str, Any]:
    """Everything a case's rows depend on beside the code (JSON-ready)."""
    cfg = params.sweep
    return {"case": json.loads(row["case_json"]), "window": window_inputs(params),
            "fatigue": params.fatigue.model_dump(mode="json"),
            "criteria": list(cfg.fatigue_criteria), "api_rp7g": bool(cfg.api_rp7g),
            "variables": list(variables)}


def read_case_file(path: Path) -> pd.DataFrame:
    """The rows of a case file (:func:`write_case_file`), columns and dtypes as written."""
    file = pq.ParquetFile(path)
    layout = json.loads(file.metadata.metadata[LAYOUT_KEY])
    varying = file.read().to_pandas()
    consts, dtypes = layout["constants"], layout["dtypes"]
    n = len(varying)
    # column by column (one frame built at the end: inserting ~60 constant columns one at
    # a time into a frame cost most of the assembly's minute)
    columns = {}
    for col in layout["columns"]:
        series = (pd.Series([consts[col]] * n, index=varying.index, dtype=object)
                  if col in consts else varying[col])
        dtype = _dtype(dtypes[col])
        columns[col] = series if series.dtype == dtype else series.astype(dtype)
    return pd.DataFrame(columns, index=varying.index)


@functools.cache
def _dtype(name: str) -> Any:
    return pd.api.types.pandas_dtype(name)


# --- the folder -------------------------------------------------------------------------
def read_marker(path: Path) -> dict[str, Any] | None:
    """The marker of a case file, or None when the file is not a readable case file."""
    try:
        meta = pq.read_metadata(path).metadata or {}
        return json.loads(meta[META_KEY])
    except (OSError, KeyError, ValueError, pa.ArrowException):
        return None


def _design_record(params: Params, n_cases: int, heldout_cases: int) -> dict[str, Any]:
    cfg = params.sweep
    return {"n_cases": n_cases, "heldout_cases": heldout_cases, "seed": cfg.seed,
            "heldout_seed": params.heldout.seed, "method": cfg.method,
            "sweep_sha256": inputs_sha256(cfg.model_dump(mode="json",
                                                         exclude={"n_cases", "n_workers",
                                                                  "scheduler"}))}


def _load_or_write_design(folder: OutputFolder, params: Params, n_cases: int,
                          heldout_cases: int, given: dict[str, pd.DataFrame] | None = None
                          ) -> dict[str, pd.DataFrame]:
    """The stored design when it is this request's; else design and write it (a stored
    design of another request is refused)."""
    record = _design_record(params, n_cases, heldout_cases)
    rec_path = folder.path / "design" / "design.json"
    if rec_path.is_file():
        found = json.loads(rec_path.read_text(encoding="utf-8"))
        if {k: found.get(k) for k in record} != record:
            raise InputError("--out", f"{folder.path} holds the research design "
                             f"{json.dumps({k: found.get(k) for k in record}, sort_keys=True)}, "
                             "not this one", "the same --n-cases, --heldout-cases and sweep "
                             "settings, or a fresh --out")
        return {s: read_cases(folder.path / "design" / f"{s}.parquet") for s in SPLITS}
    designs = given if given is not None else research_design(params, n_cases, heldout_cases)
    for s in SPLITS:
        write_cases(designs[s], folder.file(f"design/{s}.parquet"))
    info = {**record, "n_train": len(designs["train"]), "n_heldout": len(designs["heldout"]),
            "variables": list(params.sweep.variables)}
    atomic_write_text(folder.file("design/design.json"),
                      json.dumps(info, indent=2, sort_keys=True) + "\n")
    return designs


def _check_case_files(root: Path, split: str, ids: set[str], digest: str) -> dict[str, dict]:
    """Markers of the finished case files of a split; refuse foreign files and files of
    a physics digest not equivalent to ``digest`` (:func:`equivalent_digests`)."""
    folder = root / "cases" / split
    accepted = equivalent_digests(root, digest)
    found: dict[str, dict] = {}
    if not folder.is_dir():
        return found
    for path in sorted(folder.iterdir()):
        if path.name.startswith(".") and ".tmp" in path.name:
            path.unlink(missing_ok=True)  # an atomic write cut short
            continue
        marker = read_marker(path) if path.suffix == ".parquet" else None
        if marker is None or path.stem not in ids or marker.get("case_id") != path.stem:
            raise InputError("--out", f"{path} is not a case file of this research design",
                             "a folder holding only this design's case files")
        if marker.get("physics_digest") not in accepted:
            raise InputError("--out", f"{path} was made with physics digest "
                             f"{str(marker.get('physics_digest'))[:12]} at commit "
                             f"{marker.get('commit') or 'unknown'}; this code has "
                             f"{digest[:12]}", "check out that commit, run drillfatigue "
                             "dataset restamp (a change that leaves the rows equal), or a "
                             "fresh --out")
        found[path.stem] = marker
    return found


def _tasks(folder: OutputFolder, params: Params, designs: dict[str, pd.DataFrame],
           digest: str, commit: str | None, histories: bool) -> tuple[list[dict], int]:
    variables = [v for v in params.sweep.variables if v in designs["train"].columns]
    tasks: list[dict[str, Any]] = []
    skipped = 0
    for split in SPLITS:
        frame = designs[split]
        ids = set(frame["case_id"])
        done = _check_case_files(folder.path, split, ids, digest)
        (folder.path / "cases" / split).mkdir(parents=True, exist_ok=True)
        for row in frame.to_dict("records"):
            cid = str(row["case_id"])
            inputs = _case_inputs(params, row, variables)
            marker = {"case_id": cid, "split": split, "inputs_sha256": inputs_sha256(inputs),
                      "physics_digest": digest, "commit": commit}
            if cid in done:
                if done[cid].get("inputs_sha256") != marker["inputs_sha256"]:
                    raise InputError("--out", f"{folder.path}/cases/{split}/{cid}.parquet "
                                     "was made with other settings (window rule, fatigue, "
                                     "criteria)", "the settings of that run, or a fresh --out")
                skipped += 1
                continue
            tasks.append({"row": {k: (v.item() if hasattr(v, "item") else v)
                                  for k, v in row.items()},
                          "split": split, "inputs": inputs, "marker": marker,
                          "path": str(folder.path / "cases" / split / f"{cid}.parquet"),
                          "histories": str(folder.path / "histories" / split)
                          if histories else None})
            if histories:
                Path(tasks[-1]["histories"]).mkdir(parents=True, exist_ok=True)
    return tasks, skipped


def _write_failures(folder: OutputFolder, failures: list[dict[str, Any]]) -> None:
    cols = ["case_id", "split", "error_type", "error"]
    frame = pd.DataFrame(failures, columns=cols).sort_values(["split", "case_id"],
                                                             kind="mergesort")
    with atomic_output(folder.file(FAILURES_FILE)) as tmp:
        frame.reset_index(drop=True).to_parquet(tmp, index=False)


#: Columns of a case file that measure the machine that ran it, left out of the tables.
MEASURED_COLUMNS = ("wall_time_s",)


def assemble_research(root: str | Path, params: Params) -> dict[str, int]:
    """Assemble ``dataset/{train,heldout}.parquet`` from the case files of ``root``.

    Rows sorted by case_id, joint, location. The training table drops the columns
    constant over it (to ``dataset/constants.json``) but the design variables and the
    surrogate's inputs, as ``data/dataset/damage.parquet``; the held-out table has the
    training table's columns. Both gain ``split``; neither has :data:`MEASURED_COLUMNS`, so
    a run stopped and continued assembles the same bytes as one that was not. Returns
    rows and cases per split."""
    folder = OutputFolder(root, RESEARCH_KIND, "--out")
    designs = {s: read_cases(folder.path / "design" / f"{s}.parquet") for s in SPLITS}
    full: dict[str, pd.DataFrame] = {}
    counts: dict[str, int] = {}
    for split in SPLITS:
        parts = []
        for cid in sorted(designs[split]["case_id"]):
            path = folder.path / "cases" / split / f"{cid}.parquet"
            if path.is_file():
                parts.append(read_case_file(path))
        frame = pd.concat(parts, ignore_index=True, sort=False) if parts else pd.DataFrame()
        # the simulator's wall time measures the machine, not the case: a case run again
        # after a stop would change the table (the case files keep it)
        frame = frame.drop(columns=[c for c in MEASURED_COLUMNS if c in frame.columns])
        if len(frame):
            if "whirl_class" in frame.columns:
                frame["whirl_class"] = frame["whirl_class"].astype("string")
            frame = frame.sort_values(["case_id", "joint", "location"],
                                      kind="mergesort").reset_index(drop=True)
        full[split] = frame
        counts[f"n_cases_{split}"] = len(parts)
        counts[f"n_rows_{split}"] = len(frame)
    sur = params.surrogate
    keep = [*params.sweep.variables, *sur.features, *sur.categorical]
    train, constants = split_constants(full["train"], keep=keep)
    columns = list(train.columns) if len(train.columns) else list(full["heldout"].columns)
    tables = {"train": train, "heldout": full["heldout"].reindex(columns=columns)
              if len(full["heldout"]) else pd.DataFrame(columns=columns)}
    for split in SPLITS:
        out = tables[split].assign(split=split)
        with atomic_output(folder.file(f"dataset/{split}.parquet")) as tmp:
            out.to_parquet(tmp, index=False)
    atomic_write_text(folder.file("dataset/constants.json"),
                      json.dumps(constants, indent=2, sort_keys=True, default=str) + "\n")
    return counts


def _progress(done: int, total: int, t0: float, n_run: int, err: Any) -> None:
    elapsed = time.perf_counter() - t0
    rate = n_run / elapsed * 3600.0 if elapsed > 0 and n_run else float("nan")
    left = total - done
    eta = left / rate * 3600.0 if rate > 0 and math.isfinite(rate) else float("nan")
    eta_txt = "?" if not math.isfinite(eta) else f"{eta / 3600.0:.2f} h"
    print(f"research: {done}/{total} cases, {rate:.0f} cases/h, ETA {eta_txt}", file=err,
          flush=True)


def run_research(params: Params, out: str | Path = "data/research", *, n_cases: int,
                 heldout_cases: int, n_workers: int = 2, histories: bool = False,
                 progress: bool = True, scheduler: str = "processes",
                 case_fn: Callable[[dict[str, Any]], dict[str, Any]] = research_case,
                 designs: dict[str, pd.DataFrame] | None = None) -> dict[str, Any]:
    """Design, run (resumable, see the module doc) and assemble the research dataset.

    ``designs`` (``train`` and ``heldout`` case tables) replaces the design (benchmarks
    run chosen cases); ``n_cases`` and ``heldout_cases`` then only label it.
    Returns the run's counts: cases done now, skipped (already finished), failed,
    and the assembled rows and cases per split."""
    if n_workers < 1:
        raise InputError("--workers", f"must be >= 1, got {n_workers}", ">= 1")
    folder = OutputFolder(out, RESEARCH_KIND, "--out", (*DESIGN_FILES, *DATASET_FILES,
                                                        FAILURES_FILE, LINEAGE_FILE))
    digest, commit = physics_digest(), _commit()
    designs = _load_or_write_design(folder, params, n_cases, heldout_cases, designs)
    tasks, skipped = _tasks(folder, params, designs, digest, commit, histories)
    total = sum(len(designs[s]) for s in SPLITS)
    failures: list[dict[str, Any]] = []
    done = skipped
    t0 = time.perf_counter()
    err = sys.stderr
    if progress:
        _progress(done, total, t0, 0, err)
    first = Case(tasks[0]["marker"]["case_id"], tasks[0]) if tasks else None
    n_run = 0
    # the runner's pool and warm-up hook; the research case takes its task alone
    with _open_executor(scheduler, n_workers, case_fn,  # type: ignore[arg-type]
                        first) as (make, in_flight, close):
        todo = list(tasks)
        executor = make() if todo else None
        pending: dict[Future, dict[str, Any]] = {}
        while todo or pending:
            while todo and len(pending) < in_flight:
                task = todo.pop(0)
                pending[executor.submit(case_fn, task)] = task  # type: ignore[union-attr]
            finished, _ = wait(list(pending), return_when=FIRST_COMPLETED)
            broken = False
            for fut in finished:
                task = pending.pop(fut)
                try:
                    rec = fut.result()
                except BrokenProcessPool as exc:
                    broken = True
                    rec = {"ok": False, "error_type": type(exc).__name__,
                           "error": "worker process died while running the case"}
                if not rec.get("ok"):
                    failures.append({"case_id": task["marker"]["case_id"],
                                     "split": task["split"],
                                     "error_type": rec.get("error_type", "Error"),
                                     "error": rec.get("error", "")})
                n_run += 1
                done += 1
                if progress:
                    _progress(done, total, t0, n_run, err)
            if broken:
                for task in pending.values():
                    failures.append({"case_id": task["marker"]["case_id"],
                                     "split": task["split"], "error_type": "BrokenProcessPool",
                                     "error": "worker process died while running a case"})
                    done += 1
                pending.clear()
                executor = make()
        close()
    _write_failures(folder, failures)
    counts = assemble_research(folder.path, params)
    return {"n_cases": total, "n_run": n_run, "n_skipped": skipped, "n_failed": len(failures),
            "wall_s": time.perf_counter() - t0, **counts}
