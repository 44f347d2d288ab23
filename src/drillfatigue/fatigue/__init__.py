"""Fatigue evaluation: surface stresses, rainflow, S-N and Miner, critical plane, API RP7G.

Public API: :func:`evaluate_run` (a simulator run directory to ``damage.parquet``),
:mod:`.stress`, :mod:`.rainflow`, :mod:`.sn`, :mod:`.critical_plane`, :mod:`.rp7g`.
Numerical kernels live in :mod:`.kernels` (numba, numpy and math only).
"""

from __future__ import annotations

from drillfatigue.fatigue.run import evaluate_run

__all__ = ["evaluate_run"]
