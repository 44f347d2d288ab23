"""Run every ``benchmarks/bench_*.py`` in turn: ``python benchmarks/run_all.py [--quick]``.

Each script writes its own ``benchmarks/results/<name>.json``; ``--quick`` is
passed through. Exit code: the number of benchmarks that failed. numba's cache
is keyed by the kernels' source once here (the scripts inherit the folder),
and ``tests/`` is put on ``PYTHONPATH`` for the synthetic sweep cases of
``bench_sweep.py`` (:mod:`testkit.synthetic_sweep`).
"""

from __future__ import annotations

import os
import subprocess
import sys
import time
from pathlib import Path

from drillfatigue.numba_cache import scope_numba_cache


def main(argv: list[str] | None = None) -> int:
    args = sys.argv[1:] if argv is None else argv
    quick = ["--quick"] if "--quick" in args else []
    here = Path(__file__).resolve().parent
    scope_numba_cache()
    tests = str(here.parent / "tests")
    os.environ["PYTHONPATH"] = os.pathsep.join(p for p in (tests, os.environ.get("PYTHONPATH"))
                                               if p)
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
