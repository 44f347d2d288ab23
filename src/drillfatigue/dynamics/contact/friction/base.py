"""The friction parameter vector's shared block, and the helpers the laws share.

The vector ``p`` that every friction kernel takes starts with the coefficients
all laws read, then holds one block per registered law (its ``PARAMS``, in the
order of :data:`drillfatigue.dynamics.contact.friction.registry.LAWS`); a law
reads its own block from the offset ``o`` it is called with. Offsets are
derived by the registry, never written by hand.
"""

from __future__ import annotations

import math

from numba import njit

I_MU_S = 0  # static coefficient mu_s
I_MU_D = 1  # dynamic coefficient mu_d
I_AX_RATIO = 2  # mu_axial / mu_d, the axial (drag) scaling of friction_force_split
#: Entries of the shared block; the first law's block starts here.
N_SHARED = 3


@njit(cache=True, inline="always")
def tanh_sat(x):
    """tanh, skipping the libm call where it is 1.0 in float64 (x >= 19.1)."""
    if x >= 19.1:
        return 1.0
    return math.tanh(x)
