"""Well trajectories and the wellbore geometry of the contact model.

- :func:`minimum_curvature`, :class:`Survey`: survey mathematics (positions
  [north, east, tvd] in m, dogleg severity).
- :func:`build_survey`, :func:`key_points`, :func:`profile_report`: profile
  builders driven by the ``well`` config section (:func:`build_plan_survey`:
  the plan without the section's tortuosity).
- :func:`apply_tortuosity`, :func:`tortuosity_index_per_m`: hole tortuosity
  (micro-doglegs added to a plan) and its index.
- :func:`build_wellbore`, :class:`Wellbore`: the hole as a chain of straight
  cylinders with a point-on-path query; :func:`kernels.path_point` is the
  numba form for simulator kernels.
- :func:`read_survey_csv`, :func:`write_survey_csv`: survey files
  (``md_m,inc_deg,azi_deg``).
"""

from drillfatigue.well.profiles import (
    KeyPoint,
    build_plan_survey,
    build_survey,
    key_points,
    profile_report,
)
from drillfatigue.well.survey import (
    SURVEY_COLUMNS,
    Survey,
    minimum_curvature,
    read_survey_csv,
    write_survey_csv,
)
from drillfatigue.well.tortuosity import apply_tortuosity, tortuosity_index_per_m
from drillfatigue.well.wellbore import Wellbore, build_wellbore

__all__ = [
    "SURVEY_COLUMNS",
    "KeyPoint",
    "Survey",
    "Wellbore",
    "apply_tortuosity",
    "build_plan_survey",
    "build_survey",
    "build_wellbore",
    "key_points",
    "minimum_curvature",
    "profile_report",
    "read_survey_csv",
    "tortuosity_index_per_m",
    "write_survey_csv",
]
