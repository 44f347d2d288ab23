"""Wall friction: a law per module behind one kernel signature (docs/model.md#friction).

* :mod:`~drillfatigue.dynamics.contact.friction.laws` -- the laws, one module each;
* :mod:`~drillfatigue.dynamics.contact.friction.registry` -- the registered laws: ids,
  parameter blocks, packer, speed table; it writes the dispatch;
* :mod:`~drillfatigue.dynamics.contact.friction.dispatch` -- the kernels' dispatch on the law id;
* :mod:`~drillfatigue.dynamics.contact.friction.kernel` -- the friction force at a contact point;
* :mod:`~drillfatigue.dynamics.contact.friction.base` -- the shared block of the parameter vector.

Adding a law: docs/development.md, "Adding a friction or bit law".
"""

from __future__ import annotations

from drillfatigue.dynamics.core.lawtable import lazy_exports

#: Public names, by the module that defines them (loaded on first use, so that a
#: registry can be imported, and its dispatch written, before the dispatch exists).
_EXPORTS = {
    "BENSON_HALLQUIST": "drillfatigue.dynamics.contact.friction.dispatch",
    "COULOMB": "drillfatigue.dynamics.contact.friction.dispatch",
    "I_AX_RATIO": "drillfatigue.dynamics.contact.friction.base",
    "I_MU_D": "drillfatigue.dynamics.contact.friction.base",
    "I_MU_S": "drillfatigue.dynamics.contact.friction.base",
    "KARNOPP": "drillfatigue.dynamics.contact.friction.dispatch",
    "LAWS": "drillfatigue.dynamics.contact.friction.registry",
    "MODEL_IDS": "drillfatigue.dynamics.contact.friction.registry",
    "N_LAWS": "drillfatigue.dynamics.contact.friction.dispatch",
    "N_PARAMS": "drillfatigue.dynamics.contact.friction.registry",
    "N_SHARED": "drillfatigue.dynamics.contact.friction.base",
    "OFFSETS": "drillfatigue.dynamics.contact.friction.registry",
    "STICK_BAND": "drillfatigue.dynamics.contact.friction.dispatch",
    "TANH": "drillfatigue.dynamics.contact.friction.dispatch",
    "TANH_EXP": "drillfatigue.dynamics.contact.friction.dispatch",
    "VELOCITY_TRIG": "drillfatigue.dynamics.contact.friction.dispatch",
    "friction_force": "drillfatigue.dynamics.contact.friction.kernel",
    "friction_force_split": "drillfatigue.dynamics.contact.friction.kernel",
    "has_stiction": "drillfatigue.dynamics.contact.friction.dispatch",
    "law_block": "drillfatigue.dynamics.contact.friction.registry",
    "pack_friction_params": "drillfatigue.dynamics.contact.friction.registry",
    "slip_coefficient": "drillfatigue.dynamics.contact.friction.dispatch",
    "slip_scale_m_per_s": "drillfatigue.dynamics.contact.friction.registry",
    "stiction_band": "drillfatigue.dynamics.contact.friction.dispatch",
}
__all__ = sorted(_EXPORTS)
__getattr__ = lazy_exports(__name__, _EXPORTS)
