"""Numba rigid-segment drill-string dynamics (docs/model.md), a folder per kind of submodel.

* :mod:`~drillfatigue.dynamics.core` -- array layout, bundles, status codes, rigid bodies, joints;
* :mod:`~drillfatigue.dynamics.step` -- the force assembly and the integrator;
* :mod:`~drillfatigue.dynamics.contact` -- wall contact, friction laws, events;
* :mod:`~drillfatigue.dynamics.bit` -- bit laws and the rock face;
* :mod:`~drillfatigue.dynamics.top` -- top boundary, rig (block, top drive), connections, growth;
* :mod:`~drillfatigue.dynamics.span` -- bending between the wall supports;
* :mod:`~drillfatigue.dynamics.run` -- the run driver, packers, recorder, checkpoints;
* :mod:`~drillfatigue.dynamics.registries` -- writes the law registries' dispatch modules.

The map of modules and kernels is ``docs/dynamics.md`` (tested against this tree).
This package exports :func:`simulate` and its result, :class:`SimulationResult`; they
load on first use, so importing a kernel module does not import the run driver.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from drillfatigue.dynamics.run.simulation import SimulationResult, simulate

__all__ = ["SimulationResult", "simulate"]


def __getattr__(name: str) -> Any:
    if name in __all__:
        from drillfatigue.dynamics.run import simulation  # start-up: kernels need not load it

        return getattr(simulation, name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
