"""Wall contact: where the string touches the hole, the friction there, and the events it makes.

* :mod:`~drillfatigue.dynamics.contact.wall` -- point-in-cylinder test, penalty force, contact kernel;
* :mod:`~drillfatigue.dynamics.contact.friction` -- the wall-friction laws, their registry and kernel;
* :mod:`~drillfatigue.dynamics.contact.events` -- contact statistics, whirl detection, bit bounce;
* :mod:`~drillfatigue.dynamics.contact.pack` -- ``cpar``, the hole as cylinders, contact points.
"""
