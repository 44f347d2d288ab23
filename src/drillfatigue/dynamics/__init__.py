"""Numerical kernels of the drill-string dynamics model.

Each physical submodel lives in its own module (contact, friction, bit-rock,
soft-string torque and drag, ...). Kernels are ``@njit(cache=True)`` functions
on float64 arrays in SI units that import only numpy, numba and math; Python
wrappers above them validate input and raise.
"""
