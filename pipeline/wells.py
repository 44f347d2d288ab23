"""DVC stage ``wells``: build every well profile named in params.yaml.

Reads the ``well`` section of ``params.yaml`` and writes, per profile,
``data/wells/<name>/survey.csv``, ``cylinders.parquet`` and ``profile.png``,
plus the metrics file ``data/wells/summary.json`` (TD, end point, maximum DLS
per profile, and the spread of the case-2 family's end points).

Usage: ``python pipeline/wells.py [--params params.yaml] [--out data/wells]``
"""

from __future__ import annotations

import json
import sys
from argparse import Namespace
from pathlib import Path

from drillfatigue.numba_cache import scope_numba_cache

# Before any kernel module is imported: numba binds a kernel's cache folder
# when the kernel is decorated, so a later call would leave the kernels
# imported above it in the unscoped in-tree cache (stale across modules).
scope_numba_cache()

from drillfatigue.config import Params  # noqa: E402
from drillfatigue.stage import Option, stage_main  # noqa: E402
from drillfatigue.well.outputs import write_well_outputs  # noqa: E402
from drillfatigue.well.survey import atomic_output  # noqa: E402


def wells(params: Params, args: Namespace) -> None:
    cfg = params.well
    summary = write_well_outputs(cfg, args.out)
    family = [s for n, s in summary.items() if cfg.profiles[n].kind == "family_member"]
    metrics = {"profiles": summary}
    if family:
        spread = max(
            max(abs(a[k] - b[k]) for k in ("end_north_m", "end_east_m", "end_tvd_m"))
            for a in family for b in family)
        metrics["family_end_spread_m"] = spread
    with atomic_output(Path(args.out) / "summary.json") as tmp:
        tmp.write_text(json.dumps(metrics, indent=2) + "\n", encoding="utf-8")


def main(argv: list[str] | None = None) -> int:
    return stage_main(__doc__, wells, [Option("--out", default="data/wells")], argv)


if __name__ == "__main__":
    sys.exit(main())
