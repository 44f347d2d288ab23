"""Well outputs: profile plots and the files of the ``wells`` pipeline stage.

:func:`write_well_outputs` writes, for every profile of a ``well`` section,
``<out>/<name>/survey.csv`` (``md_m,inc_deg,azi_deg``), ``cylinders.parquet``
(the cylinder chain, one row per cylinder) and ``profile.png``, and returns
the summary (TD, end point, maximum DLS, number of cylinders per profile).
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import numpy as np
import pyarrow as pa
import pyarrow.parquet as pq

from drillfatigue.config.well import WellConfig
from drillfatigue.files import OutputFolder, atomic_output
from drillfatigue.io.display import Display
from drillfatigue.plotting import figure
from drillfatigue.well.profiles import build_plan_survey
from drillfatigue.well.survey import Survey, write_survey_csv
from drillfatigue.well.tortuosity import apply_tortuosity, tortuosity_report
from drillfatigue.well.wellbore import Wellbore, build_wellbore, resample_path

__all__ = ["cylinder_table", "plot_survey", "write_well_outputs"]

#: Kind of the ownership marker of a well-profile output folder.
WELL_KIND = "well"


def _figure(sv: Survey, title: str, display: Any = None):  # noqa: ANN202 - matplotlib Figure
    d = display if display is not None else Display("si")
    lu = d.unit("length")
    fig = figure(figsize=(13, 4.5))
    ax3 = fig.add_subplot(1, 3, 1, projection="3d")
    # Draw the minimum-curvature arcs, not the chords between stations.
    _, fine, _ = resample_path(sv, 2.0, np.empty(0), math.inf)
    n, e, tvd = (d.value("length", v) for v in fine.T)
    ax3.plot(e, n, tvd, lw=1.5)
    half = 0.5 * max(np.ptp(n), np.ptp(e), np.ptp(tvd), 1.0)
    for setter, v in ((ax3.set_xlim, e), (ax3.set_ylim, n), (ax3.set_zlim, tvd)):
        mid = 0.5 * (v.min() + v.max())
        setter(mid - half, mid + half)
    ax3.set_xlabel(f"east, {lu}")
    ax3.set_ylabel(f"north, {lu}")
    ax3.set_zlabel(f"TVD, {lu}")
    ax3.invert_zaxis()
    ax3.set_title("3D view")
    end = sv.pos_m[-1]
    az = math.atan2(end[1], end[0]) if math.hypot(end[0], end[1]) > 1e-9 else 0.0
    vs = n * math.cos(az) + e * math.sin(az)
    ax = fig.add_subplot(1, 3, 2)
    ax.plot(vs, tvd, lw=1.5)
    ax.invert_yaxis()
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel(f"vertical section at {math.degrees(az) % 360:.1f} deg, {lu}")
    ax.set_ylabel(f"TVD, {lu}")
    ax.set_title("vertical section")
    ax.grid(alpha=0.3)
    ax = fig.add_subplot(1, 3, 3)
    ax.step(d.value("length", sv.md_m), d.value("dogleg", sv.dls_deg_per_30m), where="pre")
    ax.set_xlabel(f"MD, {lu}")
    ax.set_ylabel(f"DLS, {d.unit('dogleg')}")
    ax.set_title("dogleg severity")
    ax.grid(alpha=0.3)
    fig.suptitle(title)
    fig.tight_layout()
    return fig


def plot_survey(sv: Survey, path: str | Path, title: str, display: Any = None) -> None:
    """Draw 3D view, vertical section and DLS vs MD; write ``path`` atomically.

    ``display``: a :class:`drillfatigue.io.display.Display` (default SI).
    """
    path = Path(path)
    suffix = path.suffix.lower().lstrip(".")
    fig = _figure(sv, title, display)
    with atomic_output(path) as tmp:
        fig.savefig(tmp, format=suffix, dpi=110)


def cylinder_table(wb: Wellbore) -> dict[str, np.ndarray]:
    """Columns of the cylinder chain: MDs, end points, axis, length, radius, curvature."""
    cols: dict[str, np.ndarray] = {"md0_m": wb.md0_m, "md1_m": wb.md1_m}
    for k, c in enumerate(("north", "east", "tvd")):
        cols[f"p0_{c}_m"] = wb.p0_m[:, k]
        cols[f"p1_{c}_m"] = wb.p1_m[:, k]
        cols[f"axis_{c}"] = wb.axis[:, k]
    cols["length_m"] = wb.length_m
    cols["radius_m"] = wb.radius_m
    cols["curvature_rad_per_m"] = np.asarray(wb.curvature_at_md(0.5 * (wb.md0_m + wb.md1_m)))
    return {k: np.ascontiguousarray(v, dtype=float) for k, v in cols.items()}


def write_well_outputs(cfg: WellConfig, out_dir: str | Path,
                       plot: bool = True) -> dict[str, dict[str, Any]]:
    """Build every profile of ``cfg`` and write its survey, cylinders and plot.

    Everything is computed and every profile folder ``out_dir/<name>`` is
    checked first (so bad input writes nothing), then each file is written
    atomically. Each profile folder is a ``well`` output folder
    (:class:`drillfatigue.files.OutputFolder`): one holding files drillfatigue
    did not write is refused, and only the profile's own files are replaced.

    With ``cfg.tortuosity`` set, the survey, cylinders and plot are those of
    the tortuous hole, and each profile's summary has a ``tortuosity`` entry
    (:func:`drillfatigue.well.tortuosity.tortuosity_report`).

    Returns
    -------
    dict
        ``{name: {kind, td_m, end_north_m, end_east_m, end_tvd_m,
        max_dls_deg_per_30m, max_dls_deg_per_100ft, n_cylinders,
        min_cylinder_length_m[, tortuosity]}}``.
    """
    out = Path(out_dir)
    built = {}
    reports: dict[str, dict[str, Any]] = {}
    for name, spec in cfg.profiles.items():
        plan = build_plan_survey(cfg, name)
        sv = plan if cfg.tortuosity is None else apply_tortuosity(plan, cfg.tortuosity)
        if cfg.tortuosity is not None:
            reports[name] = tortuosity_report(plan, sv, cfg.tortuosity)
        built[name] = (spec.kind, sv, build_wellbore(cfg, name, survey=sv))
    for name in built:
        OutputFolder.check(out / name, WELL_KIND, f"{out / name}")
    summary: dict[str, dict[str, Any]] = {}
    for name, (kind, sv, wb) in built.items():
        folder = OutputFolder(out / name, WELL_KIND, f"{out / name}")
        write_survey_csv(sv, folder.file("survey.csv"))
        with atomic_output(folder.file("cylinders.parquet")) as tmp:
            pq.write_table(pa.table(cylinder_table(wb)), tmp)
        if plot:
            plot_survey(sv, folder.file("profile.png"), f"well profile {name} ({kind})")
        end = sv.pos_m[-1]
        summary[name] = {
            "kind": kind,
            "td_m": float(sv.md_m[-1]),
            "end_north_m": float(end[0]),
            "end_east_m": float(end[1]),
            "end_tvd_m": float(end[2]),
            "max_dls_deg_per_30m": sv.max_dls_deg_per_30m,
            "max_dls_deg_per_100ft": float(sv.dls_deg_per_100ft.max()),
            "n_cylinders": wb.n,
            "min_cylinder_length_m": float(wb.length_m.min()),
        }
        if name in reports:
            summary[name]["tortuosity"] = reports[name]
    return summary
