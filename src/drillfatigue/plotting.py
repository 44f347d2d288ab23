"""Figures built with matplotlib's object-oriented API, without pyplot.

A :class:`matplotlib.figure.Figure` made directly renders to a file through
the backend of the file's format, so the library never selects a global
plotting backend (an interactive session keeps its own) and needs no
``close``: the figure is freed with its last reference.

matplotlib is imported on the first figure, not with this module: it takes
about a second to import, and the command line (``drillfatigue --help``
included) and the stages that do not plot import the modules that can plot.
"""

from __future__ import annotations

from typing import Any


def subplots(nrows: int = 1, ncols: int = 1, *, figsize: tuple[float, float],
             **kwargs: Any) -> tuple[Any, Any]:
    """``(figure, axes)`` like ``pyplot.subplots`` but on a detached ``Figure``."""
    from matplotlib.figure import Figure  # start-up: ~1 s import, paid on the first figure only

    fig = Figure(figsize=figsize)
    return fig, fig.subplots(nrows, ncols, **kwargs)


def figure(*, figsize: tuple[float, float]) -> Any:
    """An empty detached ``Figure`` of ``figsize`` inches."""
    from matplotlib.figure import Figure  # start-up: ~1 s import, paid on the first figure only

    return Figure(figsize=figsize)
