"""The sweep's pipeline stages as library functions (the ``pipeline/*.py`` scripts call these).

``design`` → ``data/design/cases.parquet`` (+ ``coverage.csv``, ``design.json``);
``simulate`` → ``data/sweep/<case_id>/`` (+ ``failures.parquet``, ``sweep.json``);
``fatigue`` → ``data/fatigue/<case_id>/`` (+ ``failures.parquet``, ``sweep.json``);
``dataset`` → ``data/dataset/damage.parquet``, ``README.md``, ``metrics.json``,
``plots/damage_rate_hist.csv``.

Each takes the validated :class:`~drillfatigue.config.Params`; paths default
to the ``sweep`` section's. The case functions can be replaced (tests and
benchmarks pass the synthetic ones).
"""

from __future__ import annotations

import json
import math
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import pandas as pd
import pyarrow.parquet as pq

from drillfatigue.config import Params
from drillfatigue.errors import InputError
from drillfatigue.files import (MARKER, OutputFolder, atomic_output, atomic_write_text,
                                check_output_file)
from drillfatigue.sweep.adaptive import (
    ADAPTIVE_KIND,
    RowSource,
    TargetFn,
    adaptive_design,
    case_targets,
    template_rows,
)
from drillfatigue.sweep.cases import fatigue_case, fatigue_tasks, run_case
from drillfatigue.sweep.dataset import DATASET_FILES, DATASET_KIND, build_dataset, write_dataset
from drillfatigue.sweep.design import base_case_from_params, design_cases, read_cases, write_cases
from drillfatigue.sweep.runner import (REPORT_NAME, SWEEP_KIND, Case, CaseFn, SweepReport,
                                      cases_from_frame, run_sweep)
from drillfatigue.sweep.window import run_case_converged, window_inputs

__all__ = ["adaptive_cache_dir", "adaptive_rows", "adaptive_targets", "dataset_stage",
           "design_stage", "fatigue_stage", "heldout_params", "heldout_stage", "simulate_stage",
           "write_report"]


def _write_json(path: Path, data: Any) -> None:
    atomic_write_text(path, json.dumps(data, indent=2, sort_keys=True) + "\n")


def write_report(report: SweepReport, path: str | Path) -> None:
    """Write a sweep report as JSON (for ``dvc metrics``)."""
    _write_json(Path(path), report.to_dict())


def check_design_outputs(cases_path: str | Path, option: str = "sweep.cases_path") -> None:
    """Refuse, before any work, a case table the design stage could not write.

    The stage writes the case table and, beside it, ``coverage.csv`` and
    ``design.json``: a folder of the table's name, or a file of one of these
    names that the stage did not write (not a case table, not a coverage
    table starting with ``case_id``, not a design record), is refused with a
    one-line :class:`InputError`; nothing is written.
    """
    path = Path(cases_path)
    check_output_file(path, option)
    allowed = "a new path, or a case table written by drillfatigue's design stage"

    def foreign(f: Path) -> InputError:
        return InputError(option, f"{f} exists and was not written by drillfatigue", allowed)

    if path.exists() or path.is_symlink():
        try:
            names = set(pq.read_schema(path).names)
        except Exception as exc:  # any unreadable file is not ours
            raise foreign(path) from exc
        if not {"case_id", "case_json"} <= names:
            raise foreign(path)
    cov = path.with_name("coverage.csv")
    if cov.exists() or cov.is_symlink():
        try:
            with cov.open(encoding="utf-8") as fh:
                ours = fh.readline().startswith("case_id")
        except (OSError, UnicodeDecodeError):
            ours = False
        if not ours:
            raise foreign(cov)
    rec = path.with_name("design.json")
    if rec.exists() or rec.is_symlink():
        try:
            info = json.loads(rec.read_text(encoding="utf-8"))
        except (OSError, ValueError, UnicodeDecodeError):
            info = None
        if not (isinstance(info, dict) and {"method", "n_cases"} <= set(info)):
            raise foreign(rec)


def check_sweep_outputs(params: Params, cases_path: str | Path | None = None) -> None:
    """Refuse, before any work, output folders ``sweep run`` could not write into.

    The design's files (:func:`check_design_outputs`), the adaptive cache, the
    sweep and fatigue folders and the dataset folder are checked as their
    stages would claim them, so a foreign file in the last of them stops the
    command at once instead of after every simulation.
    """
    cfg = params.sweep
    path = Path(cases_path or cfg.cases_path)
    check_design_outputs(path)
    OutputFolder.check(adaptive_cache_dir(params, path), ADAPTIVE_KIND,
                       "sweep.adaptive.cache_dir")
    for root, option in ((cfg.sweep_dir, "sweep.sweep_dir"), (cfg.fatigue_dir, "sweep.fatigue_dir")):
        r = Path(root)
        if r.is_dir() and not (r / MARKER).exists() and (r / REPORT_NAME).is_file():
            continue  # a sweep folder written before markers: adopted when claimed
        OutputFolder.check(r, SWEEP_KIND, option)
    OutputFolder.check(cfg.dataset_dir, DATASET_KIND, "sweep.dataset_dir", DATASET_FILES)


