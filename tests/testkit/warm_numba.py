"""Fill numba's on-disk cache (and the tiny surrogate's) before the test workers start.

On a fresh clone numba's cache is empty, and every process that meets a kernel first
compiles it: the two test workers and the commands they start compiled the simulator
and the fatigue kernels side by side, two minutes of CPU each time. ``tests/conftest.py``
runs this module twice at the start of a parallel run, one process per part, so each
kernel is compiled once and the workers load it:

``sim``
    a short research case at ``params.yaml`` (the simulator with the rig, the span
    record, every fatigue criterion, API RP7G, the hole-geometry features and the
    dataset rows).
``models``
    every fatigue criterion on a synthetic run folder (so the ``sim`` part, which
    reaches its fatigue after a minute of compiling the simulator, finds those
    kernels compiled), the tiny stand-in surrogate of :mod:`testkit.tiny_surrogate`
    (fitted into its shared cache) and its served gradient boosting's prediction kernels.

Run: ``python -m testkit.warm_numba sim|models`` (``tests/`` on ``sys.path``). A part
that fails is left to the tests that meet the same code: they report it.
"""

from __future__ import annotations

import sys
import tempfile
import time
from pathlib import Path

from drillfatigue.numba_cache import scope_numba_cache

ROOT = Path(__file__).resolve().parents[2]


def warm_sim() -> None:
    from drillfatigue.config import load_params
    from drillfatigue.sweep.research import _case_inputs, research_design
    from drillfatigue.sweep.research_case import _warmup

    p = load_params(ROOT / "params.yaml")
    row = research_design(p, 1, 0)["train"].to_dict("records")[0]
    _warmup({"row": row, "inputs": _case_inputs(p, row, list(p.sweep.variables))})


def warm_models() -> None:
    from drillfatigue.config import load_params
    from drillfatigue.fatigue.run import evaluate_run
    from drillfatigue.surrogate import Surrogate
    from testkit.fatigue_runs import write_run_dir
    from testkit.tiny_surrogate import tiny_table, train_tiny_surrogate

    with tempfile.TemporaryDirectory(prefix="warm-") as tmp:
        run = write_run_dir(Path(tmp) / "run")
        cfg = load_params(ROOT / "params.yaml").fatigue.model_copy(update={"plots": False})
        for criterion in ("matake", "uniaxial", "findley", "fatemi_socie"):
            evaluate_run(run, cfg, None, criterion=criterion)
        model = Surrogate.load(train_tiny_surrogate(ROOT / "params.yaml", Path(tmp) / "m"))
        table = tiny_table(tuple(model.features), n_cases=2)
        model.predict(table, refuse=False)


PARTS = {"sim": warm_sim, "models": warm_models}


def main(argv: list[str]) -> int:
    scope_numba_cache()
    t0 = time.perf_counter()
    try:
        PARTS[argv[0]]()
    except Exception as exc:  # noqa: BLE001 - the tests that meet this code report it
        print(f"warm_numba {argv[0]}: failed ({type(exc).__name__}: {exc}); the tests "
              "compile what they need", file=sys.stderr)
        return 0
    print(f"warm_numba {argv[0]}: {time.perf_counter() - t0:.0f} s", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
