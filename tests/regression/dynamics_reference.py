"""Reference runs of the simulator, recorded so a refactoring can prove it changed nothing.

Each case is a short run (a fraction of a second of simulated time) chosen to
pass through every submodel of the dynamics: the vertical quick case (top
drive with an rpm ramp, neutral-point hook load, given TOB, prescribed ROP),
the case-1 whirl (applied top torque, free top, horizontal hole, whirl
detection and classification), a deviated drilling case with wall contact for
each of the six friction laws (J well, tool joints, relaxation pre-run, bit
law variants and contact-point layouts varied between them), a drilling case
that splits segments off the top, and tripping out (merges) and in (splits).

``python tests/regression/dynamics_reference.py`` rewrites the ``.npz`` files
in ``tests/regression/data``; do that only when a change of results is meant.
:func:`run_case` returns the arrays a file holds: the in-memory histories
(times, joint loads, channels, kinematics), the final state, the step and the
summary (as canonical JSON, without wall times and versions).
"""

from __future__ import annotations

import json
import math
import sys
from pathlib import Path
from typing import Any

import numpy as np
import yaml

from drillfatigue.numba_cache import scope_numba_cache

# before any kernel module is imported: numba's cache keyed by the kernels' source (a
# cached kernel is not recompiled when a kernel it calls in another module changes)
scope_numba_cache()

from drillfatigue.config import CaseConfig, case_from_dict  # noqa: E402
from drillfatigue.dynamics.run.simulation import simulate  # noqa: E402
from drillfatigue.dynamics.run.model import straight_path  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]
DATA = Path(__file__).resolve().parent / "data"
FRICTION_MODELS = ("coulomb", "benson_hallquist", "karnopp", "tanh", "velocity_trig", "tanh_exp")
#: summary entries that are not results of the model (machine, time of day)
VOLATILE = ("wall_time_s", "real_time_factor", "versions")


#: options whose library default changed after the references were recorded: the
#: references keep the values they were recorded with (rigid segments as listed, ends-only
#: contact points, no span-bending record, no deepest point, steel-only lateral inertia,
#: the torsional mud drag of before Aarsnes & Shor's fit)
RECORDED_WITH: dict[str, Any] = {
    "string": {"segment_fit_fraction": None, "lateral_mud_mass": False},
    "contact": {"points": "ends", "span_bending": False, "deepest_point": False},
    "operation": {"mud_damping_torsional_N_m_s_per_m": 0.05},
}


def _pinned(data: dict[str, Any]) -> CaseConfig:
    """The case ``data`` with the options of :data:`RECORDED_WITH` it does not set itself."""
    base = json.loads(json.dumps(RECORDED_WITH))
    return case_from_dict(_merge(base, data))


def _merge(data: dict[str, Any], extra: dict[str, Any]) -> dict[str, Any]:
    for key, val in extra.items():
        if isinstance(val, dict):
            data.setdefault(key, {})
            _merge(data[key], val)
        else:
            data[key] = val
    return data


def _from_file(name: str, extra: dict[str, Any]) -> CaseConfig:
    data = yaml.safe_load((ROOT / "data" / "cases" / name).read_text(encoding="utf-8"))
    return _pinned(_merge(data, extra))


def _deviated(friction: str, k: int) -> CaseConfig:
    """J well (kick-off 30 m, 30 deg/30 m to 60 deg), 6 collars + 24 pipe segments with tool
    joints, bit on bottom at 300 m, drilling at 0.5 m/s with 1 mm lobes, contact on."""
    return _pinned({
        "well": {"profiles": {"j": {"kind": "j", "kop_m": 30.0, "dls_deg_per_30m": 30.0,
                                    "inc_deg": 60.0, "td_m": 600.0}}},
        "string": {"components": [
            {"type": "collar", "od_m": 0.17145, "id_m": 0.0714, "length_m": 54.0,
             "n_segments": 6},
            {"type": "drill_pipe", "od_m": 0.127, "id_m": 0.1086, "length_m": 216.0,
             "tool_joint_od_m": 0.1683, "tool_joint_id_m": 0.0826,
             "tool_joint_length_fraction": 0.05, "n_segments": 24}]},
        "operation": {"duration_s": 0.12, "bit_md_m": 300.0, "top_md_m": 0.0, "rpm": 120.0,
                      "rpm_ramp_s": 0.05, "top_axial": "neutral_point", "bit_on_bottom": True,
                      "rop_m_per_s": 0.5, "tob_Nm": 1500.0, "lobe_count": 3,
                      "lobe_amplitude_m": 0.001},
        "bit": {"model": ("given_tob", "yigit_christoforou", "prescribed_rop")[k % 3]},
        "contact": {"enabled": True,
                    "points": "ends_and_middle" if k % 2 else "ends"},
        "friction": {"model": friction, "mu_static": 0.4, "mu_dynamic": 0.3},
        "solver": {"relax_s": 0.05, "growth_work_trapezoid": False},
        "recording": {"loads_rate_hz": 250.0, "channels_rate_hz": 250.0,
                      "kinematics_rate_hz": 50.0, "events_start_s": 0.06},
    })


