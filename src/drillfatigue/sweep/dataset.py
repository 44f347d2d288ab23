"""Assemble the damage dataset of a sweep, its dataset card, and raw-history exports.

``damage.parquet`` has one row per (case, component location): the design
inputs (columns named by their dotted config path; the field name carries
the unit), the location (joint, component, MD, distance from the bit), the
case's summary dynamics, and per fatigue criterion the damage rate per hour,
the life in hours and the critical-plane angle. The API RP7G (Lubinski /
Hansford-Lubinski) estimate is the criterion ``api_rp7g``, so its damage rate
``damage_rate_per_h_api_rp7g`` sits beside the dynamic criteria.

Summary dynamics are read from the run's ``summary.json`` (top level, or one
level down, e.g. ``events.bit_bounce_count``; peak torque also from
``figures.surface_torque_Nm`` min/max); rms and peak surface torque fall back
to ``channels.parquet`` when the summary lacks them.
A figure the simulator does not report is NaN (``whirl_class``: missing
value), never zero.
"""

from __future__ import annotations

import json
import math
import platform
import re
import shutil
from collections.abc import Mapping, Sequence
from importlib import metadata
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd
import pyarrow.parquet as pq
import yaml

from drillfatigue import rundir
from drillfatigue.errors import InputError
from drillfatigue.files import OutputFolder, atomic_output, atomic_write_text
from drillfatigue.sweep.runner import latest_failures
from drillfatigue.sweep.design import RIG_PATHS
from drillfatigue.sweep.window import WINDOW_FILE
from drillfatigue.well.features import DESCRIPTIONS as POSITION_DESCRIPTIONS
from drillfatigue.well.features import POSITION_COLUMNS

#: Kind of the ownership marker of a history export folder.
EXPORT_KIND = "export"
#: Kind of the ownership marker of the dataset folder, and the files written there.
DATASET_KIND = "dataset"
DATASET_FILES = ("damage.parquet", "README.md", "constants.json", "metrics.json",
                 "plots/damage_rate_hist.csv")
#: The columns with one value in every row (value, unit, description), beside the table.
CONSTANTS_FILE = "constants.json"
#: Licence of the generated data (the code is MIT, ``LICENSE``).
DATA_LICENSE = "CC-BY-4.0"
#: Name prefixes of the fatigue-result columns (one per criterion).
TARGET_PREFIXES = ("damage_rate_per_h_", "life_h_", "critical_angle_deg_")

__all__ = [
    "ACHIEVED_COLUMNS",
    "DYNAMICS_COLUMNS",
    "achieved_outputs",
    "build_dataset",
    "column_roles",
    "dataset_card",
    "dataset_metrics",
    "export_histories",
    "split_constants",
    "summary_dynamics",
    "unit_of",
    "write_dataset",
]

KEY_COLUMNS = ("joint", "component", "component_type", "location", "md_m", "s_from_bit_m",
               *POSITION_COLUMNS)
INPUT_SECTIONS = ("well", "operation", "friction", "bit")
PIVOT_VALUES = ("damage_rate_per_h", "life_h", "critical_angle_deg")
DYNAMICS_COLUMNS: dict[str, str] = {
    "rms_surface_torque_Nm": "rms of the surface (top-drive) torque over the window",
    "peak_surface_torque_Nm": "largest |surface torque| over the window",
    "stick_slip_severity": "(max - min) / mean bit speed over the window, dimensionless",
    "whirl_class": "whirl class of the run (simulator's event detection)",
    "max_contact_force_N": "largest wall contact force of any segment",
    "bit_bounce_count": "number of times WOB reached zero (bit bounce)",
    "duration_s": "simulated time of the run (rpm ramp included; the window used, "
                  "sweep.window)",
    "wall_time_s": "wall-clock time of the simulation",
}
#: What the rig boundaries achieved over the recorded window (means of ``channels.parquet``
#: from ``recording.start_s``): results of the run, never inputs.
ACHIEVED_COLUMNS: dict[str, str] = {
    "achieved_mean_wob_N": "mean weight on bit over the recorded window (a result of the "
                           "ROP set-point and the bit law)",
    "achieved_mean_rop_m_per_s": "mean rate of penetration the bit cut over the recorded window",
    "achieved_mean_surface_torque_Nm": "mean surface (top-drive) torque over the recorded window",
    "achieved_on_bottom_fraction": "fraction of the recorded window with the bit on bottom "
                                   "(WOB > 0)",
}
#: The window chosen per case (``window.json`` of the run, ``sweep.window.mode: converged``).
WINDOW_COLUMNS: dict[str, str] = {
    "window_converged": "1 when the governing damage rate changed by less than "
                        "sweep.window.tol_rel over the last third of the record, 0 when the "
                        "window reached sweep.window.max_s first",
    "window_rate_change_rel": "relative change of the governing location's uniaxial damage "
                              "rate over the last third of the recorded window",
}
#: Every per-run column :func:`summary_dynamics` gives, with its description.
RUN_COLUMNS: dict[str, str] = {**DYNAMICS_COLUMNS, **ACHIEVED_COLUMNS, **WINDOW_COLUMNS}
_ACHIEVED_CHANNELS = {"achieved_mean_wob_N": "wob_N", "achieved_mean_rop_m_per_s": "rop_m_per_s",
                      "achieved_mean_surface_torque_Nm": "surface_torque_Nm"}
