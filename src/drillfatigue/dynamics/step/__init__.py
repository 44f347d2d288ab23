"""One time step: every force on every segment, and the integrator that moves them.

* :mod:`~drillfatigue.dynamics.step.forces` -- the force assembly at one instant;
* :mod:`~drillfatigue.dynamics.step.integrator` -- velocity Verlet over a chunk of steps, divergence checks;
* :mod:`~drillfatigue.dynamics.step.pack` -- the stable step and the energy scale of a case.
"""