def design_stage(params: Params, cases_path: str | Path | None = None, *,
                 progress: bool = False, case_fn: CaseFn = run_case,
                 fatigue_fn: CaseFn = fatigue_case) -> pd.DataFrame:
    """Sample the design; write the case table, ``coverage.csv`` and ``design.json`` beside it.

    ``method: adaptive`` simulates and evaluates the cases it chooses
    (:func:`adaptive_targets`, cached in :func:`adaptive_cache_dir`; the
    table gains ``round`` and ``acquisition_score``); the other methods claim
    that folder empty (a DVC output of the stage whatever the method).
    ``case_fn``/``fatigue_fn`` replace the simulator and fatigue there.
    """
    cfg = params.sweep
    cases_path = Path(cases_path or cfg.cases_path)
    check_design_outputs(cases_path)
    if cfg.method == "adaptive":
        censor = (-math.log10(params.surrogate.horizon_h)
                  if params.surrogate.censoring == "likelihood" else None)
        frame = adaptive_design(cfg, base_case_from_params(params),
                                adaptive_targets(params, progress=progress, case_fn=case_fn,
                                                 fatigue_fn=fatigue_fn, cases_path=cases_path),
                                censor_log10=censor, rows=adaptive_rows(params, cases_path))
    else:
        frame = design_cases(cfg, base_case_from_params(params))
        if _is_configured_table(params, cases_path):
            # the pipeline's stage output (dvc.yaml), claimed empty; a table written
            # elsewhere (sweep design --out) leaves it alone: a command writes only
            # under its outputs
            OutputFolder(adaptive_cache_dir(params, cases_path), ADAPTIVE_KIND,
                         "sweep.adaptive.cache_dir")
    path = write_cases(frame, cases_path)
    numeric = [c for c in frame.columns if c not in ("case_id", "design_index", "case_json")
               and pd.api.types.is_numeric_dtype(frame[c])]
    with atomic_output(path.with_name("coverage.csv")) as tmp:
        frame[["case_id", *numeric]].to_csv(tmp, index=False)
    info: dict[str, Any] = {"method": cfg.method, "seed": cfg.seed,
                            "n_cases_requested": cfg.n_cases,
                            "n_cases": len(frame), "variables": list(cfg.variables)}
    if cfg.method == "adaptive":
        info["adaptive"] = {**cfg.adaptive.model_dump(mode="json"),
                            "n_rounds": int(frame["round"].max()),
                            "cases_per_round": [int(n) for n in
                                                frame["round"].value_counts().sort_index()]}
    _write_json(path.with_name("design.json"), info)
    return frame


def _is_configured_table(params: Params, cases_path: str | Path | None) -> bool:
    """Whether ``cases_path`` (None: the configured one) is ``sweep.cases_path``."""
    configured = Path(params.sweep.cases_path)
    return cases_path is None or Path(cases_path).resolve() == configured.resolve()


def adaptive_cache_dir(params: Params, cases_path: str | Path | None = None) -> Path:
    """``sweep.adaptive.cache_dir`` for the configured case table (``sweep.cases_path``);
    ``adaptive/`` beside the case table when unset or when the table goes elsewhere
    (``sweep design --out``: a command writes only under its outputs)."""
    cfg = params.sweep
    if cfg.adaptive.cache_dir is not None and _is_configured_table(params, cases_path):
        return Path(cfg.adaptive.cache_dir)
    return Path(cases_path or cfg.cases_path).parent / "adaptive"


