"""The bit: its laws (torque on bit, rate of penetration) and the rock face under it.

* :mod:`~drillfatigue.dynamics.bit.laws` -- the bit-rock laws, their registry and kernel;
* :mod:`~drillfatigue.dynamics.bit.rockface` -- the lobed rock face, rock contact, depth of cut.
"""
