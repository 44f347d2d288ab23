"""DVC stage ``research_dataset``: assemble the research dataset from its committed case files.

``drillfatigue dataset research`` keeps each finished case's rows in
``data/research/cases/{train,heldout}/<case_id>.parquet`` (committed in git);
this stage assembles them into ``data/research/dataset/{train,heldout}.parquet``
and ``constants.json`` (DVC outputs), byte for byte what the research run
assembles (:func:`drillfatigue.sweep.research.assemble_research`). It runs no
simulation: a designed case without its file, or case files of more than one
physics digest (but digests that ``drillfatigue dataset restamp`` found equal, listed
in ``data/research/digests.json``), is refused (exit code 2) and nothing is written.

Usage: ``python pipeline/research_dataset.py [--params params.yaml] [--root data/research]``
"""

from __future__ import annotations

import sys
from argparse import Namespace
from pathlib import Path

from drillfatigue.numba_cache import scope_numba_cache

# Before any kernel module is imported (see pipeline/wells.py).
scope_numba_cache()

from drillfatigue.benchmark.card import case_provenance  # noqa: E402
from drillfatigue.config import Params  # noqa: E402
from drillfatigue.errors import InputError  # noqa: E402
from drillfatigue.stage import Option, stage_main  # noqa: E402
from drillfatigue.sweep.design import read_cases  # noqa: E402
from drillfatigue.sweep.research import SPLITS, assemble_research, read_lineage  # noqa: E402


def check_case_files(root: Path) -> None:
    """Raise InputError unless every designed case has its file, all of one physics digest."""
    for split in SPLITS:
        design = read_cases(root / "design" / f"{split}.parquet")
        missing = [c for c in design["case_id"]
                   if not (root / "cases" / split / f"{c}.parquet").is_file()]
        if missing:
            raise InputError(f"{root}/cases/{split}", f"{len(missing)} of {len(design)} designed "
                             "cases have no case file", "every case finished (run drillfatigue "
                             "dataset research to continue the run)")
    digests = set((case_provenance(root / "dataset") or {}).get("physics_digests", {}))
    listed = {e["physics_digest"] for e in read_lineage(root)}
    if len(digests) != 1 and not (digests and digests <= listed):
        raise InputError(f"{root}/cases", f"case files of {len(digests)} physics digests not "
                         "found equal", "one physics digest, or digests that drillfatigue "
                         "dataset restamp found equal (digests.json)")


def research_dataset(params: Params, args: Namespace) -> str:
    root = Path(args.root)
    check_case_files(root)
    counts = assemble_research(root, params)
    return (f"research dataset: {counts['n_cases_train']} + {counts['n_cases_heldout']} cases, "
            f"{counts['n_rows_train']} + {counts['n_rows_heldout']} rows -> {root / 'dataset'}")


def main(argv: list[str] | None = None) -> int:
    return stage_main(__doc__, research_dataset, [Option("--root", default="data/research")], argv)


if __name__ == "__main__":
    sys.exit(main())
