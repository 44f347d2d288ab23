"""Status codes of the dynamics kernels and the bounds behind ``SPEED``.

The codes are the package's one enumeration, :mod:`drillfatigue.status`,
re-exported here for the simulator's kernels; the Python layer turns a code
other than ``OK`` into an exception in one place,
:func:`drillfatigue.dynamics.run.model.raise_for_status`. The kernels read these
module-level numbers as compile-time constants (so this module counts as
kernel source for the numba cache key, :mod:`drillfatigue.numba_cache`).
"""

from drillfatigue.status import (
    BLOWUP,
    MESSAGES,
    NONFINITE,
    OK,
    SPEED,
    UNKNOWN_BIT,
    UNKNOWN_FRICTION,
    UNKNOWN_RIG_MODE,
)

__all__ = ["BLOWUP", "MAX_SPEED_M_PER_S", "MAX_SPIN_RAD_S", "MESSAGES", "NONFINITE", "OK", "SPEED",
           "UNKNOWN_BIT", "UNKNOWN_FRICTION", "UNKNOWN_RIG_MODE"]

#: Translational speed (m/s) no part of a drill string reaches: trip speeds are
#: below 10 m/s and lateral impact speeds in whirl a few m/s. A segment centre
#: faster than this means the integration diverged.
MAX_SPEED_M_PER_S = 100.0
#: Angular speed (rad/s, about any axis; ~9 550 rpm) no drill string reaches:
#: rotary tables and top drives turn below ~300 rpm, mud motors and turbodrills
#: below ~2 000 rpm (210 rad/s), and a pipe rolling round the wall in backward
#: whirl spins at orbit rate x clearance / radius, below ~100 rad/s for an
#: orbit of a few hertz.
MAX_SPIN_RAD_S = 1000.0
