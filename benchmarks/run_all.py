"""Run every ``benchmarks/bench_*.py`` in turn: ``python benchmarks/run_all.py [--quick]``.

Each script writes its own ``benchmarks/results/<name>.json``; ``--quick`` is
passed through. Exit code: the number of benchmarks that failed.
"""

from __future__ import annotations

import subprocess
import sys
import time
from pathlib import Path


def main(argv: list[str] | None = None) -> int:
    args = sys.argv[1:] if argv is None else argv
    quick = ["--quick"] if "--quick" in args else []
    here = Path(__file__).resolve().parent
    failed = 0
    for script in sorted(here.glob("bench_*.py")):
        t0 = time.perf_counter()
        print(f"== {script.name} {' '.join(quick)}", flush=True)
        rc = subprocess.call([sys.executable, str(script), *quick])
        print(f"== {script.name}: {'ok' if rc == 0 else f'FAILED ({rc})'} "
              f"in {time.perf_counter() - t0:.1f} s", flush=True)
        failed += rc != 0
    return failed


if __name__ == "__main__":
    sys.exit(main())
