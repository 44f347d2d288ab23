"""Dispatch of the bit-law kernels on the law id (written by
:mod:`drillfatigue.dynamics.bit.laws.registry` from its ``LAWS``; do not edit:
run ``python -m drillfatigue.dynamics.registries``)."""

from numba import njit

from drillfatigue.dynamics.bit.laws import (
    detournay, prescribed_rop, yigit_christoforou,
)

#: Number of registered laws (ids 0 .. N_LAWS - 1).
N_LAWS = 3
#: Law ids by name.
YIGIT_CHRISTOFOROU = 0
PRESCRIBED_ROP = 1
DETOURNAY = 2


@njit(cache=True, inline="always")
def law_response(model, p, wob_N, om, out):
    """``out = [TOB, ROP]`` of law ``model`` at WOB ``wob_N`` > 0 (``out`` zeroed
    by the caller, untouched for an unknown law)."""
    if model == 0:
        yigit_christoforou.response(p, 0, wob_N, om, out)
        return
    if model == 1:
        prescribed_rop.response(p, 9, wob_N, om, out)
        return
    if model == 2:
        detournay.response(p, 19, wob_N, om, out)
        return


@njit(cache=True, inline="always")
def law_torque_slope(model, p, wob_N, om):
    """``d TOB / d Omega`` of law ``model`` at fixed WOB > 0; 0 for an unknown law."""
    if model == 0:
        return yigit_christoforou.torque_slope(p, 0, wob_N, om)
    if model == 1:
        return prescribed_rop.torque_slope(p, 9, wob_N, om)
    if model == 2:
        return detournay.torque_slope(p, 19, wob_N, om)
    return 0.0


@njit(cache=True, inline="always")
def rop_prescribed(model):
    """Whether law ``model`` imposes the operation's ROP."""
    return model == 1
