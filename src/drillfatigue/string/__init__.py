"""Drill-string components and their segmentation into rigid bodies.

``build_segments(string_cfg, mud_density_kg_per_m3)`` turns the ``string``
configuration (components from the bit up) into per-segment and per-joint
arrays (index 0 at the bit end, going up). Beside it:
:mod:`.contacts` (contact points along each segment and their spacing rule)
and :mod:`.added_mass` (mud in the bore and hydrodynamic added mass). Span
bending between supports is :mod:`drillfatigue.dynamics.span.beam`. See
docs/bending.md.
"""

from drillfatigue.string.segments import COMPONENT_TYPES, Segments, build_segments

__all__ = ["COMPONENT_TYPES", "Segments", "build_segments"]
