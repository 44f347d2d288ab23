"""What hole tortuosity does to the soft-string torque and drag and to case 3's loads.

Case 3 of the founding paper (``params.yaml``'s ``case3`` section: profile_1's
horizontal section, the paper BHA, the bit on bottom at ``bit_md_end_m``, 50 rpm,
docs/case3.md) is run on the plan and on the same plan with the micro-doglegs of
``well.tortuosity`` (docs/wells.md#tortuosity) from the surface down:

- soft string (:func:`drillfatigue.softstring.torque_drag.torque_drag_for_case`,
  string and friction of case 3's simulator case, drilling at its autodriller's WOB
  set-point and the bit law's torque at 50 rpm): surface torque rotating off bottom
  and drilling, hook loads picking up, slacking off and rotating, largest side force;
- sine waves of period 30 m adding a peak dogleg severity of 2 deg/30 m (amplitude
  0.318 deg), a mean of 2 deg/30 m (0.5 deg, what torque-and-drag programs call a
  "2 deg/30 m" sine), and amplitude 1 deg (peak 6.3 deg/30 m); seeded random tilts
  of 1 deg every 30 m in both planes (five seeds);
- with ``--dynamics``, the case-3 simulation itself (the reduced window of
  ``params.yaml`` unless its section is changed) on the plan and with the 2 deg/30 m
  peak and the 1 deg sine: the lives at 8, 40 and 80 m behind the bit and at the
  collar connection 10.5 m behind it (the near-bit collar's top, a joint whatever
  the segmentation), the load that sets each, and each joint's bending amplitude.
  The hole-fit rule of the segmentation (``string.segment_fit_fraction``) cuts the
  collars shorter in a tortuous hole, so the joints nearest 8, 40 and 80 m may lie
  elsewhere than on the plan: each row names its joint's distance from the bit.

With ``--figure PATH``: the dogleg severity along MD and the rotating soft-string
torque along the string, plan beside the sine tortuosities (``docs/img/tortuosity.png``).

Usage: ``python benchmarks/tortuosity.py [--params params.yaml] [--dynamics]
[--figure docs/img/tortuosity.png] [--out benchmarks/results/tortuosity.json]``. The
soft-string part takes seconds; the dynamic part a few minutes (numba compilation on
first use included).
"""

from __future__ import annotations

import argparse
import math
import platform
import tempfile
import time
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

from drillfatigue.files import atomic_output
from drillfatigue.numba_cache import scope_numba_cache

# before any kernel module is imported (numba binds a kernel's cache folder then)
scope_numba_cache()

from drillfatigue import rundir  # noqa: E402
from drillfatigue.config import case_from_dict  # noqa: E402
from drillfatigue.softstring.torque_drag import torque_drag_for_case  # noqa: E402
from drillfatigue.plotting import subplots  # noqa: E402
from drillfatigue.studies.case3 import case_dict, run_case3  # noqa: E402
from drillfatigue.studies.common import write_json  # noqa: E402
from drillfatigue.studies.stages import load_section, shared_sections  # noqa: E402
from drillfatigue.well import build_plan_survey, build_survey  # noqa: E402
from drillfatigue.well.tortuosity import tortuosity_report  # noqa: E402

RESULT = Path(__file__).parent / "results" / "tortuosity.json"
PERIOD_M = 30.0
#: amplitude (deg) whose sine adds a peak dogleg severity of 2 deg/30 m over PERIOD_M
PEAK_2_AMPLITUDE_DEG = 2.0 / (2.0 * math.pi) * PERIOD_M / 30.0
SINES = {"sine_peak_2deg_per_30m": PEAK_2_AMPLITUDE_DEG,
         "sine_mean_2deg_per_30m": 0.5,
         "sine_1deg": 1.0}
SEEDS = (0, 1, 2, 3, 4)
DYNAMIC = ("plan", "sine_peak_2deg_per_30m", "sine_1deg")
#: the collar connection at the top of the near-bit collar, m behind the bit (docs/case3.md)
NEAR_BIT_CONNECTION_M = 10.5