def _span_quasistatic() -> CaseConfig:
    """The deviated drilling case with the string's contact points, the lateral mud mass
    and the span-bending record taken quasi-statically at each sample
    (``contact.span_dynamic`` off): the span correction's arithmetic."""
    cfg = _deviated("tanh_exp", 2).model_dump(mode="json")
    data = _merge(cfg, {
        "string": {"lateral_mud_mass": True},
        "contact": {"points": "string", "span_bending": True, "deepest_point": True,
                    "span_dynamic": False},
        "operation": {"duration_s": 0.3},
    })
    return case_from_dict(data)


def _drilling_split() -> CaseConfig:
    """5 x 2 m collars in a straight 30 deg hole, wall contact, 1 m/s: one split in 2.3 s."""
    return _pinned({
        "string": {"components": [{"type": "collar", "od_m": 0.17145, "id_m": 0.0714,
                                   "length_m": 10.0, "n_segments": 5}]},
        "operation": {"bit_md_m": 12.0, "top_md_m": 0.0, "duration_s": 2.3, "rpm": 60.0,
                      "rpm_ramp_s": 0.2, "rop_m_per_s": 1.0, "top_axial": "neutral_point",
                      "neutral_point_s_from_bit_m": 6.0, "tob_Nm": 500.0},
        "contact": {"enabled": True},
        "solver": {"growth_work_trapezoid": False},
        "recording": {"channels_rate_hz": 100.0, "kinematics_rate_hz": 20.0,
                      "loads_rate_hz": 50.0},
    })


def _tripping(trip: float) -> CaseConfig:
    """4 x 5 m of drill pipe off bottom in a 30 deg J well, top fixed, tripping at ``trip``."""
    return _pinned({
        "well": {"profiles": {"j": {"kind": "j", "kop_m": 1.0, "dls_deg_per_30m": 60.0,
                                    "inc_deg": 30.0, "td_m": 200.0}}},
        "string": {"components": [{"type": "drill_pipe", "od_m": 0.127, "id_m": 0.1086,
                                   "length_m": 20.0, "n_segments": 4}]},
        "operation": {"duration_s": 0.9, "bit_md_m": 70.0, "top_md_m": 50.0,
                      "bit_on_bottom": False, "top_axial": "fixed", "rpm": 30.0,
                      "rpm_ramp_s": 0.0, "trip_speed_m_per_s": trip},
        "solver": {"relax_s": 0.05, "growth_work_trapezoid": False},
        "recording": {"channels_rate_hz": 100.0, "kinematics_rate_hz": 20.0,
                      "loads_rate_hz": 50.0},
    })


def cases() -> dict[str, tuple[CaseConfig, Any]]:
    """Name -> (case, well path or None for the case's own well)."""
    out: dict[str, tuple[CaseConfig, Any]] = {
        "vertical_quick": (_from_file("vertical_quick.yaml", {
            "operation": {"duration_s": 0.3, "lobe_amplitude_m": 0.001},
            "solver": {"growth_work_trapezoid": False}}), None),
        "case1_whirl": (_from_file("case1_whirl.yaml", {
            "operation": {"duration_s": 1.4}, "recording": {"events_start_s": 0.8},
            "solver": {"growth_work_trapezoid": False}}), None),
    }
    for k, fr in enumerate(FRICTION_MODELS):
        out[f"deviated_{fr}"] = (_deviated(fr, k), None)
    out["span_quasistatic"] = (_span_quasistatic(), None)
    out["drilling_split"] = (_drilling_split(), straight_path(100.0, inclination_deg=30.0))
    out["tripping_out"] = (_tripping(-6.0), None)
    out["tripping_in"] = (_tripping(6.0), None)
    return out


def _summary_json(summary: dict[str, Any]) -> str:
    keep = {k: v for k, v in summary.items() if k not in VOLATILE}
    return json.dumps(keep, sort_keys=True, allow_nan=True)


def run_case(config: CaseConfig, path: Any) -> dict[str, np.ndarray]:
    """Run one case in memory; the arrays a reference file holds."""
    res = simulate(config, None, progress=False, path=path)
    out: dict[str, np.ndarray] = {
        "dt_s": np.array(res.model.dt),
        "times_s": res.times_s, "loads": res.loads,
        "summary_json": np.array(_summary_json(res.summary)),
    }
    if res.span_bending is not None:
        out["span_bending"] = res.span_bending
    for name, col in res.channels.items():
        out[f"channels/{name}"] = np.asarray(col)
    kin = res.kinematics
    for name in kin.column_names:
        out[f"kinematics/{name}"] = kin.column(name).to_numpy()
    for name, arr in res.state.arrays().items():
        out[f"state/{name}"] = arr
    out["model/seg"] = res.model.seg
    out["model/jp"] = res.model.jp
    return out


def main() -> None:
    DATA.mkdir(parents=True, exist_ok=True)
    only = set(sys.argv[1:])
    for name, (cfg, path) in cases().items():
        if only and name not in only:
            continue
        arrays = run_case(cfg, path)
        np.savez_compressed(DATA / f"{name}.npz", **arrays)
        s = json.loads(str(arrays["summary_json"]))
        print(f"{name}: dt {float(arrays['dt_s']):.3g} s, {arrays['loads'].shape} loads, "
              f"status {s['status']}, whirl {s['whirl_class']}, added {s['segments_added']}, "
              f"merged {s['segments_merged']}, contact ever {s['events']['segments_in_contact_ever']}",
              flush=True)
    assert math.isfinite(1.0)


if __name__ == "__main__":
    main()
