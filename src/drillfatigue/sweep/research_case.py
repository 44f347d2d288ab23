"""One research case in a worker process: simulate, evaluate, tabulate, write its rows file.

The worker side of :mod:`drillfatigue.sweep.research` (which designs, schedules,
checks and assembles). This module and what it imports decide a case's rows, so it is
one of :data:`drillfatigue.sweep.research.PHYSICS_MODULES`; the orchestration is not,
and an edit to it leaves the committed case files valid.

Worker processes run numba's parallel kernels and BLAS on one thread each: with one
worker per core the cores are already busy, and threads inside a worker only compete
(the rows are the same; docs/performance.md, "A research case").
"""

from __future__ import annotations

import json
import os
import shutil
import tempfile
import time
import uuid
from pathlib import Path
from typing import Any

import numba
import pandas as pd
import pyarrow as pa
import pyarrow.parquet as pq
from threadpoolctl import threadpool_limits

from drillfatigue.files import atomic_output
from drillfatigue.sweep.cases import fatigue_case
from drillfatigue.sweep.dataset import build_dataset
from drillfatigue.sweep.design import apply_overrides
from drillfatigue.sweep.window import run_case_converged

__all__ = ["LAYOUT_KEY", "META_KEY", "case_rows", "research_case", "write_case_file"]

#: Key of the marker in a case file's Parquet schema metadata.
META_KEY = b"drillfatigue.research"
#: Key of the column layout (order, dtypes, constant columns) in the same metadata.
LAYOUT_KEY = b"drillfatigue.layout"


_SINGLE_THREADED = False


def _single_threaded() -> None:
    """numba's parallel kernels and BLAS on one thread in this (worker) process."""
    global _SINGLE_THREADED
    if _SINGLE_THREADED:
        return
    numba.set_num_threads(1)
    threadpool_limits(1)
    _SINGLE_THREADED = True


def case_rows(row: dict[str, Any], inputs: dict[str, Any], work: Path,
              histories: Path | None = None) -> pd.DataFrame:
    """Simulate, evaluate and tabulate one design row in ``work`` (removed by the caller).

    The rows are those of :func:`drillfatigue.sweep.dataset.build_dataset` for this case,
    from the same functions the pipeline's simulate and fatigue stages run."""
    cid = str(row["case_id"])
    run_dir, fat_dir = work / "sweep" / cid, work / "fatigue" / cid
    uniaxial: list[pd.DataFrame] = []
    run_case_converged({"case": inputs["case"], "window": inputs["window"]}, run_dir, uniaxial)
    # the window check evaluated the uniaxial route on the run kept: the fatigue reuses it
    fatigue_case({"run_dir": str(run_dir), "fatigue": inputs["fatigue"],
                  "criteria": inputs["criteria"], "api_rp7g": inputs["api_rp7g"],
                  "case": inputs["case"]}, fat_dir, uniaxial[0])
    frame = pd.DataFrame([row])
    rows = build_dataset(frame, work / "sweep", work / "fatigue", inputs["variables"])
    if histories is not None:
        dest = histories / cid
        tmp = histories / f".{cid}.{uuid.uuid4().hex[:8]}"
        shutil.copytree(run_dir, tmp)
        shutil.rmtree(dest, ignore_errors=True)
        os.replace(tmp, dest)
    return rows


def research_case(task: dict[str, Any]) -> dict[str, Any]:
    """Run one research case in a worker and write its rows file (see the module doc).

    Returns a record: ``ok``, ``case_id``, ``split``, ``wall_s``, ``n_rows``, ``bytes``
    and, on failure, ``error_type`` and ``error`` (nothing unpicklable crosses back).
    """
    _single_threaded()
    t0 = time.perf_counter()
    row, out = task["row"], Path(task["path"])
    rec: dict[str, Any] = {"case_id": str(row["case_id"]), "split": task["split"]}
    hist = Path(task["histories"]) if task.get("histories") else None
    try:
        with tempfile.TemporaryDirectory(prefix="research-") as tmp:
            rows = case_rows(row, task["inputs"], Path(tmp), hist)
        if not len(rows):
            raise RuntimeError("the case gave no dataset rows")
        write_case_file(rows, out, task["marker"])
        rec.update(ok=True, n_rows=len(rows), bytes=out.stat().st_size)
    except Exception as exc:  # noqa: BLE001 - recorded in failures.parquet, never dropped
        rec.update(ok=False, error_type=type(exc).__name__, error=str(exc)[-2000:])
    rec["wall_s"] = time.perf_counter() - t0
    return rec


def _warmup(task: dict[str, Any]) -> None:
    """Fill numba's on-disk cache before workers start: one short copy of a case through
    the simulator, every fatigue criterion and the row builder."""
    inputs = task["inputs"]
    short = apply_overrides(inputs["case"], {"operation.duration_s": 0.05,
                                             "recording.start_s": 0.0,
                                             "solver.checkpoint_every_s": 0.0})
    win = {**inputs["window"], "first_s": 0.05, "max_s": 0.05}
    try:
        with tempfile.TemporaryDirectory(prefix="warmup-") as tmp:
            case_rows({**task["row"], "case_json": json.dumps(short)},
                      {**inputs, "case": short, "window": win}, Path(tmp))
    except Exception:  # noqa: BLE001 - the real run of this case reports the error
        return


research_case.warmup = _warmup  # type: ignore[attr-defined]


def _scalar(value: Any) -> Any:
    """A JSON-ready Python scalar (NaN stays NaN: Python's json writes and reads it)."""
    if value is None or value is pd.NA:
        return None
    return value.item() if hasattr(value, "item") else value


def write_case_file(rows: pd.DataFrame, path: Path, marker: dict[str, Any]) -> None:
    """Write one case's rows atomically: the columns that vary over the case's rows as
    Parquet (zstd), the rest as one value each in the schema
    metadata with every column's order and dtype, and the marker beside them. Most
    columns of a case (its inputs and run figures) are constant over its rows: stored
    once, a case takes a fifth of the bytes (docs/pipeline.md#generating-the-research-dataset)."""
    const = [c for c in rows.columns if rows[c].nunique(dropna=False) <= 1]
    var = [c for c in rows.columns if c not in const]
    layout = {"columns": list(rows.columns), "dtypes": {c: str(rows[c].dtype) for c in rows},
              "constants": {c: _scalar(rows[c].iloc[0]) for c in const}}
    table = pa.Table.from_pandas(rows[var], preserve_index=False).replace_schema_metadata(None)
    meta = {META_KEY: json.dumps(marker, sort_keys=True).encode(),
            LAYOUT_KEY: json.dumps(layout, separators=(",", ":")).encode()}
    with atomic_output(path) as part:
        # store_schema=False: the Arrow schema would repeat the metadata (base64) in the footer
        with pq.ParquetWriter(part, table.schema, compression="zstd", compression_level=19,
                              write_statistics=False, use_dictionary=False,
                              store_schema=False) as writer:
            writer.write_table(table)
            writer.add_key_value_metadata(meta)
