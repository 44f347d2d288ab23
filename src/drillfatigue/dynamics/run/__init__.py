"""A run: the case packed into arrays, the run driver, its records, checkpoints and buckling watch.

* :mod:`~drillfatigue.dynamics.run.simulation` -- :func:`simulate` and the run directory;
* :mod:`~drillfatigue.dynamics.run.model` -- a case's model from the subpackages' packers, its initial state;
* :mod:`~drillfatigue.dynamics.run.recorder` -- record buffers into tables, in memory or Parquet parts;
* :mod:`~drillfatigue.dynamics.run.checkpoint` -- the state saved between chunks, restored bit for bit;
* :mod:`~drillfatigue.dynamics.run.buckling` -- buckling detected in the run from its lateral offsets;
* :mod:`~drillfatigue.dynamics.run.examples` -- small reference cases for validation and benchmarks.
"""
