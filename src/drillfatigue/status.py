"""Status codes of the package's numba kernels: the one enumeration.

Kernels never raise; they return one of these integers (and, where it helps,
say where in an ``info`` array). The numba kernels read these module-level
ints as compile-time constants, so :mod:`drillfatigue.numba_cache` counts this
module as kernel source. The Python layer turns a code other than ``OK`` into
an exception in one wrapper per chain:
:func:`drillfatigue.dynamics.run.model.raise_for_status` for the simulator (it
adds the time and the segment) and :func:`drillfatigue.errors.raise_for_status`
for the fatigue kernels.

This module imports nothing, so kernels of every subpackage may import it.
"""

OK = 0

# --- simulator (drillfatigue.dynamics) --------------------------------------
#: a position, velocity or force became NaN or infinite
NONFINITE = 1
#: the kinetic energy exceeded ``bp[B_ESCALE]`` (energy blow-up)
BLOWUP = 2
#: a segment moved faster than ``MAX_SPEED_M_PER_S`` or spun faster than
#: ``MAX_SPIN_RAD_S`` (:mod:`drillfatigue.dynamics.core.status`)
SPEED = 3
#: a friction model id outside :mod:`drillfatigue.dynamics.contact.friction`'s list
UNKNOWN_FRICTION = 4
#: a bit-law id outside :mod:`drillfatigue.dynamics.bit.laws`'s list
UNKNOWN_BIT = 5
#: a block or top-drive mode id outside :mod:`drillfatigue.dynamics.top.rig`'s list
UNKNOWN_RIG_MODE = 6

# --- fatigue chain (drillfatigue.fatigue.kernels) ---------------------------
#: a rainflow residue stack outgrew the capacity it was given (the
#: critical-plane wrapper retries with a larger one)
STACK_OVERFLOW = 7
#: more cycles than the output arrays hold
OUT_OVERFLOW = 8

# --- span bending (drillfatigue.dynamics.span.bending) ----------------------
#: a span or bending stiffness <= 0 or not finite, unsorted supports, or a
#: read point outside its span
BAD_SPAN = 9
#: a span in compression at or beyond the Euler load of the pinned span
SPAN_BUCKLED = 10
#: the three-moment system could not be solved (zero or non-finite pivot)
SINGULAR = 11

#: Text of each failure code, for the error message.
MESSAGES = {
    NONFINITE: "non-finite state",
    BLOWUP: "kinetic energy above the blow-up limit",
    SPEED: "speed above the divergence bound",
    UNKNOWN_FRICTION: "unknown friction model",
    UNKNOWN_BIT: "unknown bit model",
    UNKNOWN_RIG_MODE: "unknown block or top-drive mode",
    STACK_OVERFLOW: "rainflow residue stack overflow",
    OUT_OVERFLOW: "more cycles than the output capacity",
    BAD_SPAN: "bad span, stiffness, support order or read point",
    SPAN_BUCKLED: "a span in compression at or beyond its Euler load",
    SINGULAR: "singular three-moment system",
}
