"""Dispatch of the friction kernels on the law id (written by
:mod:`drillfatigue.dynamics.contact.friction.registry` from its ``LAWS``; do not edit:
run ``python -m drillfatigue.dynamics.registries``)."""

from numba import njit

from drillfatigue.dynamics.contact.friction.laws import (
    benson_hallquist, coulomb, karnopp, stick_band, tanh, tanh_exp, velocity_trig,
)

#: Number of registered laws (ids 0 .. N_LAWS - 1).
N_LAWS = 7
#: Law ids by name.
COULOMB = 0
BENSON_HALLQUIST = 1
KARNOPP = 2
TANH = 3
VELOCITY_TRIG = 4
TANH_EXP = 5
STICK_BAND = 6


@njit(cache=True, inline="always")
def slip_coefficient(model, p, speed):
    """Coefficient ``mu(|v|)`` of law ``model`` at slip speed ``speed`` (m/s), in
    [0, mu_s]; -1.0 for an unknown law (the caller checks)."""
    if model == 0:
        return coulomb.coefficient(p, 3, speed)
    if model == 1:
        return benson_hallquist.coefficient(p, 4, speed)
    if model == 2:
        return karnopp.coefficient(p, 6, speed)
    if model == 3:
        return tanh.coefficient(p, 7, speed)
    if model == 4:
        return velocity_trig.coefficient(p, 8, speed)
    if model == 5:
        return tanh_exp.coefficient(p, 10, speed)
    if model == 6:
        return stick_band.coefficient(p, 12, speed)
    return -1.0


@njit(cache=True, inline="always")
def stiction_band(model, p):
    """Stick band half-width (m/s) of a stiction law; -1.0 for any other law."""
    if model == 2:
        return karnopp.band(p, 6)
    return -1.0


@njit(cache=True, inline="always")
def has_stiction(model):
    """Whether law ``model`` needs the other tangential forces on the body."""
    return model == 2
