"""Carry the research case files across a change of code that leaves their rows unchanged.

Every case file's marker names the *physics digest* of the code that wrote it
(:func:`drillfatigue.sweep.research.physics_digest`), and a research run refuses case
files of another digest: a change to any module of
:data:`~drillfatigue.sweep.research.PHYSICS_MODULES` (a faster kernel, a module moved)
would otherwise leave thousands of committed cases unusable. ``drillfatigue dataset
restamp`` (:func:`restamp`) re-runs a sample of the committed cases at the current code
in a scratch folder and compares each re-run case's rows with its committed file value
for value and dtype for dtype (all columns but
:data:`~drillfatigue.sweep.research.MEASURED_COLUMNS`, the machine's wall time). Only
when every sampled case is equal does it record the current digest as equivalent in
``<root>/digests.json``; one difference refuses (exit code 2) with the case, the column
and the largest relative difference, and nothing is written.

The case files are not rewritten: each keeps the digest and commit that made it, and
``digests.json`` lists the digests found equal, each with the digest it was checked
against, the commit, the cases re-run and the rows compared. A research run (and the
``research_dataset`` stage) accepts a case file of any digest of that list when its own
digest is in it.

The sample is drawn per split in proportion to the split's cases, ordered by a hash of
the new digest and the case id (another change samples other cases), and alternates
between cases whose window was extended by the window rule and cases that ended at the
first window, so both paths of the window rule are re-run.
"""

from __future__ import annotations

import hashlib
import json
import math
import tempfile
import time
from pathlib import Path
from typing import Any

import numpy as np
import pyarrow.parquet as pq

from drillfatigue.config import Params
from drillfatigue.errors import InputError
from drillfatigue.files import OutputFolder, atomic_write_text
from drillfatigue.sweep.design import read_cases
from drillfatigue.sweep.research import (LAYOUT_KEY, _commit, LINEAGE_FILE, MEASURED_COLUMNS,
                                         RESEARCH_KIND, SPLITS, equivalent_digests,
                                         physics_digest, read_case_file, read_lineage,
                                         read_marker, run_research)

__all__ = ["compare_case_files", "restamp", "restamp_sample"]


def _window_s(path: Path) -> float:
    """The simulated duration of a case file (a constant column of its layout)."""
    layout = json.loads(pq.read_metadata(path).metadata[LAYOUT_KEY])
    value = layout["constants"].get("duration_s")
    return float(value) if value is not None else float("nan")


def restamp_sample(root: Path, digest: str, n_cases: int) -> dict[str, list[str]]:
    """Case ids to re-run, per split (see the module doc for the rule)."""
    files = {s: sorted((root / "cases" / s).glob("*.parquet")) for s in SPLITS}
    total = sum(len(v) for v in files.values())
    if total == 0:
        raise InputError("--out", f"{root} holds no case files", "a research folder with cases")
    n_cases = min(n_cases, total)
    counts = {s: round(n_cases * len(files[s]) / total) for s in SPLITS}
    for s in SPLITS:  # every split that has cases gets at least one
        if files[s] and counts[s] == 0:
            counts[s] = 1
    sample: dict[str, list[str]] = {}
    for split in SPLITS:
        ranked = sorted(files[split], key=lambda p: hashlib.sha256(
            f"{digest}:{p.stem}".encode()).hexdigest())
        windows = {p: _window_s(p) for p in ranked}
        first = min((w for w in windows.values() if math.isfinite(w)), default=math.nan)
        strata = [[p for p in ranked if windows[p] > first],
                  [p for p in ranked if not windows[p] > first]]
        chosen: list[str] = []
        while len(chosen) < min(counts[split], len(ranked)):
            for stratum in strata:
                if stratum and len(chosen) < counts[split]:
                    chosen.append(stratum.pop(0).stem)
        sample[split] = sorted(chosen)
    return sample


def compare_case_files(committed: Path, rerun: Path) -> str | None:
    """None when the two case files hold the same rows (all columns but the measured
    ones, values and dtypes); else one line naming the first difference."""
    a, b = read_case_file(committed), read_case_file(rerun)
    a = a.drop(columns=[c for c in MEASURED_COLUMNS if c in a.columns])
    b = b.drop(columns=[c for c in MEASURED_COLUMNS if c in b.columns])
    if list(a.columns) != list(b.columns):
        extra = sorted(set(a.columns) ^ set(b.columns))
        return f"columns differ ({', '.join(extra[:5]) or 'order'})"
    if len(a) != len(b):
        return f"{len(b)} rows, committed {len(a)}"
    for col in a.columns:
        if a[col].dtype != b[col].dtype:
            return f"column {col}: dtype {b[col].dtype}, committed {a[col].dtype}"
        x, y = a[col].to_numpy(), b[col].to_numpy()
        if x.dtype.kind == "f":
            same = np.array_equal(x, y, equal_nan=True) and np.array_equal(
                np.signbit(x), np.signbit(y))
        else:
            same = bool((a[col].isna() == b[col].isna()).all()
                        and (a[col][a[col].notna()] == b[col][b[col].notna()]).all())
        if not same:
            if x.dtype.kind == "f":
                with np.errstate(divide="ignore", invalid="ignore"):
                    rel = np.nanmax(np.abs(y - x) / np.maximum(np.abs(x), 1e-300))
                return f"column {col}: largest relative difference {rel:.3g}"
            return f"column {col}: values differ"
    return None


