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
from drillfatigue.files import atomic_output
from drillfatigue.well.profiles import build_survey
from drillfatigue.well.survey import Survey, write_survey_csv
from drillfatigue.well.wellbore import Wellbore, build_wellbore, resample_path

__all__ = ["cylinder_table", "plot_survey", "write_well_outputs"]


def _figure(sv: Survey, title: str):  # noqa: ANN202 - matplotlib Figure
    # matplotlib is imported where a figure is drawn: its backend is chosen here, and
    # choosing it at module import would be a global side effect
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig = plt.figure(figsize=(13, 4.5))
    ax3 = fig.add_subplot(1, 3, 1, projection="3d")
    # Draw the minimum-curvature arcs, not the chords between stations.
    _, fine, _ = resample_path(sv, 2.0, np.empty(0), math.inf)
    n, e, tvd = fine.T
    ax3.plot(e, n, tvd, lw=1.5)
    half = 0.5 * max(np.ptp(n), np.ptp(e), np.ptp(tvd), 1.0)
    for setter, v in ((ax3.set_xlim, e), (ax3.set_ylim, n), (ax3.set_zlim, tvd)):
        mid = 0.5 * (v.min() + v.max())
        setter(mid - half, mid + half)
    ax3.set_xlabel("east, m")
    ax3.set_ylabel("north, m")
    ax3.set_zlabel("TVD, m")
    ax3.invert_zaxis()
    ax3.set_title("3D view")
    end = sv.pos_m[-1]
    az = math.atan2(end[1], end[0]) if math.hypot(end[0], end[1]) > 1e-9 else 0.0
    vs = n * math.cos(az) + e * math.sin(az)
    ax = fig.add_subplot(1, 3, 2)
    ax.plot(vs, tvd, lw=1.5)
    ax.invert_yaxis()
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel(f"vertical section at {math.degrees(az) % 360:.1f} deg, m")
    ax.set_ylabel("TVD, m")
    ax.set_title("vertical section")
    ax.grid(alpha=0.3)
    ax = fig.add_subplot(1, 3, 3)
    ax.step(sv.md_m, sv.dls_deg_per_30m, where="pre")
    ax.set_xlabel("MD, m")
    ax.set_ylabel("DLS, deg/30 m")
    ax.set_title("dogleg severity")
    ax.grid(alpha=0.3)
    fig.suptitle(title)
    fig.tight_layout()
    return fig


def plot_survey(sv: Survey, path: str | Path, title: str) -> None:
    """Draw 3D view, vertical section and DLS vs MD; write ``path`` atomically."""
    # matplotlib is imported where a figure is drawn: its backend is chosen here, and
    # choosing it at module import would be a global side effect
    import matplotlib.pyplot as plt

    path = Path(path)
    suffix = path.suffix.lower().lstrip(".")
    fig = _figure(sv, title)
    try:
        with atomic_output(path) as tmp:
            fig.savefig(tmp, format=suffix, dpi=110)
    finally:
        plt.close(fig)


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

    Everything is computed first (so bad input writes nothing), then each file
    is written atomically.

    Returns
    -------
    dict
        ``{name: {kind, td_m, end_north_m, end_east_m, end_tvd_m,
        max_dls_deg_per_30m, max_dls_deg_per_100ft, n_cylinders,
        min_cylinder_length_m}}``.
    """
    out = Path(out_dir)
    built = {}
    for name, spec in cfg.profiles.items():
        sv = build_survey(cfg, name)
        built[name] = (spec.kind, sv, build_wellbore(cfg, name, survey=sv))
    summary: dict[str, dict[str, Any]] = {}
    for name, (kind, sv, wb) in built.items():
        folder = out / name
        folder.mkdir(parents=True, exist_ok=True)
        write_survey_csv(sv, folder / "survey.csv")
        with atomic_output(folder / "cylinders.parquet") as tmp:
            pq.write_table(pa.table(cylinder_table(wb)), tmp)
        if plot:
            plot_survey(sv, folder / "profile.png", f"well profile {name} ({kind})")
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
    return summary
