"""Numba rigid-segment drill-string dynamics (docs/model.md): one module per submodel.

Kernel modules (numpy, numba and math only; map in ``docs/dynamics.md``):

* :mod:`rigid` -- rigid bodies: quaternions, the Newton-Euler kick, the free rotor;
* :mod:`integrator` -- velocity Verlet over a chunk of steps, recording, divergence checks;
* :mod:`forces` -- the force assembly, one kernel per force kind (gravity, mud);
* :mod:`joints` -- the joint spring-dampers between segments;
* :mod:`contact` -- wall contact with its friction call and the Karnopp pre-pass;
* :mod:`friction` -- the seven wall-friction laws;
* :mod:`bitrock` -- the bit-rock laws (torque on bit, rate of penetration);
* :mod:`boundaries` -- the top drive and hoisting system; the bit guide;
* :mod:`growth` -- drilling and tripping: the top segment grows, splits, merges;
* :mod:`events` -- contact statistics, whirl detection and classification, bit bounce;
* :mod:`bundles`, :mod:`layout`, :mod:`status` -- named bundles of arrays, their
  column layout, the status codes.

Python layer: :mod:`model` (packers: a case into arrays and the initial
state; the status wrapper), :mod:`api` (the run driver :func:`api.simulate`)
with :mod:`recorder`, :mod:`checkpoint`; :mod:`softstring` (soft-string
torque and drag), :mod:`examples` (reference cases).
"""
