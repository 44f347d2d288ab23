"""The core every kernel shares: the array layout and its bundles, status codes, rigid bodies, joints.

* :mod:`~drillfatigue.dynamics.core.layout` -- column layout of the packed parameter and state arrays;
* :mod:`~drillfatigue.dynamics.core.bundles` -- the named bundles of arrays the kernels take;
* :mod:`~drillfatigue.dynamics.core.status` -- status codes of the kernels;
* :mod:`~drillfatigue.dynamics.core.rigid` -- unit quaternions and the Newton-Euler update;
* :mod:`~drillfatigue.dynamics.core.joints` -- the spring-damper joint between two segments;
* :mod:`~drillfatigue.dynamics.core.pack` -- a case's segments and joints as ``seg`` and ``jp`` rows;
* :mod:`~drillfatigue.dynamics.core.lawtable` -- what the friction and bit-law registries share.
"""
