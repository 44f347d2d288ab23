"""What the bit laws share: the smoothstep fade-in of the cutting above its thresholds."""

from __future__ import annotations

from numba import njit


@njit(cache=True)
def fade_in(x, th, band):
    """0 below th, smoothstep to 1 at th (1 + band); a sharp step if band or th is 0."""
    if x < th or x <= 0.0:
        return 0.0
    w = band * th
    if w <= 0.0 or x >= th + w:
        return 1.0
    t = (x - th) / w
    return t * t * (3.0 - 2.0 * t)


@njit(cache=True)
def fade_in_slope(x, th, band):
    """Derivative of :func:`fade_in` with respect to ``x`` (0 outside the band)."""
    if x < th or x <= 0.0:
        return 0.0
    w = band * th
    if w <= 0.0 or x >= th + w:
        return 0.0
    t = (x - th) / w
    return 6.0 * t * (1.0 - t) / w
