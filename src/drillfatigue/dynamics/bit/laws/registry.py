"""The registered bit laws: names, ids, parameter blocks and packer.

A law is a module of :mod:`drillfatigue.dynamics.bit.laws`; registering it is one
line in :data:`LAWS` (its position is its id). Derived from it: the ids by name and
alias (:data:`MODEL_IDS`), each law's block in the parameter vector (:data:`OFFSETS`),
its length (:data:`N_PARAMS`), the packer and the kernels' dispatch on the law id
(:mod:`~drillfatigue.dynamics.bit.laws.dispatch`, written by
``python -m drillfatigue.dynamics.registries``).
"""

from __future__ import annotations

from pathlib import Path
from types import ModuleType
from typing import TYPE_CHECKING

import numpy as np

from drillfatigue.dynamics.core.lawtable import block_offsets, dispatch_prelude
from drillfatigue.dynamics.bit.laws import detournay, prescribed_rop, yigit_christoforou

if TYPE_CHECKING:  # pydantic stays out of the kernel modules at run time
    from drillfatigue.config.bit import BitConfig

#: The registered laws; a law's id is its position.
LAWS: tuple[ModuleType, ...] = (
    yigit_christoforou,
    prescribed_rop,
    detournay,
)

MODEL_IDS: dict[str, int] = {name: i for i, law in enumerate(LAWS)
                             for name in (law.NAME, *law.ALIASES)}



#: Start of each law's block in the parameter vector, by id, and the vector's length.
OFFSETS, N_PARAMS = block_offsets(LAWS, 0)


def pack_bit_params(cfg: BitConfig, rop_m_per_s: float = 0.0) -> tuple[int, np.ndarray]:
    """Model id and parameter vector (shape (N_PARAMS,), float64) of a validated
    ``BitConfig``; ``rop_m_per_s``: the operation's ROP, which ``prescribed_rop`` imposes.
    Every law's block is filled; the kernels read the chosen one."""
    p = np.zeros(N_PARAMS)
    for law, at in zip(LAWS, OFFSETS, strict=True):
        values = law.pack(cfg, rop_m_per_s)
        assert len(values) == len(law.PARAMS), law.NAME
        p[at:at + len(values)] = values
    return MODEL_IDS[cfg.model], p


# --- the dispatch module, written from the registry ---------------------------------------
DISPATCH = Path(__file__).with_name("dispatch.py")


def dispatch_source() -> str:
    """The source of the dispatch module for :data:`LAWS`."""
    head, names = dispatch_prelude("bit-law", "drillfatigue.dynamics.bit.laws.registry", LAWS)
    out = [head]
    out.append('\n\n@njit(cache=True, inline="always")\ndef law_response(model, p, wob_N, om, out):\n'
               '    """``out = [TOB, ROP]`` of law ``model`` at WOB ``wob_N`` > 0 (``out`` zeroed\n'
               '    by the caller, untouched for an unknown law)."""\n')
    for i, name in enumerate(names):
        out.append(f"    if model == {i}:\n        {name}.response(p, {OFFSETS[i]}, wob_N, om, out)\n"
                   "        return\n")
    out.append('\n\n@njit(cache=True, inline="always")\ndef law_torque_slope(model, p, wob_N, om):\n'
               '    """``d TOB / d Omega`` of law ``model`` at fixed WOB > 0; 0 for an unknown law."""\n')
    for i, name in enumerate(names):
        out.append(f"    if model == {i}:\n        return {name}.torque_slope(p, {OFFSETS[i]}, wob_N, om)\n")
    out.append("    return 0.0\n")
    out.append('\n\n@njit(cache=True, inline="always")\ndef rop_prescribed(model):\n'
               '    """Whether law ``model`` imposes the operation\'s ROP."""\n')
    ids = [str(i) for i, law in enumerate(LAWS) if law.ROP_PRESCRIBED]
    out.append(f"    return {' or '.join(f'model == {i}' for i in ids) or 'False'}\n")
    return "".join(out)
