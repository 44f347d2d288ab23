"""The research dataset's card (``README.md``) and its Croissant metadata (``croissant.json``).

The card is a Hugging Face dataset card: YAML front matter (licence, the two
splits' files, typed features, the column roles and units) and a markdown body
for the reader (version, licence, generating command and commit, splits by
case, inputs / targets / post-run columns with units, censoring, the
replicate noise ceiling, loading and scoring). ``croissant.json`` describes the
same files in Croissant 1.0 JSON-LD (MLCommons, "Croissant format
specification", version 1.0): one ``cr:FileObject`` per split with its SHA-256
and one ``cr:RecordSet`` per split whose ``cr:Field`` s extract the parquet
columns.
"""

from __future__ import annotations

import hashlib
import json
import subprocess
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import pandas as pd
import yaml

from drillfatigue.benchmark.splits import (DATASET_VERSION, DESIGN_INPUTS, GROUP_COLUMN,
                                           KEY_COLUMNS, SPLIT_COLUMN, SPLITS, hf_dtype,
                                           load_splits, split_path)
from drillfatigue.files import atomic_write_text
from drillfatigue.sweep.dataset import DATA_LICENSE, _describe, column_roles, unit_of
from drillfatigue.sweep.research import read_lineage, read_marker

CARD_FILE = "README.md"
CROISSANT_FILE = "croissant.json"
CROISSANT_CONFORMS_TO = "http://mlcommons.org/croissant/1.0"
#: The dataset's address: the card's path in the repository (the project names no public
#: address; a publisher of the dataset replaces it with theirs).
DATASET_URL = "data/research/dataset/README.md"
DATASET_NAME = "drillfatigue-research"
#: Where the docs say how the dataset is generated.
GENERATION_DOCS = "docs/pipeline.md#generating-the-research-dataset"
#: Croissant data type of each Hugging Face value type.
_CROISSANT_TYPES = {"float64": "sc:Float", "int64": "sc:Integer", "bool": "sc:Boolean",
                    "string": "sc:Text"}
#: JSON-LD context of Croissant 1.0 (the specification's example context).
CROISSANT_CONTEXT: dict[str, Any] = {
    "@language": "en", "@vocab": "https://schema.org/", "sc": "https://schema.org/",
    "cr": "http://mlcommons.org/croissant/", "rai": "http://mlcommons.org/croissant/RAI/",
    "dct": "http://purl.org/dc/terms/",
    "citeAs": "cr:citeAs", "column": "cr:column", "conformsTo": "dct:conformsTo",
    "data": {"@id": "cr:data", "@type": "@json"},
    "dataType": {"@id": "cr:dataType", "@type": "@vocab"},
    "examples": {"@id": "cr:examples", "@type": "@json"},
    "extract": "cr:extract", "field": "cr:field", "fileProperty": "cr:fileProperty",
    "fileObject": "cr:fileObject", "fileSet": "cr:fileSet", "format": "cr:format",
    "includes": "cr:includes", "isLiveDataset": "cr:isLiveDataset", "jsonPath": "cr:jsonPath",
    "key": "cr:key", "md5": "cr:md5", "parentField": "cr:parentField", "path": "cr:path",
    "recordSet": "cr:recordSet", "references": "cr:references", "regex": "cr:regex",
    "repeated": "cr:repeated", "replace": "cr:replace", "separator": "cr:separator",
    "source": "cr:source", "subField": "cr:subField", "transform": "cr:transform",
}


def roles_of(columns: list[str]) -> dict[str, str]:
    """Role of each column: ``id`` (case id), ``key`` (joint, location), ``split``,
    ``input``, ``target``, ``post_run``
    (:func:`drillfatigue.sweep.dataset.column_roles`)."""
    roles = column_roles(columns, list(DESIGN_INPUTS))
    for col in columns:
        if col == SPLIT_COLUMN:
            roles[col] = "split"
        elif col in KEY_COLUMNS and col != GROUP_COLUMN and col != "location":
            roles[col] = "key"
    return roles


def describe(column: str) -> str:
    """One line on what a column holds."""
    if column == SPLIT_COLUMN:
        return "split of the row: train or heldout (the file's split)"
    return _describe(column, list(DESIGN_INPUTS))


def sha256_of(path: Path) -> str:
    """SHA-256 hex digest of a file's bytes."""
    h = hashlib.sha256()
    with open(path, "rb") as f:
        for block in iter(lambda: f.read(1 << 20), b""):
            h.update(block)
    return h.hexdigest()


def git_commit(repo: str | Path = ".") -> str:
    """HEAD commit of the repository at ``repo``, or ``unknown`` outside a git clone."""
    try:
        out = subprocess.run(["git", "-C", str(repo), "rev-parse", "HEAD"], capture_output=True,
                             text=True, check=True, timeout=30)
    except (OSError, subprocess.SubprocessError):
        return "unknown"
    return out.stdout.strip() or "unknown"


