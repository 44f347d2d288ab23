"""Stage entry points of the case studies (thin ``pipeline/*.py`` scripts call these).

Each study reads its own ``params.yaml`` section (``case1``, ``case2``,
``case3``, ``plan``, ``report``; models in :mod:`drillfatigue.config.studies`),
runs, and writes its folder plus a small metrics JSON.
"""

from __future__ import annotations

import argparse
import functools
import time
from pathlib import Path
from typing import Any, NamedTuple

from drillfatigue.config import FatigueConfig, WellConfig
from drillfatigue.config.base import read_yaml, validate
from drillfatigue.config.studies import (
    Case1Config,
    Case2Config,
    Case3Config,
    PlanConfig,
    ReportConfig,
)
from drillfatigue.errors import InputError
from drillfatigue.files import OutputFolder
from drillfatigue.stage import Option
from drillfatigue.stage import stage_main as shared_stage_main
from drillfatigue.studies.case1 import run_case1
from drillfatigue.studies.case2 import run_case2
from drillfatigue.studies.case3 import run_case3
from drillfatigue.studies.common import write_json


class StudyInputs(NamedTuple):
    """What a case study reads of the params file, validated."""

    name: str
    config: Any
    well: dict[str, Any]
    fatigue: FatigueConfig


SECTIONS: dict[str, type] = {"case1": Case1Config, "case2": Case2Config, "case3": Case3Config,
                             "plan": PlanConfig, "report": ReportConfig}


def load_section(params_path: str | Path, name: str) -> Any:
    """Validate section ``name`` of a params file (absent section: defaults)."""
    if name not in SECTIONS:
        raise InputError("study", f"unknown study {name!r}", ", ".join(SECTIONS))
    data = read_yaml(params_path)
    section = data.get(name) or {}
    if not isinstance(section, dict):
        raise InputError(name, "section must be a mapping", "a mapping of the section's keys")
    return validate(SECTIONS[name], section, name)


def shared_sections(params_path: str | Path) -> tuple[dict[str, Any], FatigueConfig]:
    """The params file's ``well`` section (profiles, family, hole; validated) and its
    ``fatigue`` section (plots off), which cases 2 and 3 use."""
    data = read_yaml(params_path)
    well = data.get("well") or {}
    validate(WellConfig, well, "well")
    fat = dict(data.get("fatigue") or {})
    fat["plots"] = False
    return dict(well), validate(FatigueConfig, fat, "fatigue")


def load_study(params_path: str | Path, name: str) -> StudyInputs:
    """Validate what study ``case1``, ``case2`` or ``case3`` reads of a params file."""
    if name not in ("case1", "case2", "case3"):
        raise InputError("study", f"unknown study {name!r}", "case1, case2, case3")
    cfg = load_section(params_path, name)
    well, fatigue = shared_sections(params_path)
    return StudyInputs(name, cfg, well, fatigue)


def run_study(name: str, params_path: str | Path, out_dir: str | Path,
              metrics_path: str | Path | None = None, dpi: int = 110) -> dict[str, Any]:
    """Run study ``case1``, ``case2`` or ``case3`` into ``out_dir``; return its summary.

    ``out_dir`` is an output folder of the study's kind
    (:class:`drillfatigue.files.OutputFolder`): a folder holding files
    drillfatigue did not write is refused before the study runs; the files
    the study writes are recorded in its marker.
    """
    return run_loaded_study(load_study(params_path, name), out_dir, metrics_path, dpi)


def run_loaded_study(study: StudyInputs, out_dir: str | Path,
                     metrics_path: str | Path | None = None, dpi: int = 110) -> dict[str, Any]:
    """:func:`run_study` on the inputs :func:`load_study` validated."""
    name, cfg, well, fatigue = study
    folder = OutputFolder(out_dir, name)
    foreign = _files_under(folder.path) - folder.owned
    t0 = time.perf_counter()
    if name == "case1":
        summary = run_case1(cfg, Path(out_dir), dpi=dpi)
    elif name == "case2":
        summary = run_case2(cfg, Path(out_dir), dpi=dpi, well=well, fatigue=fatigue)
    else:
        summary = run_case3(cfg, Path(out_dir), dpi=dpi, well=well, fatigue=fatigue)
    wall = time.perf_counter() - t0
    folder.record(_files_under(folder.path) - foreign)
    if metrics_path is not None:
        write_json(Path(metrics_path), _metrics(name, summary, wall))
    return summary