def adaptive_targets(params: Params, *, progress: bool = False, case_fn: CaseFn = run_case,
                     fatigue_fn: CaseFn = fatigue_case,
                     cases_path: str | Path | None = None) -> TargetFn:
    """The adaptive design's target function: simulate and evaluate with the stages' code.

    The cases designed so far go through :func:`simulate_stage` and
    :func:`fatigue_stage` into ``<cache>/sweep`` and ``<cache>/fatigue``
    (``<cache>``: :func:`adaptive_cache_dir`). Resumable: a finished case is
    skipped, so an interrupted design continues where it stopped;
    ``sweep.failure_threshold`` applies to all of them. The dataset rows of
    the cases given then give the governing log10 damage rate per component
    type (:func:`drillfatigue.sweep.adaptive.case_targets`, the surrogate's
    target column and floor).
    """
    folder = OutputFolder(adaptive_cache_dir(params, cases_path), ADAPTIVE_KIND,
                          "sweep.adaptive.cache_dir")
    sweep_dir, fatigue_dir = folder.path / "sweep", folder.path / "fatigue"
    pending = folder.file("pending.parquet")
    sur = params.surrogate

    designed: list[pd.DataFrame] = []

    def target(cases: pd.DataFrame) -> pd.DataFrame:
        # every case designed so far goes to the stages (the finished ones are skipped), so
        # sweep.failure_threshold applies to the design, not to one small batch
        designed.append(cases)
        write_cases(pd.concat(designed, ignore_index=True).drop_duplicates("case_id"), pending)
        simulate_stage(params, cases_path=pending, sweep_dir=sweep_dir, progress=progress,
                       case_fn=case_fn)
        fatigue_stage(params, cases_path=pending, sweep_dir=sweep_dir, fatigue_dir=fatigue_dir,
                      progress=progress, fatigue_fn=fatigue_fn)
        ids = pd.Index(cases["case_id"], name="case_id")
        rows = build_dataset(cases, sweep_dir, fatigue_dir)
        if not len(rows):
            return pd.DataFrame(index=ids)
        return case_targets(rows, sur.target_column, sur.rate_floor_per_h,
                            sur.group_column).reindex(ids)

    return target


def adaptive_rows(params: Params, cases_path: str | Path | None = None) -> RowSource:
    """The row-level acquisitions' rows: the dataset rows of the cases finished in the
    adaptive design's cache (:func:`adaptive_targets`) and candidates' rows built from their
    inputs (:func:`drillfatigue.sweep.adaptive.template_rows`), on the surrogate's inputs."""
    root = adaptive_cache_dir(params, cases_path)
    sur = params.surrogate
    variables = tuple(params.sweep.variables)

    def finished(cases: pd.DataFrame) -> pd.DataFrame:
        rows = build_dataset(cases, root / "sweep", root / "fatigue")
        return rows.assign(case_id=rows[sur.group_column].astype(str)) if len(rows) else rows

    def candidates(cases: pd.DataFrame, done: pd.DataFrame) -> pd.DataFrame:
        return template_rows(cases, done, variables)

    return RowSource(finished=finished, candidates=candidates, features=tuple(sur.features),
                     categorical=tuple(sur.categorical), target_column=sur.target_column,
                     floor_per_h=sur.rate_floor_per_h)


def _runner_kwargs(params: Params, scheduler: str | None, n_workers: int | None,
                   progress: bool) -> dict[str, Any]:
    cfg = params.sweep
    return {"scheduler": scheduler or cfg.scheduler, "n_workers": n_workers or cfg.n_workers,
            "max_retries": cfg.max_retries, "failure_threshold": cfg.failure_threshold,
            "progress": progress}


def simulate_stage(params: Params, *, cases_path: str | Path | None = None,
                   sweep_dir: str | Path | None = None, scheduler: str | None = None,
                   n_workers: int | None = None, progress: bool = False,
                   case_fn: CaseFn = run_case) -> SweepReport:
    """Simulate every designed case not already done (resumable); see :func:`run_sweep`.

    With ``sweep.window.mode: converged`` and the simulator's case function, each
    case runs through :func:`drillfatigue.sweep.window.run_case_converged` (its
    inputs: the case and the window settings, so a change of either re-runs it).
    """
    cfg = params.sweep
    cases = cases_from_frame(read_cases(cases_path or cfg.cases_path))
    if cfg.window.mode == "converged" and case_fn is run_case:
        window = window_inputs(params)
        cases = [Case(c.case_id, {"case": c.inputs, "window": window}) for c in cases]
        case_fn = run_case_converged
    return run_sweep(cases, case_fn, sweep_dir or cfg.sweep_dir,
                     **_runner_kwargs(params, scheduler, n_workers, progress))


def fatigue_stage(params: Params, *, cases_path: str | Path | None = None,
                  sweep_dir: str | Path | None = None, fatigue_dir: str | Path | None = None,
                  scheduler: str | None = None, n_workers: int | None = None,
                  progress: bool = False, fatigue_fn: CaseFn = fatigue_case) -> SweepReport:
    """Evaluate fatigue of every simulated case (resumable; redone if its run or settings change).

    Cases whose simulation failed have no run folder and no fatigue task;
    they are counted as simulation failures in the dataset card.
    """
    cfg = params.sweep
    frame = read_cases(cases_path or cfg.cases_path)
    case_dicts = {cid: json.loads(t) for cid, t in zip(frame["case_id"], frame["case_json"],
                                                       strict=True)}
    tasks = fatigue_tasks(list(frame["case_id"]), sweep_dir or cfg.sweep_dir,
                          params.fatigue.model_dump(mode="json"), list(cfg.fatigue_criteria),
                          cfg.api_rp7g, case_dicts)
    return run_sweep([Case(cid, inputs) for cid, inputs in tasks], fatigue_fn,
                     fatigue_dir or cfg.fatigue_dir,
                     **_runner_kwargs(params, scheduler, n_workers, progress))