def commit_date(commit: str, repo: str | Path = ".") -> str | None:
    """ISO date (YYYY-MM-DD) of ``commit`` in the repository, or None when unknown."""
    try:
        out = subprocess.run(["git", "-C", str(repo), "show", "-s", "--format=%cs", commit],
                             capture_output=True, text=True, check=True, timeout=30)
    except (OSError, subprocess.SubprocessError):
        return None
    return out.stdout.strip() or None


def case_provenance(dataset_dir: str | Path) -> dict[str, Any] | None:
    """What the research sweep's case files beside the dataset folder (``../cases``) say
    made them: the physics digest(s) and the commit of each case, or None when there are
    no case files (a dataset not assembled by the research sweep)."""
    cases = Path(dataset_dir).parent / "cases"
    digests: dict[str, int] = {}
    commits: dict[str, int] = {}
    for path in sorted(cases.glob("*/*.parquet")):
        marker = read_marker(path)
        if marker is None:
            continue
        digests[marker["physics_digest"]] = digests.get(marker["physics_digest"], 0) + 1
        commits[marker["commit"]] = commits.get(marker["commit"], 0) + 1
    if not digests:
        return None
    lineage = read_lineage(cases.parent)
    return {"physics_digests": digests, "commits": commits,
            "equivalent": [e for e in lineage if e["physics_digest"] not in digests]}


def read_spread(path: str | Path | None) -> dict[str, Any] | None:
    """The replicates stage's ``spread.json``, or None when there is none."""
    if path is None or not Path(path).is_file():
        return None
    return json.loads(Path(path).read_text(encoding="utf-8"))


def croissant(frames: Mapping[str, pd.DataFrame], dataset_dir: str | Path, *,
              rate_floor_per_h: float, horizon_h: float, commit: str, command: str
              ) -> dict[str, Any]:
    """Croissant 1.0 JSON-LD of the dataset folder (one file object and one record set
    per split; fields typed, units in their descriptions)."""
    files, record_sets = [], []
    for split, frame in frames.items():
        path = split_path(split, dataset_dir)
        file_id = f"{split}.parquet"
        files.append({"@type": "cr:FileObject", "@id": file_id, "name": file_id,
                      "description": f"the {split} split, one row per case, joint and location",
                      "contentUrl": file_id, "encodingFormat": "application/x-parquet",
                      "sha256": sha256_of(path)})
        fields = []
        for col in frame.columns:
            unit = unit_of(col)
            text = describe(col) + (f" [{unit}]" if unit not in ("-", "1") else "")
            fields.append({"@type": "cr:Field", "@id": f"{split}/{col}", "name": col,
                           "description": text,
                           "dataType": _CROISSANT_TYPES[hf_dtype(frame[col])],
                           "source": {"fileObject": {"@id": file_id},
                                      "extract": {"column": col}}})
        record_sets.append({"@type": "cr:RecordSet", "@id": split, "name": split,
                            "description": f"{frame[GROUP_COLUMN].nunique()} cases, "
                                           f"{len(frame)} rows",
                            "key": [{"@id": f"{split}/{k}"} for k in KEY_COLUMNS],
                            "field": fields})
    doc: dict[str, Any] = {
        "@context": CROISSANT_CONTEXT, "@type": "sc:Dataset", "name": DATASET_NAME,
        "description": "Fatigue damage rate of drill-string component locations (pipe body, "
                       "connection, upset) simulated by drillfatigue's drill-string dynamics "
                       "and fatigue chain over a designed range of operating conditions, wells "
                       "and bottom-hole assemblies; splits by case. Target: log10 of "
                       f"damage_rate_per_h_<criterion> floored at {rate_floor_per_h:g} per h; "
                       f"lives beyond {horizon_h:g} h are answered 'longer than'. Generated by "
                       f"`{command}` at commit {commit}.",
        "conformsTo": CROISSANT_CONFORMS_TO, "version": DATASET_VERSION,
        "license": f"https://spdx.org/licenses/{DATA_LICENSE}.html",
        "url": DATASET_URL,
        "citeAs": "drillfatigue contributors, drillfatigue: drill-string dynamics in deviated "
                  "wells with fatigue prognosis (CITATION.cff)",
        "isLiveDataset": False,
        "keywords": ["drilling", "drill string", "fatigue", "simulation", "tabular regression",
                     "surrogate model"],
        "creator": {"@type": "sc:Organization", "name": "drillfatigue contributors"},
        "distribution": files, "recordSet": record_sets,
    }
    published = commit_date(commit)
    if published is not None:  # the day of the commit that generated the data
        doc["datePublished"] = published
    return doc