def _files_under(root: Path) -> set[str]:
    """Relative paths of the files under ``root`` (temporary dot-files excluded)."""
    return {str(p.relative_to(root)) for p in root.rglob("*")
            if p.is_file() and not p.name.startswith(".")}


def _metrics(name: str, s: dict[str, Any], wall: float) -> dict[str, Any]:
    m: dict[str, Any] = {"stage_wall_s": wall}
    if name == "case2":
        for r in s["rows"]:
            m[f"life_windows_{r['profile']}"] = r["life_windows_critical_plane"]
            m[f"life_windows_api_rp7g_{r['profile']}"] = r["life_windows_api_rp7g"]
        m["order_agrees_with_paper"] = s["order_agrees"]
        tort = s.get("tortuous") or {}
        for r in tort.get("rows", []):
            m[f"life_windows_tortuous_{r['profile']}"] = r["life_windows_critical_plane"]
            m[f"life_windows_api_rp7g_tortuous_{r['profile']}"] = r["life_windows_api_rp7g"]
        if tort:
            m["order_agrees_with_paper_tortuous"] = tort["order_agrees"]
        for r in s.get("drilling", []):
            tag = f"{r['profile']}" + (f"_sample{r['sample']}" if r["sample"] else "")
            for key in ("on_bottom_fraction", "wob_error_rel", "mean_rop_m_per_h",
                        "mean_surface_torque_Nm", "block_within_travel",
                        "string_top_below_rotary", "stick_slip_class", "whirl_class",
                        "bounce_class"):
                m[f"{key}_{tag}"] = r[key]
            for key in ("rop_over_bit_law", "surface_torque_over_tnd"):
                if key in r:
                    m[f"{key}_{tag}"] = r[key]
    elif name == "case3":
        for r in s["rows"]:
            m[f"life_h_{r['s_from_bit_m']:g}m"] = r["life_h"]
            m[f"life_ratio_to_paper_{r['s_from_bit_m']:g}m"] = r["life_ratio_ours_to_paper"]
            m[f"dominant_load_{r['s_from_bit_m']:g}m"] = r["dominant_load"]
        for r in (s.get("tortuous") or {}).get("rows", []):
            m[f"life_h_tortuous_{r['s_from_bit_m']:g}m"] = r["life_h"]
            m[f"life_ratio_to_paper_tortuous_{r['s_from_bit_m']:g}m"] = \
                r["life_ratio_ours_to_paper"]
            m[f"dominant_load_tortuous_{r['s_from_bit_m']:g}m"] = r["dominant_load"]
    else:
        for r in s["rows"]:
            m[f"whirl_ratio_{r['model']}_{r['friction']}"] = r["whirl_ratio"]
            m[f"wall_s_{r['model']}_{r['friction']}"] = r["wall_s"]
    return m


def stage_main(name: str, argv: list[str] | None = None) -> int:
    """Command line of the ``pipeline/<name>.py`` stage script of a case study.

    ``[--params params.yaml] [--out data/<name>] [--metrics JSON]``, through the
    stage scripts' shared :func:`drillfatigue.stage.stage_main`: bad input is one
    line ``error: ...`` on stderr and exit code 2.
    """
    def study(inputs: StudyInputs, args: argparse.Namespace) -> None:
        run_loaded_study(inputs, args.out, args.metrics)

    return shared_stage_main(f"DVC stage {name}: the founding paper's case study {name[-1]}",
                             study, (Option("--out", default=f"data/{name}"), Option("--metrics")),
                             argv, load=functools.partial(load_study, name=name))
