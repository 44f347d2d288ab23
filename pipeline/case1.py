"""DVC stage ``case1``: the founding paper's case study 1 (see drillfatigue.studies.case1).

Reads the ``case1`` section of params.yaml, writes ``data/case1/`` (tables, figures,
runs) and ``metrics/case1.json``.

Usage: ``python pipeline/case1.py [--params params.yaml] [--out data/case1]
[--metrics metrics/case1.json]``
"""

from __future__ import annotations

import argparse
import sys

from drillfatigue.errors import InputError
from drillfatigue.studies.stages import run_study


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--params", default="params.yaml")
    parser.add_argument("--out", default="data/case1")
    parser.add_argument("--metrics", default=None)
    args = parser.parse_args(argv)
    try:
        run_study("case1", args.params, args.out, args.metrics)
    except InputError as exc:
        print(f"error: {exc.one_line()}", file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main())
