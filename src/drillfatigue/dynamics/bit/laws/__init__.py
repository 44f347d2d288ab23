"""Bit-rock interaction: torque on bit and rate of penetration, a law per module (docs/model.md#bit).

* :mod:`~drillfatigue.dynamics.bit.laws.yigit_christoforou` -- Yigit-Christoforou torque,
  Sarker et al. ROP with thresholds;
* :mod:`~drillfatigue.dynamics.bit.laws.prescribed_rop` -- the same torque, the operation's ROP;
* :mod:`~drillfatigue.dynamics.bit.laws.detournay` -- the Detournay-Defourny PDC law;
* :mod:`~drillfatigue.dynamics.bit.laws.registry` -- the registered laws: ids, parameter
  blocks, packer; it writes the dispatch;
* :mod:`~drillfatigue.dynamics.bit.laws.dispatch` -- the kernels' dispatch on the law id;
* :mod:`~drillfatigue.dynamics.bit.laws.kernel` -- :func:`bit_response`, :func:`bit_torque_slope`;
* :mod:`~drillfatigue.dynamics.bit.laws.base` -- the fade-in the laws share.

Each law module declares ``NAME`` (the ``bit.model`` value) and ``ALIASES``, ``PARAMS``
(its block), ``ROP_PRESCRIBED``, the packer ``pack(cfg, rop_m_per_s)`` and the kernels
``response(p, o, wob_N, om, out)`` and ``torque_slope(p, o, wob_N, om)`` (``o``: its
block's offset), and ``rop_bound_m_per_s(cfg, wob_N, omega_rad_s)`` (the largest ROP it
gives, or None: a run's growth allowance). Adding a law: docs/development.md, "Adding a friction or bit law".
"""

from __future__ import annotations

from drillfatigue.dynamics.core.lawtable import lazy_exports

#: Public names, by the module that defines them (loaded on first use, so that a
#: registry can be imported, and its dispatch written, before the dispatch exists).
_EXPORTS = {
    "DETOURNAY": "drillfatigue.dynamics.bit.laws.dispatch",
    "I_B0": "drillfatigue.dynamics.bit.laws.yigit_christoforou",
    "I_B1": "drillfatigue.dynamics.bit.laws.yigit_christoforou",
    "I_B2": "drillfatigue.dynamics.bit.laws.yigit_christoforou",
    "I_B3": "drillfatigue.dynamics.bit.laws.yigit_christoforou",
    "I_BAND": "drillfatigue.dynamics.bit.laws.yigit_christoforou",
    "I_C1": "drillfatigue.dynamics.bit.laws.yigit_christoforou",
    "I_C2": "drillfatigue.dynamics.bit.laws.yigit_christoforou",
    "I_OMEGA_TH": "drillfatigue.dynamics.bit.laws.yigit_christoforou",
    "I_WOB_TH": "drillfatigue.dynamics.bit.laws.yigit_christoforou",
    "LAWS": "drillfatigue.dynamics.bit.laws.registry",
    "MODEL_IDS": "drillfatigue.dynamics.bit.laws.registry",
    "N_LAWS": "drillfatigue.dynamics.bit.laws.dispatch",
    "N_PARAMS": "drillfatigue.dynamics.bit.laws.registry",
    "OFFSETS": "drillfatigue.dynamics.bit.laws.registry",
    "PRESCRIBED_ROP": "drillfatigue.dynamics.bit.laws.dispatch",
    "YIGIT_CHRISTOFOROU": "drillfatigue.dynamics.bit.laws.dispatch",
    "bit_response": "drillfatigue.dynamics.bit.laws.kernel",
    "bit_torque_slope": "drillfatigue.dynamics.bit.laws.kernel",
    "detournay_law": "drillfatigue.dynamics.bit.laws.detournay",
    "pack_bit_params": "drillfatigue.dynamics.bit.laws.registry",
    "rop_prescribed": "drillfatigue.dynamics.bit.laws.dispatch",
}
__all__ = sorted(_EXPORTS)
__getattr__ = lazy_exports(__name__, _EXPORTS)