# Longest first: a compound suffix before its tail (``_N_s_per_m2`` before ``_m2``).
_UNIT_SUFFIXES: tuple[tuple[str, str], ...] = (
    ("_m_per_s_per_N", "(m/s)/N"), ("_m_per_s2_per_N", "(m/s²)/N"),
    ("_m_per_N_sqrt_s", "m/(N·√s)"), ("_N_m_s_per_m", "N·m·s/m"), ("_Nm_s_per_rad", "N·m·s/rad"),
    ("_N_s_per_m2", "N·s/m²"), ("_N_s_per_m", "N·s/m"), ("_s2_per_rad2", "s²/rad²"),
    ("_Nm_per_rad", "N·m/rad"), ("_s_per_rad", "s/rad"), ("_N_per_m", "N/m"),
    ("_kg_m2", "kg·m²"), ("_m_per_s2", "m/s²"), ("_rad_s", "rad/s"),
    ("_deg_per_30m", "deg/30 m"), ("_m_per_s", "m/s"), ("_m_per_h", "m/h"),
    ("_kg_per_m3", "kg/m³"), ("_per_h", "1/h"), ("_Nm", "N·m"), ("_kN", "kN"),
    ("_N", "N"), ("_Pa", "Pa"), ("_MPa", "MPa"), ("_deg", "deg"), ("_rad", "rad"),
    ("_mm", "mm"), ("_m", "m"), ("_s", "s"), ("_h", "h"), ("_kg", "kg"), ("_Hz", "Hz"),
    ("rpm", "rev/min"), ("_count", "count"), ("_fraction", "1"), ("_rel", "1"),
    ("_severity", "1"),
)


#: Dimensionless quantities whose names carry no unit suffix.
_DIMENSIONLESS = frozenset({"mu_dynamic", "mu_static", "mu_axial", "mu0", "threshold_band",
                            "shear_coefficient", "added_mass_coefficient"})


def unit_of(column: str) -> str:
    """Unit of a column from its name's suffix (project naming convention): ``1`` for a
    dimensionless quantity, ``-`` for what is not a quantity (ids, categories, flags)."""
    leaf = column.rsplit(".", 1)[-1]
    if leaf in _DIMENSIONLESS:
        return "1"
    for value in PIVOT_VALUES:  # damage_rate_per_h_<criterion> -> damage_rate_per_h
        if leaf.startswith(value + "_"):
            leaf = value
    for suffix, unit in _UNIT_SUFFIXES:
        if leaf.endswith(suffix):
            return unit
    return "-"


def _criterion_name(name: Any) -> str:
    return re.sub(r"[^a-z0-9]+", "_", str(name).lower()).strip("_")


def _lookup(summary: Mapping[str, Any], name: str) -> Any:
    """``summary[name]``, else the first ``summary[<section>][name]`` (events, figures ...)."""
    if name in summary:
        return summary[name]
    for value in summary.values():
        if isinstance(value, Mapping) and name in value:
            return value[name]
    return None


def summary_dynamics(run_dir: str | Path) -> dict[str, Any]:
    """Summary dynamics of one run folder (see module doc for the fallbacks)."""
    run_dir = Path(run_dir)
    try:
        summary = json.loads((run_dir / rundir.SUMMARY).read_text(encoding="utf-8"))
    except (OSError, ValueError):
        summary = {}
    out: dict[str, Any] = {}
    torque = summary.get("figures", {}).get("surface_torque_Nm") if isinstance(
        summary.get("figures"), dict) else None
    if isinstance(torque, dict):  # the simulator's figures: {mean, min, max[, rms]}
        if "rms" in torque:
            summary.setdefault("rms_surface_torque_Nm", torque["rms"])
        if "min" in torque and "max" in torque:
            summary.setdefault("peak_surface_torque_Nm",
                               max(abs(float(torque["min"])), abs(float(torque["max"]))))
    for name in DYNAMICS_COLUMNS:
        value = _lookup(summary, name)
        if name == "whirl_class":
            out[name] = None if value is None else str(value)
        else:
            out[name] = float(value) if isinstance(value, int | float) else math.nan
    need = [n for n in ("rms_surface_torque_Nm", "peak_surface_torque_Nm") if math.isnan(out[n])]
    channels = run_dir / rundir.CHANNELS
    out.update(achieved_outputs(channels))
    out.update(window_record(run_dir))
    if need and channels.is_file():
        torque = pd.read_parquet(channels, columns=["surface_torque_Nm"])["surface_torque_Nm"]
        values = torque.to_numpy(dtype=float)
        if values.size:
            stats = {"rms_surface_torque_Nm": float(np.sqrt(np.mean(values**2))),
                     "peak_surface_torque_Nm": float(np.max(np.abs(values)))}
            out.update({n: stats[n] for n in need})
    return out


