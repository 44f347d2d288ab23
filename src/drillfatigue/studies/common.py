"""Shared pieces of the case studies: the paper's string, case builders, fatigue helpers.

String sizes are docs/model.md#bodies's typical values (the paper's Table 2 is not
available): 6 3/4 in collars (OD 171.45 mm, ID 71.4 mm), 5 in 19.5 lb/ft drill
pipe (OD 127.0 mm, ID 108.6 mm, tool joint 168.3 x 82.6 mm).
"""

from __future__ import annotations

import json
import math
import time
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

from drillfatigue import rundir
from drillfatigue.config import CaseConfig, FatigueConfig, case_from_dict
from drillfatigue.config.string import PRESETS
from drillfatigue.config.studies import StringSpec
from drillfatigue.dynamics.run.simulation import simulate
from drillfatigue.errors import InputError
from drillfatigue.files import atomic_output, atomic_write_text
from drillfatigue.sweep.cases import api_rp7g_rows
from drillfatigue.units import HOUR_S

COLLAR = {"type": "collar", "name": "6.75in DC", "od_m": 0.17145, "id_m": 0.0714}
DRILL_PIPE = {"type": "drill_pipe", "name": "5in 19.5ppf DP", "od_m": 0.127, "id_m": 0.1086,
              "tool_joint_od_m": 0.1683, "tool_joint_id_m": 0.0826,
              "tool_joint_length_fraction": 0.05}


def string_components(spec: StringSpec, total_length_m: float) -> list[dict[str, Any]]:
    """Collars of ``spec.dc_length_m`` at the bit, drill pipe up to ``total_length_m``."""
    dp_len = total_length_m - spec.dc_length_m
    if dp_len <= 0:
        raise InputError("string.dc_length_m", f"collars ({spec.dc_length_m} m) longer than the "
                         f"string ({total_length_m} m)", f"< {total_length_m}")
    return [{**COLLAR, "length_m": spec.dc_length_m, "n_segments": spec.dc_segments},
            {**DRILL_PIPE, "length_m": dp_len, "n_segments": spec.dp_segments}]


def paper_bha_components(total_length_m: float, dp_segments: int,
                         dp_joints_per_segment: int | None) -> list[dict[str, Any]]:
    """The ``paper_bha`` preset's BHA (stabilizers and collars, docs/bending.md) with its
    drill pipe reaching up to ``total_length_m``.

    The drill pipe is cut at its joints (``dp_joints_per_segment`` whole joints per
    segment) or, when that is None, into ``dp_segments`` equal segments (a reduced
    string: the tool joints are then only at the segment ends).
    """
    comps = [c.model_dump(mode="json", exclude_none=True) for c in PRESETS["paper_bha"]()]
    bha_m = sum(c["length_m"] for c in comps if c["type"] != "drill_pipe")
    dp_len = total_length_m - bha_m
    if dp_len <= 0:
        raise InputError("bit_md_m", f"the paper BHA ({bha_m:g} m) is longer than the string "
                         f"({total_length_m:g} m)", f"> {bha_m:g}")
    out = []
    for c in comps:
        if c["type"] == "drill_pipe":
            c = {**c, "length_m": dp_len}
            if dp_joints_per_segment is None:
                c.pop("joints_per_segment", None)
                c["n_segments"] = dp_segments
            else:
                c["joints_per_segment"] = dp_joints_per_segment
        out.append(c)
    return out


def span_sections(*, points: str = "string", span_bending: bool = True,
                  lateral_mud_mass: bool = True) -> dict[str, dict[str, Any]]:
    """Case sections that switch on bending between supports (docs/bending.md): contact
    points where the string touches the wall, the span-bending correction recorded
    beside the joint moment, mud and added mass in the lateral inertia. ``string``
    goes into the case's string section beside its components."""
    return {"contact": {"points": points, "span_bending": span_bending},
            "string": {"lateral_mud_mass": lateral_mud_mass}}