def _variants() -> dict[str, dict[str, Any] | None]:
    out: dict[str, dict[str, Any] | None] = {"plan": None}
    for name, amp in SINES.items():
        out[name] = {"model": "sine", "amplitude_deg": amp, "period_m": PERIOD_M}
    for seed in SEEDS:
        out[f"random_1deg_both_seed{seed}"] = {"model": "random", "amplitude_deg": 1.0,
                                              "period_m": PERIOD_M, "direction": "both",
                                              "seed": seed}
    return out


def _hole(case: dict[str, Any]) -> dict[str, Any]:
    """The tortuosity report of the case's hole (plan beside tortuous hole)."""
    well = case_from_dict(case).well
    rep = tortuosity_report(build_plan_survey(well), build_survey(well), well.tortuosity)
    return {k: rep[k] for k in ("plan", "tortuous")}


def soft_string(case: dict[str, Any], wob_N: float) -> dict[str, Any]:
    """Surface values and largest side force of the soft string in the case's hole."""
    td = torque_drag_for_case(case_from_dict(case), wob_N=wob_N)
    s = td.summary()
    return {**s, "max_side_force_rotating_N_per_m": float(td.normal_rotating_N_per_m.max()),
            "hole": _hole(case)}


def draw(cases: dict[str, dict[str, Any]], wob_N: float, path: Path) -> None:
    """DLS along MD and rotating torque along the string, plan and sine tortuosities."""
    fig, (ax1, ax2) = subplots(1, 2, figsize=(12.0, 4.2))
    for name, case in cases.items():
        well = case_from_dict(case).well
        sv = build_survey(well)
        td = torque_drag_for_case(case_from_dict(case), wob_N=wob_N)
        lw = 1.6 if name == "plan" else 0.9
        ax1.plot(sv.md_m, sv.dls_deg_per_30m, lw=lw, label=name.replace("_", " "))
        ax2.plot(td.md_m, td.torque_rotating_Nm / 1e3, lw=lw, label=name.replace("_", " "))
    ax1.set_xlabel("MD, m")
    ax1.set_ylabel("DLS, deg/30 m")
    ax1.set_title("dogleg severity of the hole (case 3's well, profile_1)")
    ax2.set_xlabel("MD, m")
    ax2.set_ylabel("torque, kN m")
    ax2.set_title("soft-string torque, rotating off bottom")
    for ax in (ax1, ax2):
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
    fig.tight_layout()
    with atomic_output(path) as tmp:
        fig.savefig(tmp, format=path.suffix.lstrip(".") or "png", dpi=100)


def _connection_bending(run_dir: Path, joint: int) -> dict[str, float]:
    """Half the peak-to-peak of the joint's bending moment over the window, in the
    direction where it is largest (rigid joint moment and span correction), N m."""
    loads = pd.read_parquet(run_dir / rundir.LOADS)
    h = loads[loads["joint"] == joint]
    out: dict[str, float] = {}
    for name, cols in (("joint", ("bending_x_Nm", "bending_y_Nm")),
                       ("span", ("span_bending_x_Nm", "span_bending_y_Nm"))):
        if not all(c in h.columns for c in cols):
            continue
        m = h[list(cols)].to_numpy(dtype=float)
        phi = np.linspace(0.0, math.pi, 36, endpoint=False)
        proj = m @ np.stack([np.cos(phi), np.sin(phi)])
        out[f"{name}_bending_amplitude_Nm"] = float(0.5 * np.ptp(proj, axis=0).max())
    return out


