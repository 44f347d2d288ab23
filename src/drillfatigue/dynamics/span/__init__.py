"""Bending between supports: the continuous pipe between the points where it touches the wall.

* :mod:`~drillfatigue.dynamics.span.bending` -- the continuous beam-column on its supports (kernels);
* :mod:`~drillfatigue.dynamics.span.chain` -- the rigid chain's own quasi-static moments on the same holds;
* :mod:`~drillfatigue.dynamics.span.modal` -- a span's dynamic response through its first mode;
* :mod:`~drillfatigue.dynamics.span.record` -- the span correction recorded at the joints;
* :mod:`~drillfatigue.dynamics.span.beam` -- the Python layer over the beam kernels.
"""