def _front_matter(frames: Mapping[str, pd.DataFrame], roles: Mapping[str, str], *,
                  rate_floor_per_h: float, horizon_h: float) -> list[str]:
    first = next(iter(frames.values()))
    n_rows = sum(len(f) for f in frames.values())
    size = ("n<1K" if n_rows < 1_000 else "1K<n<10K" if n_rows < 10_000
            else "10K<n<100K" if n_rows < 100_000 else "100K<n<1M")
    meta = {
        "license": DATA_LICENSE.lower(),
        "pretty_name": "drillfatigue research dataset",
        "tags": ["drilling", "drill-string", "fatigue", "simulation", "tabular-regression"],
        "task_categories": ["tabular-regression"],
        "size_categories": [size],
        "configs": [{"config_name": "default",
                     "data_files": [{"split": s, "path": f"{s}.parquet"} for s in frames]}],
        "dataset_info": {
            "features": [{"name": c, "dtype": hf_dtype(first[c])} for c in first.columns],
            "splits": [{"name": s, "num_examples": int(len(f))} for s, f in frames.items()]},
        "drillfatigue": {
            "version": DATASET_VERSION,
            "group_column": GROUP_COLUMN,
            "key_columns": list(KEY_COLUMNS),
            "split_rule": "split by case_id: rows of one case share one simulation",
            "n_cases": {s: int(f[GROUP_COLUMN].nunique()) for s, f in frames.items()},
            "censoring_floor_per_h": float(rate_floor_per_h),
            "horizon_h": float(horizon_h),
            "columns": {c: {"role": roles[c], "unit": unit_of(c)} for c in first.columns},
        },
    }
    return ["---", yaml.safe_dump(meta, sort_keys=False, allow_unicode=True).rstrip(), "---", ""]


def _column_table(columns: list[str]) -> list[str]:
    lines = ["| column | unit | description |", "|---|---|---|"]
    lines += [f"| `{c}` | {unit_of(c)} | {describe(c)} |" for c in columns]
    return lines


def dataset_card(frames: Mapping[str, pd.DataFrame], *, rate_floor_per_h: float,
                 horizon_h: float, commit: str, command: str,
                 spread: Mapping[str, Any] | None = None,
                 provenance: Mapping[str, Any] | None = None) -> str:
    """The card's text (front matter and body) of the splits in ``frames``."""
    first = next(iter(frames.values()))
    columns = list(first.columns)
    roles = roles_of(columns)
    lines = _front_matter(frames, roles, rate_floor_per_h=rate_floor_per_h, horizon_h=horizon_h)
    by_role = {r: [c for c in columns if roles[c] == r] for r in set(roles.values())}
    lines += [
        "# drillfatigue research dataset",
        "",
        f"Version {DATASET_VERSION}. Written by `drillfatigue benchmark card`; do not edit by hand.",
        "",
        "Fatigue damage of drill-string component locations (pipe body, connection, upset run-out)",
        "under designed operating conditions, wells and bottom-hole assemblies: rigid-segment",
        "drill-string dynamics in a deviated well, then rainflow, S-N curves and Miner's rule with",
        "multiaxial critical-plane criteria, the API RP7G estimate beside them. For training and",
        "benchmarking surrogate models of damage rate against the inputs (docs/dataset.md).",
        "",
        "## Licence",
        "",
        f"The data are licensed under {DATA_LICENSE} (attribution: cite the project, see",
        "`CITATION.cff`). The code that generates, loads and scores them is under the project's",
        "MIT licence (`LICENSE`).",
        "",
        "## Generation",
        "",
        f"- command: `{command}` ({GENERATION_DOCS})",
        f"- commit: `{commit}`",
        *_provenance_lines(provenance),
        "",
        "## Splits (by case)",
        "",
        "All rows of one case come from one simulation: they share its inputs, dynamics and",
        "window, and their damage rates move together. The splits are by `case_id` and the",
        "held-out cases come from a design of their own seed; no case is in both.",
        "",
        "| split | file | cases | rows |",
        "|---|---|---|---|",
    ]
    for s, f in frames.items():
        lines.append(f"| {s} | `{s}.parquet` | {f[GROUP_COLUMN].nunique()} | {len(f)} |")
    lines += ["", "## Columns", "",
              "Units follow the column names (SI unless the name says otherwise). The row's keys",
              "are `case_id`, `joint` (0 nearest the bit) and `location`.", "",
              "### Inputs", "",
              "The design's inputs (what a case's simulation was asked to do), then the",
              "location's component, position and the hole geometry around it.", ""]
    lines += _column_table([c for c in columns if roles[c] in ("input", "key")])
    lines += ["", "### Targets", "",
              "Miner damage per hour of rotation, life in hours and the critical-plane angle per",
              "criterion (`matake` is the surrogate's; `api_rp7g` is the industry baseline,",
              "defined on pipe bodies only).", ""]
    lines += _column_table(by_role.get("target", []))
    lines += ["", "### Post-run columns", "",
              "What the simulation did. They are not inputs: a model that uses them is answered",
              "by the simulation it replaces.", ""]
    lines += _column_table(by_role.get("post_run", []))
    lines += [
        "", "## Censoring", "",
        "A location with no damaging cycle in the window has a rate of 0. The benchmark's",
        f"target is log10 of the rate floored at {rate_floor_per_h:g} per h",
        f"(`surrogate.rate_floor_per_h`), and lives beyond the horizon of {horizon_h:g} h",
        "(`surrogate.horizon_h`) are answered \"longer than the horizon\": scored as a",
        "classification, not as a number (docs/surrogate.md).", "",
        "## Replicate noise ceiling", "",
    ]
    if spread:
        lines += [
            f"Runs of the same case with rpm moved by {spread.get('rel_step')} (relative) land in",
            "different states of the string's dynamics; their spread bounds what any model can",
            f"reach on this data: sigma of log10 damage rate {spread.get('sigma_log10', float('nan')):.3f}",
            f"decades, factor-2 ceiling {spread.get('ceiling_factor2_fraction', float('nan')):.3f}",
            f"({spread.get('n_cases')} cases x {spread.get('n_replicates')} runs, the replicates",
            "stage's `spread.json`)."]
    else:
        lines += ["Not measured for this dataset (no replicates stage output was given)."]
    lines += [
        "", "## Loading and scoring", "",
        "```python",
        "from drillfatigue.benchmark import load_split, load_datasets",
        "train = load_split(\"train\")            # pandas DataFrame",
        "splits = load_datasets()                # Hugging Face DatasetDict",
        "from drillfatigue.benchmark.torch_dataset import load_torch_splits",
        "torch_splits = load_torch_splits()      # torch Datasets, codes shared",
        "```", "",
        "Score a prediction file on the held-out split:",
        "`drillfatigue benchmark score --predictions PRED.parquet` (docs/dataset.md).",
        "Machine-readable metadata: the YAML header above and `croissant.json` (Croissant 1.0).",
        "",
    ]
    return "\n".join(lines)