def dataset_stage(params: Params, *, cases_path: str | Path | None = None,
                  sweep_dir: str | Path | None = None, fatigue_dir: str | Path | None = None,
                  dataset_dir: str | Path | None = None,
                  keep: Sequence[str] = ()) -> dict[str, Any]:
    """Assemble ``damage.parquet``, the dataset card and metrics; return the metrics.

    Columns constant over the dataset go to ``constants.json`` except the design
    variables, the surrogate's configured columns and those in ``keep``."""
    cfg = params.sweep
    frame = read_cases(cases_path or cfg.cases_path)
    # The card's base case comes from the case table (first case; the design
    # variables are listed apart), so this stage reads no case section.
    base = json.loads(frame["case_json"].iloc[0]) if len(frame) else None
    design = {**cfg.model_dump(mode="json"), "criterion": params.surrogate.criterion}
    return write_dataset(frame, sweep_dir or cfg.sweep_dir, fatigue_dir or cfg.fatigue_dir,
                         dataset_dir or cfg.dataset_dir, design=design, base_case=base,
                         floor_per_h=params.surrogate.rate_floor_per_h,
                         keep=[*params.surrogate.features, *params.surrogate.categorical,
                               *keep])



def heldout_params(params: Params) -> Params:
    """``params`` with the ``sweep`` section turned into the held-out design's: the
    ``heldout`` section's size, seed and folders (Sobol for an adaptive training
    design), everything else (ranges, base case,
    boundaries, window rule, criteria, scheduler) the training sweep's."""
    h = params.heldout
    # an adaptive training design is tested on a space-filling one (Sobol of the held-out seed)
    method = "sobol" if params.sweep.method == "adaptive" else params.sweep.method
    sweep = params.sweep.model_copy(update={
        "method": method, "n_cases": h.n_cases, "seed": h.seed, "cases_path": h.cases_path,
        "sweep_dir": h.sweep_dir, "fatigue_dir": h.fatigue_dir, "dataset_dir": h.dataset_dir})
    return params.model_copy(update={"sweep": sweep})


def heldout_stage(params: Params, *, progress: bool = False, case_fn: CaseFn = run_case,
                  fatigue_fn: CaseFn = fatigue_case) -> dict[str, Any]:
    """Design, simulate, evaluate and assemble the held-out test set (``heldout`` section).

    The same functions as the training stages run on :func:`heldout_params`;
    designed cases whose id is in the training design (``sweep.cases_path``,
    when it exists) are dropped before anything runs, so training and test
    share no case, and the test table keeps every column of the training
    table (``sweep.dataset_dir``, when it exists) even where it is constant.
    Returns the held-out dataset's metrics plus ``n_cases_shared_with_training_dropped``.
    """
    if params.heldout.seed == params.sweep.seed:
        raise InputError("heldout.seed", f"equals sweep.seed ({params.sweep.seed}): the held-out "
                         "design would repeat the training design",
                         "a seed other than sweep.seed")
    hp = heldout_params(params)
    cfg = hp.sweep
    frame = design_cases(cfg, base_case_from_params(hp))
    train_path = Path(params.sweep.cases_path)
    shared = 0
    if train_path.is_file():
        train_ids = set(read_cases(train_path)["case_id"])
        keep = ~frame["case_id"].isin(train_ids)
        shared = int((~keep).sum())
        frame = frame[keep].reset_index(drop=True)
    if not len(frame):
        raise InputError("heldout.n_cases", "every held-out case is also a training case",
                         "a design with cases of its own (another seed, more cases)")
    path = write_cases(frame, cfg.cases_path)
    simulate_stage(hp, cases_path=path, progress=progress, case_fn=case_fn)
    fatigue_stage(hp, cases_path=path, progress=progress, fatigue_fn=fatigue_fn)
    # the test table has every column of the training table, constant here or not
    train_table = Path(params.sweep.dataset_dir) / "damage.parquet"
    keep = pq.read_schema(train_table).names if train_table.is_file() else []
    metrics = dataset_stage(hp, cases_path=path, keep=keep)
    return {**metrics, "n_cases_shared_with_training_dropped": shared}
