"""Field data in: the one input boundary for engineers' files.

Every entry point (CLI, pipeline stages, twin, plan) reads field data through
this package, which recognises columns by name and unit, converts to SI once
(factors from :mod:`drillfatigue.units`) and returns the project's objects:

- :mod:`drillfatigue.io.names`: names with unit suffixes (``wob_klbf``,
  ``rop_ft_per_h``, ``mud_density_ppg``), the query/twin vocabulary;
- :mod:`drillfatigue.io.headers`: unit spellings of file headers and unit
  fields (``MD (ft)``, ``HKLD [klbf]``, ``uom="dega"``), exact field-unit text;
- surveys (CSV in m or ft, WITSML 1.4.1.1 trajectory), cross-checked against
  minimum curvature: :mod:`drillfatigue.well.survey_file`, beside the well that
  reads them, on this package's header and unit parsing;
- :mod:`drillfatigue.io.tally`: string tallies in field units with API
  grades and a cited catalogue of pipe, HWDP and collar sizes;
- :mod:`drillfatigue.io.logs`: rig operating logs (LAS 2.0, WITSML 1.4.1.1
  log, CSV) for the twin, with the documented fill rules;
- :mod:`drillfatigue.io.display`: SI or field units for tables and plots.

See ``docs/field-data.md``.
"""
