"""The top of the string and the rig: boundaries, block and top drive, connections, growth.

* :mod:`~drillfatigue.dynamics.top.boundaries` -- top drive and hoisting at the top, bit guide below;
* :mod:`~drillfatigue.dynamics.top.rig` -- the travelling block (autodriller) and the top drive;
* :mod:`~drillfatigue.dynamics.top.setup` -- the rig set-up from the configuration, checked and packed;
* :mod:`~drillfatigue.dynamics.top.connection` -- the connection sequence when the block reaches the floor;
* :mod:`~drillfatigue.dynamics.top.growth` -- drilling and tripping: the top segment grows, splits, merges;
* :mod:`~drillfatigue.dynamics.top.pack` -- rpm table, ``bp``, rig blocks and state, preload, anchor.
"""
