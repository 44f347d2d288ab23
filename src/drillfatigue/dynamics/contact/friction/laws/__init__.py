"""The wall-friction laws, one module each (registered in
:mod:`drillfatigue.dynamics.contact.friction.registry`).

* :mod:`~drillfatigue.dynamics.contact.friction.laws.coulomb` -- regularised Coulomb;
* :mod:`~drillfatigue.dynamics.contact.friction.laws.benson_hallquist` -- exponential decay;
* :mod:`~drillfatigue.dynamics.contact.friction.laws.karnopp` -- Karnopp stiction;
* :mod:`~drillfatigue.dynamics.contact.friction.laws.tanh` -- Mostaghel and Davis;
* :mod:`~drillfatigue.dynamics.contact.friction.laws.velocity_trig` -- trigonometric Stribeck shape;
* :mod:`~drillfatigue.dynamics.contact.friction.laws.tanh_exp` -- the paper's hybrid;
* :mod:`~drillfatigue.dynamics.contact.friction.laws.stick_band` -- Coulomb with a stick band.

Each law module declares ``NAME`` (the ``friction.model`` value), ``PARAMS`` (the
``FrictionConfig`` fields of its block, in order), ``STICTION`` (whether it needs the
other tangential forces on the body: true stiction), the kernel
``coefficient(p, o, speed)`` and the speed-table entry ``slip_scale_m_per_s(q)``
(``q`` its block); a stiction law also ``band(p, o)``.
"""