def window_record(run_dir: str | Path) -> dict[str, float]:
    """:data:`WINDOW_COLUMNS` of a run from its ``window.json`` (NaN without one: a
    fixed window)."""
    out = dict.fromkeys(WINDOW_COLUMNS, math.nan)
    try:
        record = json.loads((Path(run_dir) / WINDOW_FILE).read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return out
    out["window_converged"] = 1.0 if record.get("converged") else 0.0
    change = record.get("rate_change_rel")
    out["window_rate_change_rel"] = float(change) if isinstance(change, int | float) else math.nan
    return out


def achieved_outputs(channels_path: str | Path) -> dict[str, float]:
    """:data:`ACHIEVED_COLUMNS` of a run from its ``channels.parquet`` (NaN where a
    channel is missing); the channels are sampled at a fixed rate, so plain means
    are time means."""
    out = dict.fromkeys(ACHIEVED_COLUMNS, math.nan)
    path = Path(channels_path)
    if not path.is_file():
        return out
    have = set(pq.read_schema(path).names)
    cols = [c for c in ("wob_N", "rop_m_per_s", "surface_torque_Nm") if c in have]
    if not cols:
        return out
    ch = pd.read_parquet(path, columns=cols)
    if not len(ch):
        return out
    for name, col in _ACHIEVED_CHANNELS.items():
        if col in ch.columns:
            out[name] = float(ch[col].to_numpy(dtype=float).mean())
    if "wob_N" in ch.columns:
        out["achieved_on_bottom_fraction"] = float(np.mean(ch["wob_N"].to_numpy(dtype=float) > 0.0))
    return out


def _case_rows(case_id: str, damage: pd.DataFrame) -> pd.DataFrame:
    """Pivot one case's long damage table to one row per location (joint, location).

    Descriptive columns (MD, distance from bit, component) are taken from the
    first criterion's row of each location, so criteria whose MD differs by
    rounding still share one row.
    """
    keys = [k for k in ("joint", "location") if k in damage.columns]
    damage = damage.assign(criterion=damage["criterion"].map(_criterion_name))
    values = [v for v in PIVOT_VALUES if v in damage.columns]
    long = damage.set_index([*keys, "criterion"])[values]
    if not long.index.is_unique:
        raise InputError(f"fatigue/{case_id}/damage.parquet", "repeated (location, criterion) rows",
                         "one row per location and criterion")
    wide = long.unstack("criterion")
    wide.columns = [f"{value}_{crit}" for value, crit in wide.columns]
    wide = wide.dropna(axis=1, how="all")
    info_cols = [k for k in KEY_COLUMNS if k in damage.columns and k not in keys]
    info = damage.groupby(keys, sort=True, dropna=False)[info_cols].first()
    wide = info.join(wide).reset_index()
    wide.insert(0, "case_id", case_id)
    return wide


def _get_path(data: Mapping[str, Any], path: str) -> Any:
    node: Any = data
    for key in path.split("."):
        if not isinstance(node, Mapping) or key not in node:
            return None
        node = node[key]
    return node


def _input_table(cases: pd.DataFrame, variables: Sequence[str]) -> pd.DataFrame:
    """Inputs per case (index case_id): the design variables, then every scalar field of
    the operating-condition sections (:data:`INPUT_SECTIONS`) from the case JSON."""
    rows = {}
    for cid, text in zip(cases["case_id"], cases["case_json"], strict=True):
        case = json.loads(text)
        row: dict[str, Any] = {}
        for section in INPUT_SECTIONS:
            for key, value in (case.get(section) or {}).items():
                if isinstance(value, bool | int | float | str):
                    row[f"{section}.{key}"] = value
        rig = case.get("rig")
        if isinstance(rig, dict):
            # the rig section holds the set-points the operation names stand for
            row["rig.block_mode"] = rig.get("block_mode")
            for src, dst in RIG_PATHS.items():
                value = _get_path(case, dst)
                if value is not None:
                    row[src] = value
        rows[cid] = row
    extra = pd.DataFrame.from_dict(rows, orient="index")
    table = cases.set_index("case_id")[list(variables)]
    rest = [c for c in extra.columns if c not in table.columns]
    return table.join(extra[rest]) if rest else table


def build_dataset(cases: pd.DataFrame, sweep_root: str | Path, fatigue_root: str | Path,
                  variables: Sequence[str] | None = None) -> pd.DataFrame:
    """One row per (case, component location) of every case with fatigue results.

    Parameters
    ----------
    cases : DataFrame
        Design table (``case_id``, variable columns, ``case_json``).
    sweep_root, fatigue_root : path
        ``<root>/<case_id>/`` folders of the simulate and fatigue passes.
    variables : sequence of str, optional
        Design-variable columns of ``cases`` to carry first; default: every
        column but ``case_id``, ``design_index`` and ``case_json``. Every
        scalar field of the ``well``, ``operation``, ``friction`` and ``bit``
        sections follows (constant ones included), named ``<section>.<field>``.

    Returns
    -------
    DataFrame
        Columns: ``case_id``, inputs, location keys, dynamics, then
        ``damage_rate_per_h_<criterion>``, ``life_h_<criterion>``,
        ``critical_angle_deg_<criterion>``. Cases without a
        ``damage.parquet`` are left out (they are counted as failures in the
        card and metrics).
    """
    if variables is None:
        variables = [c for c in cases.columns if c not in ("case_id", "design_index", "case_json")]
    inputs = _input_table(cases, variables)
    variables = list(inputs.columns)
    parts = []
    for cid in cases["case_id"]:
        damage_path = Path(fatigue_root) / cid / "damage.parquet"
        if not damage_path.is_file():
            continue
        wide = _case_rows(cid, pd.read_parquet(damage_path))
        for name, value in reversed(list(summary_dynamics(Path(sweep_root) / cid).items())):
            wide.insert(1, name, value)
        for name in reversed(list(variables)):
            wide.insert(1, name, inputs.at[cid, name])
        parts.append(wide)
    if not parts:
        return pd.DataFrame(columns=["case_id", *variables, *KEY_COLUMNS, *RUN_COLUMNS])
    frame = pd.concat(parts, ignore_index=True, sort=False)
    if "whirl_class" in frame.columns:
        frame["whirl_class"] = frame["whirl_class"].astype("string")
    return frame


def _versions() -> dict[str, str]:
    out = {"python": platform.python_version()}
    for pkg in ("drillfatigue", "numpy", "numba", "scipy", "pandas", "pyarrow", "fatpack",
                "dask", "distributed", "torch"):
        try:
            out[pkg] = metadata.version(pkg)
        except metadata.PackageNotFoundError:
            out[pkg] = "not installed"
    return out


def _describe(column: str, variables: Sequence[str]) -> str:
    if column == "case_id":
        return "case id: first 12 hex digits of SHA-256 of the case's simulation inputs"
    if column in variables:
        return f"design input `{column}` (case configuration path)"
    if column == "operation.duration_s":
        return "first simulated window (sweep.window_s); the window used is `duration_s`"
    if column.split(".")[0] in INPUT_SECTIONS and "." in column:
        return f"case input `{column}` (constant unless a design variable)"
    if column in RUN_COLUMNS:
        return RUN_COLUMNS[column]
    fixed = {"joint": "recorded joint index (0 = nearest the bit)",
             "component": "string component name", "component_type": "component type",
             "location": "location on the component (pipe body, upset, thread root ...)",
             "md_m": "measured depth of the location at the end of the window",
             "s_from_bit_m": "distance from the bit along the string", **POSITION_DESCRIPTIONS}
    if column in fixed:
        return fixed[column]
    for value, text in (("damage_rate_per_h_", "Miner damage per hour"),
                        ("life_h_", "fatigue life in hours"),
                        ("critical_angle_deg_", "critical-plane angle")):
        if column.startswith(value):
            crit = column[len(value):]
            extra = " (API RP7G, Lubinski/Hansford-Lubinski baseline)" if crit == "api_rp7g" else ""
            return f"{text}, criterion `{crit}`{extra}"
    return ""


def dataset_metrics(frame: pd.DataFrame, *, n_designed: int, n_sim_failed: int,
                    n_fatigue_failed: int, criterion: str | None = None) -> dict[str, Any]:
    """Small metrics dict for ``dvc metrics``: counts and damage-rate quantiles."""
    n_with = int(frame["case_id"].nunique()) if len(frame) else 0
    out: dict[str, Any] = {"n_cases_designed": n_designed, "n_cases_in_dataset": n_with,
                           "n_cases_failed_simulation": n_sim_failed,
                           "n_cases_failed_fatigue": n_fatigue_failed, "n_rows": int(len(frame))}
    for col in sorted(c for c in frame.columns if c.startswith("damage_rate_per_h_")):
        values = pd.to_numeric(frame[col], errors="coerce").dropna()
        if len(values):
            out[f"median_{col}"] = float(values.median())
            out[f"max_{col}"] = float(values.max())
    if criterion is not None and f"damage_rate_per_h_{criterion}" in frame.columns:
        rate = pd.to_numeric(frame[f"damage_rate_per_h_{criterion}"], errors="coerce")
        out["n_rows_zero_damage"] = int((rate == 0.0).sum())
    return out


def column_roles(columns: Sequence[str], variables: Sequence[str]) -> dict[str, str]:
    """Role of each dataset column: ``id``, ``input`` (design variables, case inputs and
    the location's keys and hole geometry), ``target`` (fatigue results), ``post_run``
    (what the simulation did: leaks the answer if used as an input)."""
    roles = {}
    for col in columns:
        if col == "case_id":
            roles[col] = "id"
        elif col in RUN_COLUMNS:
            roles[col] = "post_run"
        elif any(col.startswith(p) for p in TARGET_PREFIXES):
            roles[col] = "target"
        else:
            roles[col] = "input"
    return roles


def split_constants(frame: pd.DataFrame, keep: Sequence[str] = ()) -> tuple[pd.DataFrame,
                                                                              dict[str, Any]]:
    """``frame`` without its constant columns (one value, NaN included), and those columns'
    values. Columns in ``keep`` stay (the design variables: a surrogate's features, constant
    only in a one-case dataset)."""
    constants: dict[str, Any] = {}
    if len(frame) < 2:
        return frame, constants
    for col in frame.columns:
        if col in keep or col == "case_id":
            continue
        if frame[col].nunique(dropna=False) <= 1:
            value = frame[col].iloc[0]
            if isinstance(value, np.generic):
                value = value.item()
            if isinstance(value, float) and not math.isfinite(value):
                value = None
            elif value is pd.NA:
                value = None
            constants[col] = value
    return frame.drop(columns=list(constants)), constants


def _front_matter(frame: pd.DataFrame, roles: Mapping[str, str], *, floor_per_h: float | None,
                  n_cases: int) -> list[str]:
    """Hugging Face dataset-card YAML front matter: licence, data files, features, and the
    column roles, units and split rule under ``drillfatigue``."""
    def dtype(col: str) -> str:
        kind = frame[col].dtype
        if pd.api.types.is_bool_dtype(kind):
            return "bool"
        if pd.api.types.is_integer_dtype(kind):
            return "int64"
        if pd.api.types.is_float_dtype(kind):
            return "float64"
        return "string"

    size = ("n<1K" if len(frame) < 1_000 else "1K<n<10K" if len(frame) < 10_000
            else "10K<n<100K" if len(frame) < 100_000 else "100K<n<1M")
    meta = {
        "license": DATA_LICENSE.lower(),
        "pretty_name": "drillfatigue damage dataset",
        "tags": ["drilling", "drill-string", "fatigue", "simulation", "tabular-regression"],
        "size_categories": [size],
        "configs": [{"config_name": "default", "data_files": "damage.parquet"}],
        "dataset_info": {"features": [{"name": c, "dtype": dtype(c)} for c in frame.columns]},
        "drillfatigue": {
            "group_column": "case_id",
            "split_rule": "split by case_id: rows of one case share one simulation",
            "n_cases": n_cases,
            "censoring_floor_per_h": floor_per_h,
            "constants_file": CONSTANTS_FILE,
            "columns": {c: {"role": roles[c], "unit": unit_of(c)} for c in frame.columns},
        },
    }
    return ["---", yaml.safe_dump(meta, sort_keys=False, allow_unicode=True).rstrip(), "---", ""]


def dataset_card(frame: pd.DataFrame, *, design: Mapping[str, Any], metrics: Mapping[str, Any],
                 base_case: Mapping[str, Any] | None = None,
                 constants: Mapping[str, Any] | None = None, floor_per_h: float | None = None,
                 paths: Mapping[str, str] | None = None) -> str:
    """Markdown dataset card with Hugging Face YAML front matter (see ``docs/pipeline.md``)."""
    variables = list(design.get("variables", {}))
    roles = column_roles(list(frame.columns), variables)
    paths = {"sweep": "data/sweep", "fatigue": "data/fatigue", "dataset": "data/dataset",
             **(paths or {})}
    lines = _front_matter(frame, roles, floor_per_h=floor_per_h,
                          n_cases=int(metrics.get("n_cases_in_dataset") or 0))
    lines += _card_intro(metrics, paths)
    lines += _card_design(design)
    lines += _card_columns(frame, roles, variables, design, metrics, floor_per_h)
    lines += _card_constants(dict(constants or {}))
    lines += _card_loading(frame, roles, paths, floor_per_h)
    if base_case is not None:
        lines += ["## Base case", "", "The first case (the design variables above vary per case):",
                  "", "```json", json.dumps(dict(base_case), indent=1, sort_keys=True), "```", ""]
    return "\n".join(lines)


def _card_intro(metrics: Mapping[str, Any], paths: Mapping[str, str]) -> list[str]:
    """The card's purpose, licence, how to regenerate it, its contents and the split rule."""
    return [
        "# drillfatigue damage dataset",
        "",
        "Generated by the `dataset` stage of the drillfatigue DVC pipeline; do not edit by hand.",
        "",
        "## Purpose",
        "",
        "Fatigue damage of drill-string component locations under sampled operating conditions",
        "(rigid-segment drill-string dynamics in a deviated well, then rainflow/S-N/Miner and",
        "multiaxial critical-plane criteria, with the API RP7G estimate beside them). Meant for",
        "engineering screening and for training surrogate models of damage rate versus inputs.",
        "",
        "## Licence",
        "",
        f"The data are licensed under {DATA_LICENSE} (attribution: cite the project, see",
        "`CITATION.cff`). The code that generates them is under the project's MIT licence",
        "(`LICENSE`).",
        "",
        "## How to regenerate",
        "",
        "`dvc repro dataset` in a clone of the repository (`make repro` runs every stage, the",
        "install included). The design, the case ids and the base case are a function of",
        "`params.yaml` alone. The simulated numbers are reproducible bit for bit on one machine",
        "and software stack (`Software versions` below). Across CPUs they can differ in the last",
        "bits: numba compiles the kernels for the CPU it runs on (vector width, fused",
        "multiply-add), so round-off differs, and in the chaotic cases (whirl onset, bit bounce)",
        "a round-off difference grows into a different trajectory. The replicate study",
        "(`data/replicates/spread.json`) measures how far such a perturbation moves the damage",
        "rate; expect differences of that size between machines, not larger.",
        "",
        "## Contents",
        "",
        f"- cases designed: {metrics.get('n_cases_designed')}",
        f"- cases in the dataset: {metrics.get('n_cases_in_dataset')}",
        f"- cases failed in simulation (after retries): {metrics.get('n_cases_failed_simulation')}"
        f" (see `{paths['sweep']}/failures.parquet`)",
        f"- cases failed in fatigue evaluation: {metrics.get('n_cases_failed_fatigue')}"
        f" (see `{paths['fatigue']}/failures.parquet`)",
        f"- rows (case x component location): {metrics.get('n_rows')}",
        "",
        "## Rows are correlated: split by case",
        "",
        "All rows of one case come from one simulation: they share its inputs, its dynamics",
        "and its window, and their damage rates move together. A random split of rows puts",
        "rows of one simulation on both sides and scores a model on cases it has seen. Split",
        "by `case_id` (snippets under Loading); a held-out design of its own seed is the",
        "`heldout` stage's dataset (`data/heldout/dataset`).",
        "",
    ]


def _card_design(design: Mapping[str, Any]) -> list[str]:
    """The card's sampling design: method, window, and the table of design variables."""
    window = design.get("window") or {}
    lines = [
        "## Sampling design",
        "",
        f"- method: {design.get('method')} (scipy.stats.qmc, scrambled), seed {design.get('seed')}",
        f"- cases requested: {design.get('n_cases')}"
        + (" (a Sobol design is rounded up to a power of two)" if design.get("method") == "sobol"
           else ""),
        f"- boundaries: {design.get('boundaries', 'operation')}"
        + (" (the rig's block lowers at `operation.rop_m_per_s`, the bit cuts what the bit law"
           " lets it; the WOB is a result, see `achieved_*`)"
           if design.get("boundaries") == "rig" else ""),
        f"- first simulated window per case: {design.get('window_s') or 'the base case duration'}"
        + (" s" if design.get("window_s") else ""),
    ]
    if window.get("mode") == "converged":
        lines.append(
            f"- window per case: extended x{window.get('growth')} up to {window.get('max_s')} s"
            f" while the governing location's uniaxial damage rate changes by more than"
            f" {window.get('tol_rel')} (relative) over the last third of the record;"
            " `duration_s`, `window_converged` and `window_rate_change_rel` record the outcome")
    lines += ["", "| input (config path) | range / choices | scale | kind |", "|---|---|---|---|"]
    for path, spec in design.get("variables", {}).items():
        if spec.get("choices") is not None:
            rng = ", ".join(json.dumps(c) for c in spec["choices"])
            lines.append(f"| `{path}` | {rng} | - | categorical |")
        else:
            lines.append(f"| `{path}` | {spec.get('low')} ... {spec.get('high')} | "
                         f"{spec.get('scale', 'linear')} | {spec.get('kind', 'float')} |")
    if not design.get("variables", {}):
        lines.append("| (none: the base case only) | | | |")
    lines += ["", "Every other input is the base case of `params.yaml` (stored in full, per case,",
              "in the design's `cases.parquet`, column `case_json`).", ""]
    return lines


def _card_columns(frame: pd.DataFrame, roles: Mapping[str, str], variables: list[str],
                  design: Mapping[str, Any], metrics: Mapping[str, Any],
                  floor_per_h: float | None) -> list[str]:
    """The card's column roles, censoring note and schema table."""
    lines: list[str] = []
    names = {"input": "Inputs", "target": "Targets", "post_run": "Post-run outputs"}
    lines += ["## Column roles", ""]
    for role, text in (
            ("input", "what is known before the simulation: the design variables, the case "
                      "inputs that vary, and the location (component, distance from the bit, "
                      "hole geometry)"),
            ("target", "the fatigue results"),
            ("post_run", "what the simulation did; they carry the answer (torque, contact "
                         "forces, achieved WOB follow the damage-causing dynamics), so using "
                         "them as inputs leaks the target")):
        cols = [c for c in frame.columns if roles[c] == role]
        lines.append(f"- {names[role]} ({text}): " + ", ".join(f"`{c}`" for c in cols))
    lines += [
        "",
        "## Censoring",
        "",
        "A location with no fatigue cycle in its window has damage rate 0 and life `inf`: its",
        "life is longer than anything the window can show. "
        + (f"The surrogate reads such rates (and any below) at the floor {floor_per_h:g} per hour"
           f" (a life of {1.0 / floor_per_h:g} h, `surrogate.rate_floor_per_h`): treat rows at or"
           " below the floor as censored (\"longer than\"), not as measured."
           if floor_per_h else "Treat such rows as censored (\"longer than\"), not as measured."),
        f"Rows at zero damage (`{TARGET_PREFIXES[0]}{design.get('criterion', 'matake')}`): "
        f"{metrics.get('n_rows_zero_damage', 'n/a')} of {metrics.get('n_rows')}.",
        "",
        "## Schema",
        "",
        "| column | role | dtype | unit | description |",
        "|---|---|---|---|---|",
    ]
    for col in frame.columns:
        lines.append(f"| `{col}` | {roles[col]} | {frame[col].dtype} | {unit_of(col)} | "
                     f"{_describe(col, variables)} |")
    return lines


def _card_constants(constants: Mapping[str, Any]) -> list[str]:
    """The card's note on units, the constant columns and the software versions."""
    lines = ["", "Unit `1`: dimensionless; `-`: not a quantity (an id, a category, a flag). A",
             "missing dynamics figure (not reported by the simulator) is NaN, never zero.", "",
             "## Constant columns", "",
             f"Columns with one value in every row are not in the table; `{CONSTANTS_FILE}`",
             "holds them (value, unit, description):", "",
             "| column | value | unit |", "|---|---|---|"]
    for col, value in constants.items():
        lines.append(f"| `{col}` | {json.dumps(value)} | {unit_of(col)} |")
    if not constants:
        lines.append("| (none) | | |")
    lines += ["", "## Software versions", "", "| package | version |", "|---|---|"]
    for pkg, ver in _versions().items():
        lines.append(f"| {pkg} | {ver} |")
    return lines


def _card_loading(frame: pd.DataFrame, roles: Mapping[str, str], paths: Mapping[str, str],
                  floor_per_h: float | None) -> list[str]:
    """The card's loading snippets: pandas, Hugging Face ``datasets`` and torch."""
    target = next((c for c in frame.columns if c.startswith("damage_rate_per_h_")),
                  "damage_rate_per_h_<criterion>")
    numeric_inputs = [c for c in frame.columns if roles[c] == "input" and c != "joint"
                      and pd.api.types.is_numeric_dtype(frame[c])
                      and not pd.api.types.is_bool_dtype(frame[c])]
    data_path = f"{paths['dataset']}/damage.parquet"
    return [
        "", "## Loading", "",
        "pandas, split by case (20 % of the cases held out, seeded):", "", "```python",
        "import numpy as np, pandas as pd",
        f'df = pd.read_parquet("{data_path}")',
        'cases = np.sort(df["case_id"].unique())',
        "rng = np.random.default_rng(0)",
        "test_cases = rng.choice(cases, size=max(1, len(cases) // 5), replace=False)",
        'test = df[df["case_id"].isin(test_cases)]',
        'train = df[~df["case_id"].isin(test_cases)]',
        f"inputs = {numeric_inputs!r}",
        f'y_train = np.log10(np.maximum(train["{target}"], {floor_per_h or 1e-12!r}))',
        "```", "",
        "Hugging Face `datasets`, the same split by case:", "", "```python",
        "import numpy as np",
        "from datasets import load_dataset",
        f'ds = load_dataset("parquet", data_files="{data_path}")["train"]',
        'cases = np.sort(np.unique(ds["case_id"]))',
        "test_cases = set(np.random.default_rng(0).choice(cases, size=max(1, len(cases) // 5),"
        " replace=False))",
        'test = ds.filter(lambda row: row["case_id"] in test_cases)',
        'train = ds.filter(lambda row: row["case_id"] not in test_cases)',
        "```", "",
        "torch (numeric inputs → log10 damage rate):", "", "```python",
        "import numpy as np, pandas as pd, torch",
        f'df = pd.read_parquet("{data_path}")',
        f"inputs = {numeric_inputs!r}",
        f'df = df.dropna(subset=inputs + ["{target}"])',
        "x = torch.tensor(df[inputs].to_numpy(np.float32))",
        f'y = torch.tensor(np.log10(np.maximum(df["{target}"].to_numpy(np.float32), '
        f'{floor_per_h or 1e-12!r})))',
        "dataset = torch.utils.data.TensorDataset(x, y)", "```", "",
        "Raw load histories (optional): `drillfatigue dataset export --histories OUT`, then",
        '`pd.read_parquet("OUT/loads", filters=[("case_id", "==", "<id>")])`.', ""]


def _failed_count(root: Path) -> int:
    """Cases still failed at the end of the latest sweep run in ``root``."""
    return int(latest_failures(root)["final"].sum())


def write_dataset(cases: pd.DataFrame, sweep_root: str | Path, fatigue_root: str | Path,
                  out_dir: str | Path, *, design: Mapping[str, Any],
                  base_case: Mapping[str, Any] | None = None,
                  floor_per_h: float | None = None, keep: Sequence[str] = ()) -> dict[str, Any]:
    """Build and write ``damage.parquet``, ``constants.json``, ``README.md``,
    ``metrics.json`` and plot data.

    ``design`` is the ``sweep`` section as a dict (method, seed, n_cases,
    variables, window_s, window, boundaries; ``criterion`` optionally names the
    criterion whose zero-damage rows the card counts). Columns with one value in
    every row go to ``constants.json``, but for the design variables and the columns
    in ``keep`` (a model's configured inputs, which it looks up by name). ``floor_per_h``:
    the censoring floor the card states. Plot data: ``plots/damage_rate_hist.csv``
    (log10 damage-rate histogram per criterion). Returns the metrics dict.

    ``out_dir`` is a ``dataset`` output folder (:class:`drillfatigue.files.OutputFolder`):
    a folder holding files drillfatigue did not write is refused before the
    dataset is assembled; only the files of :data:`DATASET_FILES` are replaced.
    """
    folder = OutputFolder(out_dir, DATASET_KIND, "sweep.dataset_dir")
    out = folder.path
    for name in DATASET_FILES:
        folder.file(name)
    variables = [v for v in design.get("variables", {}) if v in cases.columns]
    full = build_dataset(cases, sweep_root, fatigue_root, variables)
    frame, constants = split_constants(full, keep=[*variables, *keep])
    metrics = dataset_metrics(
        full, n_designed=len(cases),
        n_sim_failed=_failed_count(Path(sweep_root)),
        n_fatigue_failed=_failed_count(Path(fatigue_root)), criterion=design.get("criterion"))
    with atomic_output(out / "damage.parquet") as tmp:
        frame.to_parquet(tmp, index=False)
    atomic_write_text(out / CONSTANTS_FILE, json.dumps(
        {col: {"value": value, "unit": unit_of(col), "description": _describe(col, variables)}
         for col, value in constants.items()}, indent=2) + "\n")
    paths = {"sweep": str(sweep_root), "fatigue": str(fatigue_root), "dataset": str(out_dir)}
    atomic_write_text(out / "README.md", dataset_card(
        frame, design=design, metrics=metrics, base_case=base_case, constants=constants,
        floor_per_h=floor_per_h, paths=paths))
    atomic_write_text(out / "metrics.json", json.dumps(metrics, indent=2, sort_keys=True) + "\n")
    rows = []
    for col in sorted(c for c in frame.columns if c.startswith("damage_rate_per_h_")):
        values = pd.to_numeric(frame[col], errors="coerce").to_numpy(dtype=float)
        values = values[np.isfinite(values) & (values > 0)]
        if values.size == 0:
            continue
        counts, edges = np.histogram(np.log10(values), bins=20)
        for c, lo, hi in zip(counts, edges[:-1], edges[1:], strict=True):
            rows.append({"criterion": col[len("damage_rate_per_h_"):],
                         "log10_damage_rate_per_h": 0.5 * (lo + hi), "count": int(c)})
    hist = pd.DataFrame(rows, columns=["criterion", "log10_damage_rate_per_h", "count"])
    atomic_write_text(out / "plots" / "damage_rate_hist.csv", hist.to_csv(index=False))
    return metrics


def export_histories(sweep_root: str | Path, out: str | Path,
                     case_ids: Sequence[str] | None = None,
                     tables: Sequence[str] = ("loads", "channels")) -> Path:
    """Export raw histories to Parquet datasets partitioned by case (hive layout).

    Writes ``out/<table>/case_id=<id>/part-0.parquet`` for each table
    (``loads``: internal loads per joint; ``channels``: surface and bit
    channels) of every completed case (a ``DONE`` marker), each file under a
    temporary name first. Read back with ``pd.read_parquet(out / "loads")``
    (``case_id`` becomes a column).

    ``out`` is an ``export`` output folder (:class:`drillfatigue.files.OutputFolder`):
    a new or empty folder, or one an earlier export wrote. A rerun replaces
    the files it wrote and removes those of cases no longer exported; any
    other file in ``out`` is kept.

    Raises
    ------
    InputError
        ``sweep_root`` missing or holding no completed case; ``out`` a file or
        a folder holding files drillfatigue did not write (checked before
        anything is written).
    """
    root = Path(sweep_root)
    if not root.is_dir():
        raise InputError(str(root), "sweep folder not found", "the output folder of a sweep")
    ids = list(case_ids) if case_ids is not None else sorted(
        p.name for p in root.iterdir() if (p / "DONE").is_file())
    ids = [i for i in ids if (root / i / "DONE").is_file()]
    if not ids:
        raise InputError(str(root), "no completed case to export", "a folder with finished cases")
    folder = OutputFolder(out, EXPORT_KIND)
    written: set[str] = set()
    for table in tables:
        for cid in ids:
            src = root / cid / f"{table}.parquet"
            if not src.is_file():
                continue
            name = f"{table}/case_id={cid}/part-0.parquet"
            with atomic_output(folder.file(name)) as tmp:
                shutil.copyfile(src, tmp)
            written.add(name)
    stale = sorted(n for n in folder.owned if n not in written)
    folder.remove(stale)
    for name in stale:  # drop partition folders left empty (only ever this export's)
        d = (folder.path / name).parent
        while d != folder.path and d.is_dir() and not any(d.iterdir()):
            d.rmdir()
            d = d.parent
    return folder.path