def dynamics(params: Path, wells: dict[str, dict[str, Any]]) -> dict[str, Any]:
    """Case 3 on each well section of ``wells``: lives, dominant loads, near-bit bending."""
    cfg = load_section(params, "case3")
    cfg = cfg.model_copy(update={"s_from_bit_m": (*cfg.s_from_bit_m, NEAR_BIT_CONNECTION_M)})
    _, fatigue = shared_sections(params)
    out: dict[str, Any] = {}
    with tempfile.TemporaryDirectory(prefix="tortuosity_case3_") as tmp:
        for name, well in wells.items():
            t0 = time.perf_counter()
            summ = run_case3(cfg, Path(tmp) / name, well=well, fatigue=fatigue)
            rows = []
            for r in summ["rows"]:
                run_dir = Path(tmp) / name / "runs" / cfg.profile
                rows.append({k: r[k] for k in (
                    "s_from_bit_m", "joint", "joint_s_from_bit_m", "md_m",
                    "hole_dls_deg_per_30m", "life_h", "critical_location", "dominant_load",
                    "paper_life_h", "sigma_amplitude_MPa_axial_torsion",
                    "sigma_amplitude_MPa_joint_bending", "sigma_amplitude_MPa_span_bending",
                    "tau_amplitude_MPa_axial_torsion")}
                    | _connection_bending(run_dir, int(r["joint"])))
            out[name] = {"rows": rows, "recorded_s": summ["recorded_s"],
                         "simulated_s": summ["simulated_s"], "n_segments": summ["n_segments"],
                         "simulation_wall_s": summ["wall_s"],
                         "wall_s_with_compilation_and_fatigue": time.perf_counter() - t0,
                         "drilling": {k: summ.get("drilling", {}).get(k) for k in
                                      ("mean_wob_N", "mean_surface_torque_Nm",
                                       "on_bottom_fraction", "mean_rop_m_per_h")}}
            print(f"case 3 {name}: lives "
                  + ", ".join(f"{r['s_from_bit_m']:g} m {r['life_h']:.3g} h" for r in rows),
                  flush=True)
    return out


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--params", default="params.yaml")
    ap.add_argument("--out", default=str(RESULT))
    ap.add_argument("--dynamics", action="store_true", help="also run case 3 (minutes)")
    ap.add_argument("--figure", default=None, help="also draw the DLS and torque (PNG)")
    args = ap.parse_args(argv)
    params = Path(args.params)
    cfg = load_section(params, "case3")
    well, _ = shared_sections(params)
    wells = {name: (well if spec is None else {**well, "tortuosity": spec})
             for name, spec in _variants().items()}
    cases: dict[str, dict[str, Any]] = {}
    out: dict[str, Any] = {
        "case": {"section": "case3", "profile": cfg.profile, "bit_md_m": cfg.bit_md_end_m,
                 "bha": cfg.bha, "rpm": cfg.rpm, "wob_N": cfg.wob_set_N,
                 "tortuosity_from_md_m": 0.0,
                 "period_m": PERIOD_M},
        "machine": platform.processor() or platform.machine(),
        "soft_string": {},
    }
    for name, w in wells.items():
        case, _ = case_dict(cfg, None, w)
        # the simulator's case turns by its rpm table; the bit law's torque wants the speed
        case["operation"]["rpm"] = cfg.rpm
        cases[name] = case
        out["soft_string"][name] = soft_string(case, cfg.wob_set_N)
        s = out["soft_string"][name]
        print(f"{name}: rotating torque {s['surface_torque_rotating_Nm'] / 1e3:.2f} kN m, "
              f"drilling {s['surface_torque_drilling_Nm'] / 1e3:.2f} kN m, pick-up "
              f"{s['hookload_pickup_N'] / 1e3:.1f} kN, slack-off "
              f"{s['hookload_slackoff_N'] / 1e3:.1f} kN", flush=True)
    plan = out["soft_string"]["plan"]
    rnd = [out["soft_string"][f"random_1deg_both_seed{s}"] for s in SEEDS]
    out["random_1deg_both"] = {
        k: {"mean": float(np.mean([r[k] for r in rnd])), "min": float(min(r[k] for r in rnd)),
            "max": float(max(r[k] for r in rnd))}
        for k in ("surface_torque_rotating_Nm", "surface_torque_drilling_Nm",
                  "hookload_pickup_N", "hookload_slackoff_N")}
    out["ratio_to_plan"] = {
        name: {k: s[k] / plan[k] for k in ("surface_torque_rotating_Nm",
                                           "surface_torque_drilling_Nm", "hookload_pickup_N",
                                           "hookload_slackoff_N")}
        for name, s in out["soft_string"].items() if name != "plan"}
    if args.figure is not None:
        draw({k: cases[k] for k in ("plan", *SINES)}, cfg.wob_set_N, Path(args.figure))
    if args.dynamics:
        out["case3_dynamics"] = dynamics(params, {k: wells[k] for k in DYNAMIC})
    write_json(Path(args.out), out)  # NaN (no paper life at 10.5 m) as null
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
