"""Drill-string components and their segmentation into rigid bodies.

``build_segments(string_cfg, mud_density_kg_per_m3)`` turns the ``string``
configuration (components from the bit up) into per-segment and per-joint
arrays (index 0 at the bit end, going up).
"""

from drillfatigue.string.segments import COMPONENT_TYPES, Segments, build_segments

__all__ = ["COMPONENT_TYPES", "Segments", "build_segments"]
