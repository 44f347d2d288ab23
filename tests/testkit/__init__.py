"""Test fixtures kept out of the installed package.

- :mod:`testkit.synthetic_sweep`: fake simulator and fatigue case functions
  with fault injection (failures, worker crashes, sleeps) for the sweep engine.
- :mod:`testkit.fatigue_runs`: synthetic simulator run folders for the fatigue tests.

The benchmarks reuse :mod:`testkit.synthetic_sweep` (``make bench`` puts
``tests/`` on ``PYTHONPATH``).
"""