def _provenance_lines(provenance: Mapping[str, Any] | None) -> list[str]:
    if not provenance:
        return []
    digests = ", ".join(f"`{d[:16]}`" for d in provenance["physics_digests"])
    commits = ", ".join(f"`{c[:7]}` ({n})" for c, n in provenance["commits"].items())
    lines = [f"- physics digest: {digests} (SHA-256 over the source of the modules that decide a",
             "  case's rows, `drillfatigue.sweep.research.PHYSICS_MODULES`; a run at a commit",
             "  of another digest refuses these case files unless `../digests.json` lists it)",
             f"- case files written at commits (cases): {commits}; a stopped run was continued",
             "  from the committed case files, at the same digest"]
    for entry in provenance.get("equivalent", []):
        n = sum(len(v) for v in entry.get("cases", {}).values())
        lines += [f"- the same rows at physics digest `{entry['physics_digest'][:16]}`: {n} cases",
                  f"  re-run bit for bit on top of commit `{str(entry.get('commit'))[:7]}` "
                  "(`drillfatigue dataset restamp`)"]
    return lines


def write_card(dataset_dir: str | Path, *, rate_floor_per_h: float, horizon_h: float,
               command: str, commit: str | None = None,
               spread_path: str | Path | None = None) -> tuple[Path, Path]:
    """Write ``README.md`` and ``croissant.json`` into the dataset folder.

    The folder belongs to the research sweep, which writes the splits; the card
    writes only these two files (atomically), from the splits it finds.

    Returns
    -------
    card, croissant : Path
    """
    frames = load_splits(dataset_dir)
    commit = commit or git_commit()
    spread = read_spread(spread_path)
    card = dataset_card(frames, rate_floor_per_h=rate_floor_per_h, horizon_h=horizon_h,
                        commit=commit, command=command, spread=spread,
                        provenance=case_provenance(dataset_dir))
    meta = croissant(frames, dataset_dir, rate_floor_per_h=rate_floor_per_h, horizon_h=horizon_h,
                     commit=commit, command=command)
    out = Path(dataset_dir)
    atomic_write_text(out / CARD_FILE, card)
    atomic_write_text(out / CROISSANT_FILE, json.dumps(meta, indent=2, allow_nan=False) + "\n")
    return out / CARD_FILE, out / CROISSANT_FILE


__all__ = ["CARD_FILE", "CROISSANT_FILE", "croissant", "dataset_card", "write_card", "SPLITS"]
