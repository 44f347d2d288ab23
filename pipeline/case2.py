"""DVC stage ``case2``: the founding paper's case study 2 (see drillfatigue.studies.case2).

Reads the ``case2`` section of params.yaml, writes ``data/case2/`` (tables, figures,
runs) and ``metrics/case2.json``.

Usage: ``python pipeline/case2.py [--params params.yaml] [--out data/case2]
[--metrics metrics/case2.json]``
"""

from __future__ import annotations

import argparse
import sys

from drillfatigue.errors import InputError
from drillfatigue.studies.stages import run_study


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--params", default="params.yaml")
    parser.add_argument("--out", default="data/case2")
    parser.add_argument("--metrics", default=None)
    args = parser.parse_args(argv)
    try:
        run_study("case2", args.params, args.out, args.metrics)
    except InputError as exc:
        print(f"error: {exc.one_line()}", file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main())
