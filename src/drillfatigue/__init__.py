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

from importlib.metadata import PackageNotFoundError, version

from drillfatigue.numba_cache import scope_numba_cache, source_digest

__all__ = ["SimulationResult", "scope_numba_cache", "simulate", "source_digest"]

try:
    __version__ = version("drillfatigue")
except PackageNotFoundError:  # sources on the path without an installed distribution
    __version__ = "0+unknown"


def __getattr__(name: str) -> object:
    """Lazy top-level API: ``drillfatigue.simulate``.

    Imported on first use, not at the top: the simulator's numba kernels must load
    only after :func:`scope_numba_cache` has chosen the cache folder, and a command
    that never simulates does not pay for importing them.
    """
    if name == "simulate":
        from drillfatigue.dynamics.run.simulation import simulate  # start-up: numba loads on use

        return simulate
    if name == "SimulationResult":
        from drillfatigue.dynamics.run.simulation import SimulationResult  # start-up: numba loads on use

        return SimulationResult
    raise AttributeError(f"module 'drillfatigue' has no attribute {name!r}")