def restamp(params: Params, root: str | Path = "data/research", *, n_cases: int = 16,
            n_workers: int = 2, progress: bool = False) -> dict[str, Any]:
    """Re-run a sample of the committed cases at the current code; when all are equal,
    record the current physics digest as equivalent in ``<root>/digests.json``.

    Returns what was done: ``status`` ``"current"`` (the digest is already accepted,
    nothing run) or ``"restamped"``, the digest, the cases re-run and the rows compared.

    Raises
    ------
    InputError
        The folder holds no case files, case files of digests not known to be
        equivalent, or a re-run case differs from its committed file (the case and the
        first difference are named); nothing is written then.
    """
    if n_cases < 1:
        raise InputError("--sample", f"must be >= 1, got {n_cases}", ">= 1")
    folder = OutputFolder(root, RESEARCH_KIND, "--out", (LINEAGE_FILE,))
    root = folder.path
    digest = physics_digest()
    found: dict[str, int] = {}
    for path in sorted(root.glob("cases/*/*.parquet")):
        marker = read_marker(path)
        if marker is not None:
            found[marker["physics_digest"]] = found.get(marker["physics_digest"], 0) + 1
    if not found:
        raise InputError("--out", f"{root} holds no case files", "a research folder with cases")
    lineage = read_lineage(root)
    if set(found) <= equivalent_digests(root, digest):
        return {"status": "current", "physics_digest": digest, "n_cases": 0, "n_rows": 0}
    previous = [e["physics_digest"] for e in lineage] if lineage else sorted(found)
    if not set(found) <= set(previous) or (not lineage and len(found) != 1):
        raise InputError("--out", f"{root} holds case files of {len(found)} physics digests "
                         "not known to be equivalent", "case files of one digest, or of "
                         "the digests of its digests.json")
    sample = restamp_sample(root, digest, n_cases)
    designs = {s: read_cases(root / "design" / f"{s}.parquet") for s in SPLITS}
    subset = {s: designs[s][designs[s]["case_id"].isin(sample[s])].reset_index(drop=True)
              for s in SPLITS}
    t0 = time.perf_counter()
    n_rows = 0
    with tempfile.TemporaryDirectory(prefix="drillfatigue-restamp-") as scratch:
        res = run_research(params, Path(scratch) / "research", n_cases=len(subset["train"]),
                           heldout_cases=len(subset["heldout"]), n_workers=n_workers,
                           progress=progress, designs=subset)
        if res["n_failed"]:
            raise InputError("--out", f"{res['n_failed']} re-run case(s) failed at the current "
                             "code", "a change that runs every committed case")
        for split in SPLITS:
            for cid in sample[split]:
                committed = root / "cases" / split / f"{cid}.parquet"
                rerun = Path(scratch) / "research" / "cases" / split / f"{cid}.parquet"
                old, new = read_marker(committed) or {}, read_marker(rerun) or {}
                if old.get("inputs_sha256") != new.get("inputs_sha256"):
                    raise InputError("--params", f"case {split}/{cid} was made with other "
                                     "settings (window rule, fatigue, criteria) than these",
                                     "the params the research run used")
                diff = compare_case_files(committed, rerun)
                if diff is not None:
                    raise InputError("--out", f"case {split}/{cid} re-run at physics digest "
                                     f"{digest[:12]} differs from its committed file: {diff}",
                                     "a change that leaves the rows bit for bit, or a new "
                                     "dataset version (a fresh --out)")
                n_rows += len(read_case_file(committed))
    entries = list(lineage) if lineage else [
        {"physics_digest": d, "how": "case files written at this digest"} for d in previous]
    entries.append({"physics_digest": digest, "how": "re-run equal", "checked_against":
                    sorted(set(found)), "commit": _commit(), "cases": sample, "n_rows": n_rows,
                    "at_utc": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime())})
    atomic_write_text(folder.file(LINEAGE_FILE),
                      json.dumps({"equivalent_digests": entries}, indent=2) + "\n")
    return {"status": "restamped", "physics_digest": digest,
            "n_cases": sum(len(v) for v in sample.values()), "n_rows": n_rows,
            "wall_s": time.perf_counter() - t0}