def rig_drilling_sections(*, wob_set_N: float, measurement: str, initial_travel_m: float,
                          lobe_amplitude_m: float) -> dict[str, Any]:
    """``bit`` and ``rig`` sections of a rig-driven drilling window (docs/rig.md): the
    autodriller holds ``wob_set_N``, the bit law (Yigit-Christoforou) gives the ROP, the
    rock face has three lobes of ``lobe_amplitude_m``; the operation needs
    ``top_axial: neutral_point`` and ``bit_on_bottom: true``."""
    return {"bit": {"model": "yigit_christoforou"},
            "rig": {"block_mode": "autodriller",
                    "autodriller": {"measurement": measurement, "wob_set_N": wob_set_N},
                    "block": {"initial_travel_m": initial_travel_m},
                    "rock": {"lobe_count": 3, "lobe_amplitude_m": lobe_amplitude_m}}}


def write_json(path: Path, data: Any) -> None:
    """Atomic JSON write (sorted keys, NaN/inf as null)."""
    atomic_write_text(path, json.dumps(_clean(data), indent=2, sort_keys=True) + "\n")


def _clean(x: Any) -> Any:
    if isinstance(x, dict):
        return {str(k): _clean(v) for k, v in x.items()}
    if isinstance(x, list | tuple):
        return [_clean(v) for v in x]
    if isinstance(x, np.integer):
        return int(x)
    if isinstance(x, float | np.floating):
        v = float(x)
        return v if math.isfinite(v) else None
    return x


def write_csv(path: Path, frame: pd.DataFrame) -> None:
    """Atomic CSV write."""
    atomic_write_text(path, frame.to_csv(index=False))


def save_figure(fig: Any, path: Path, dpi: int = 110) -> None:
    """Save a matplotlib figure atomically as PNG."""
    with atomic_output(path) as tmp:
        fig.savefig(tmp, dpi=dpi, bbox_inches="tight")


def run_simulation(case: dict[str, Any], run_dir: Path) -> tuple[CaseConfig, dict[str, Any], float]:
    """Validate ``case``, simulate into ``run_dir``; return (config, summary, wall seconds)."""
    cfg = case_from_dict(case)
    run_dir.mkdir(parents=True, exist_ok=True)
    t0 = time.perf_counter()
    res = simulate(cfg, run_dir, progress=False)
    wall = time.perf_counter() - t0
    return cfg, res.summary, wall


def warm_up(case: dict[str, Any], duration_s: float = 0.02) -> None:
    """Compile the simulator kernels for ``case`` with a very short run kept in memory.

    Wall times measured afterwards exclude numba compilation (cached on disk after
    the first process, but loading still costs ~1 s).
    """
    short = {**case, "operation": {**case["operation"], "duration_s": duration_s},
             "recording": {**case.get("recording", {}), "start_s": 0.0}}
    if "rpm_table" in short["operation"]:
        short["operation"]["rpm_table"] = [[0.0, 0.0]]
    simulate(case_from_dict(short), None, progress=False)


def recorded_span_s(run_dir: Path) -> float:
    """Length of the recorded loads history, s (last minus first sample plus one step)."""
    return rundir.recorded_span_s(
        pd.read_parquet(run_dir / rundir.LOADS, columns=["time_s"])["time_s"].to_numpy())


def rp7g_rates(run_dir: Path, case: dict[str, Any], fatigue: FatigueConfig) -> pd.DataFrame:
    """API RP7G (Lubinski) damage rate per hour of every recorded joint's body."""
    return pd.DataFrame(api_rp7g_rows(run_dir, case, fatigue))


def study_fatigue() -> FatigueConfig:
    """Fatigue settings of the studies: project defaults (docs/fatigue.md), plots off."""
    return FatigueConfig(plots=False)


def hours(seconds: float) -> float:
    """Seconds to hours."""
    return seconds / HOUR_S
