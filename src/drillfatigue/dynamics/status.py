"""Status codes of the dynamics kernels: the one enumeration for the package.

Kernels never raise; they return one of these integers (and, where it helps,
say where in an ``info`` array). The numba kernels read these module-level
ints as compile-time constants (so this module counts as kernel source for
the numba cache key of :mod:`drillfatigue`). The Python layer turns a code other than
``OK`` into an exception in one place,
:func:`drillfatigue.dynamics.model.raise_for_status`.
"""

OK = 0
#: a position, velocity or force became NaN or infinite
NONFINITE = 1
#: the kinetic energy exceeded ``bp[B_ESCALE]`` (energy blow-up)
BLOWUP = 2
#: a segment moved faster than :data:`MAX_SPEED_M_PER_S` or spun faster than
#: :data:`MAX_SPIN_RAD_S`
SPEED = 3
#: a friction model id outside :mod:`drillfatigue.dynamics.friction`'s list
UNKNOWN_FRICTION = 4
#: a bit-law id outside :mod:`drillfatigue.dynamics.bitrock`'s list
UNKNOWN_BIT = 5
#: a block or top-drive mode id outside :mod:`drillfatigue.dynamics.rig`'s list
UNKNOWN_RIG_MODE = 6

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

#: Text of each failure code, for the error message.
MESSAGES = {
    NONFINITE: "non-finite state",
    BLOWUP: "kinetic energy above the blow-up limit",
    SPEED: "speed above the divergence bound",
    UNKNOWN_FRICTION: "unknown friction model",
    UNKNOWN_BIT: "unknown bit model",
    UNKNOWN_RIG_MODE: "unknown block or top-drive mode",
}
