"""The registered friction laws: names, ids, parameter blocks, packer and speed table.

A law is a module of :mod:`drillfatigue.dynamics.contact.friction.laws`; registering
it is one line in :data:`LAWS` (its position is its id). Everything else is derived:
the ids by name (:data:`MODEL_IDS`), each law's block in the parameter vector
(:data:`OFFSETS`, after the shared block of :mod:`~drillfatigue.dynamics.contact.friction.base`),
its length (:data:`N_PARAMS`), the packer, the stable step's speed table, and the
kernels' dispatch on the law id, :mod:`~drillfatigue.dynamics.contact.friction.dispatch`,
which :func:`dispatch_source` gives and :mod:`drillfatigue.dynamics.registries` writes
(numba compiles and caches functions from files only)::

    python -m drillfatigue.dynamics.registries

``tests/unit/dynamics/test_registries.py`` fails when the dispatch is out of date, when a law
is not a ``friction.model`` of the configuration, or when docs/model.md does not
describe it.
"""

from __future__ import annotations

from pathlib import Path
from types import ModuleType
from typing import TYPE_CHECKING

import numpy as np

from drillfatigue.dynamics.core.lawtable import block_offsets, dispatch_prelude
from drillfatigue.dynamics.contact.friction.base import I_AX_RATIO, I_MU_D, I_MU_S, N_SHARED
from drillfatigue.dynamics.contact.friction.laws import (
    benson_hallquist, coulomb, karnopp, stick_band, tanh, tanh_exp, velocity_trig,
)

if TYPE_CHECKING:  # pydantic stays out of the kernel modules at run time
    from drillfatigue.config.friction import FrictionConfig

#: The registered laws; a law's id is its position.
LAWS: tuple[ModuleType, ...] = (
    coulomb,
    benson_hallquist,
    karnopp,
    tanh,
    velocity_trig,
    tanh_exp,
    stick_band,
)

MODEL_IDS: dict[str, int] = {law.NAME: i for i, law in enumerate(LAWS)}



#: Start of each law's block in the parameter vector, by id, and the vector's length.
OFFSETS, N_PARAMS = block_offsets(LAWS, N_SHARED)


def pack_friction_params(cfg: FrictionConfig) -> tuple[int, np.ndarray]:
    """Model id and parameter vector (shape (N_PARAMS,), float64) of a validated
    ``FrictionConfig``: the shared coefficients, then every law's block from its
    ``PARAMS`` fields (all blocks are filled; the kernels read the chosen one)."""
    p = np.zeros(N_PARAMS)
    p[I_MU_S] = cfg.mu_static
    p[I_MU_D] = cfg.mu_dynamic
    mu_ax = cfg.mu_dynamic if cfg.mu_axial is None else cfg.mu_axial
    if cfg.mu_dynamic > 0.0:
        p[I_AX_RATIO] = mu_ax / cfg.mu_dynamic
    else:  # no sliding friction at all: nothing to scale
        p[I_AX_RATIO] = 1.0
    for law, at in zip(LAWS, OFFSETS, strict=True):
        for k, name in enumerate(law.PARAMS):
            p[at + k] = getattr(cfg, name)
    return MODEL_IDS[cfg.model], p


def law_block(model: int, p: np.ndarray) -> np.ndarray:
    """The block of law ``model`` in the parameter vector ``p``."""
    return p[OFFSETS[model]:OFFSETS[model] + len(LAWS[model].PARAMS)]


def slip_scale_m_per_s(model: int, p: np.ndarray) -> float:
    """The law's slip speed scale (m/s): the stable step's speed table entry."""
    return float(LAWS[model].slip_scale_m_per_s(law_block(model, p)))


def has_stiction(model: int) -> bool:
    """Whether law ``model`` is true stiction (it needs the other tangential forces)."""
    return bool(LAWS[model].STICTION)


# --- the dispatch module, written from the registry ---------------------------------------
DISPATCH = Path(__file__).with_name("dispatch.py")


def dispatch_source() -> str:
    """The source of the dispatch module for :data:`LAWS`."""
    head, names = dispatch_prelude("friction", "drillfatigue.dynamics.contact.friction.registry", LAWS)
    out = [head]
    out.append('\n\n@njit(cache=True, inline="always")\ndef slip_coefficient(model, p, speed):\n'
               '    """Coefficient ``mu(|v|)`` of law ``model`` at slip speed ``speed`` (m/s), in\n'
               '    [0, mu_s]; -1.0 for an unknown law (the caller checks)."""\n')
    for i, name in enumerate(names):
        out.append(f"    if model == {i}:\n        return {name}.coefficient(p, {OFFSETS[i]}, speed)\n")
    out.append("    return -1.0\n")
    out.append('\n\n@njit(cache=True, inline="always")\ndef stiction_band(model, p):\n'
               '    """Stick band half-width (m/s) of a stiction law; -1.0 for any other law."""\n')
    for i, (law, name) in enumerate(zip(LAWS, names, strict=True)):
        if law.STICTION:
            out.append(f"    if model == {i}:\n        return {name}.band(p, {OFFSETS[i]})\n")
    out.append("    return -1.0\n")
    out.append('\n\n@njit(cache=True, inline="always")\ndef has_stiction(model):\n'
               '    """Whether law ``model`` needs the other tangential forces on the body."""\n')
    ids = [str(i) for i, law in enumerate(LAWS) if law.STICTION]
    out.append(f"    return {' or '.join(f'model == {i}' for i in ids) or 'False'}\n")
    return "".join(out)

