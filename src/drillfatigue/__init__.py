"""drillfatigue: drill-string dynamics in deviated wells and fatigue prognosis.

Subpackages: ``well`` (trajectories, wellbore geometry), ``string`` (components
and segmentation), ``dynamics`` (numba rigid-segment simulator), ``fatigue``
(stresses, rainflow, S-N, Miner, critical plane, API RP7G), ``surrogate``
(torch ensemble), ``sweep`` (case design and parallel runs), ``config``
(validated parameter models), ``cli``. SI units throughout the code.

Importing the package changes nothing outside it (no environment variable,
no numba setting, no plotting backend); :func:`scope_numba_cache` keys numba's
on-disk cache by the kernels' source and is called explicitly by the command
line, the pipeline stages and the tests.
"""

from __future__ import annotations

from drillfatigue.numba_cache import scope_numba_cache, source_digest

__all__ = ["SimulationResult", "scope_numba_cache", "simulate", "source_digest"]

__version__ = "0.1.0"


def __getattr__(name: str) -> object:
    """Lazy top-level API: ``drillfatigue.simulate``.

    Imported on first use, not at the top: the simulator imports this package
    (a real cycle at import time), and its numba kernels must load only after
    :func:`_scope_numba_cache` has chosen the cache folder.
    """
    if name == "simulate":
        from drillfatigue.dynamics.api import simulate  # cycle: dynamics.api imports this package

        return simulate
    if name == "SimulationResult":
        from drillfatigue.dynamics.api import SimulationResult  # cycle: dynamics.api imports this package

        return SimulationResult
    raise AttributeError(f"module 'drillfatigue' has no attribute {name!r}")
