"""The founding paper's case studies and the well-plan ranking tool (docs/model.md#case-studies).

- :mod:`~drillfatigue.studies.case1`: whirl of a 5 m pipe, Karnopp vs tanh-exponential.
- :mod:`~drillfatigue.studies.case2`: three profiles with shared end points, lives in
  800 s windows by the critical-plane criterion and API RP7G.
- :mod:`~drillfatigue.studies.case3`: horizontal section of profile 1, lives at 8/40/80 m.
- :mod:`~drillfatigue.studies.plan`: ``drillfatigue plan rank`` (surrogate ranking of
  candidate plans, simulator confirmation).
- :mod:`~drillfatigue.studies.report`: ``data/report/README.md``.
- :mod:`~drillfatigue.studies.stages`: section loading and stage entry points.

Settings: :mod:`drillfatigue.config.studies` (sections ``case1``, ``case2``,
``case3``, ``plan``, ``report``).
"""
