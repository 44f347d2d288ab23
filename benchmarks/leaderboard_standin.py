"""The leaderboard's stand-in dataset: the default pipeline's 32 + 8 cases in the research
dataset's layout, so the leaderboard page runs before the research dataset is assembled.

Reads a checkout where ``make repro`` (``dvc repro``) has run: ``data/dataset/damage.parquet``
(training split), ``data/heldout/dataset/damage.parquet`` (held-out split) and
``data/heldout/design/cases.parquet`` (the held-out design, which the physics baseline
reads). Writes ``train.parquet``, ``heldout.parquet`` (each with its ``split`` column) and
``heldout_design.parquet`` into ``--out``, each atomically.

Usage: ``python benchmarks/leaderboard_standin.py [--pipeline .] [--out data/benchmark/standin]``
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import pandas as pd

from drillfatigue.files import atomic_output

SOURCES = {"train": "data/dataset/damage.parquet",
           "heldout": "data/heldout/dataset/damage.parquet",
           "heldout_design": "data/heldout/design/cases.parquet"}


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--pipeline", type=Path, default=Path("."),
                        help="a checkout where make repro has run")
    parser.add_argument("--out", type=Path, default=Path("data/benchmark/standin"))
    args = parser.parse_args(argv)
    paths = {k: args.pipeline / v for k, v in SOURCES.items()}
    missing = [str(p) for p in paths.values() if not p.is_file()]
    if missing:
        print(f"error: --pipeline: {', '.join(missing)} not found (allowed: a checkout "
              "where make repro has run)", file=sys.stderr)
        return 2
    frames = {s: pd.read_parquet(paths[s]).assign(split=s) for s in ("train", "heldout")}
    frames["heldout"] = frames["heldout"][list(frames["train"].columns)]
    frames["heldout_design"] = pd.read_parquet(paths["heldout_design"],
                                               columns=["case_id", "case_json"])
    args.out.mkdir(parents=True, exist_ok=True)
    for name, frame in frames.items():
        with atomic_output(args.out / f"{name}.parquet") as tmp:
            frame.to_parquet(tmp, index=False)
    print(f"stand-in: {frames['train']['case_id'].nunique()} + "
          f"{frames['heldout']['case_id'].nunique()} cases -> {args.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
