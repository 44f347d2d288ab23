"""Test fixtures kept out of the installed package.

- :mod:`testkit.synthetic_sweep`: fake simulator and fatigue case functions
  with fault injection (failures, worker crashes, sleeps) for the sweep engine.
- :mod:`testkit.fatigue_runs`: synthetic simulator run folders for the fatigue tests.
- :mod:`testkit.torsional_wave`: a distributed torsional wave model of a string off
  bottom (Aarsnes & Shor 2018), the stick-slip reference.
- :mod:`testkit.off_bottom_well`: one deep deviated well off bottom, run by the
  simulator and by that reference.

The benchmarks reuse :mod:`testkit.synthetic_sweep` and :mod:`testkit.off_bottom_well`
(``make bench`` puts ``tests/`` on ``PYTHONPATH``).
"""
