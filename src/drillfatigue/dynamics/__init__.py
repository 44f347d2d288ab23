"""Numba rigid-segment drill-string dynamics (docs/model.md).

Kernel modules (numpy/numba/math only): :mod:`rigid` (quaternions, Newton-Euler
kick), :mod:`joints` (joint spring-dampers and loads), :mod:`forces` (force
assembly, boundaries), :mod:`integrator` (velocity-Verlet chunk loop),
:mod:`layout` (packed array columns). Python layer: :mod:`model` (build the
arrays and the initial state). The run driver with outputs is
:mod:`drillfatigue.simulate`.
"""
