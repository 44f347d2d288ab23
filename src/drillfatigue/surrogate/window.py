"""Operating-window map: predicted life over a grid of two operating parameters.

"Which operating window spares the string?" For one location of the string
(a component type and location at a distance from the bit) at one depth of a
well, every other input held fixed, the surrogate is asked for the damage
rate at each node of a regular grid of two operating parameters, typically
rpm x WOB or rpm x ROP. The map shows the predicted life (1 / damage rate,
hours of operation) per node, with the calibrated interval, and flags the
nodes outside the training domain (:class:`drillfatigue.surrogate.DomainChecker`):
there the number is not trusted and the map hatches the cell.

Axis and fixed-input names are the user vocabulary of
:mod:`drillfatigue.io.names` (``rpm``, ``wob_kN``, ``rop_m_per_h``,
``md_m``, ``component_type``, ...). The hole-geometry features of
:mod:`drillfatigue.well.features` can come from a survey table instead of
fixed values (the bit is at ``md_m + s_from_bit_m``).
"""

from __future__ import annotations

import io
import math
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd
from matplotlib.collections import PatchCollection
from matplotlib.figure import Figure
from matplotlib.lines import Line2D
from matplotlib.patches import Patch, Rectangle

from drillfatigue.errors import InputError
from drillfatigue.files import atomic_write_bytes
from drillfatigue.limits import check_feature_values, first_outside
from drillfatigue.surrogate.facade import Surrogate, prediction_frame
from drillfatigue.io.names import Vocabulary
from drillfatigue.well.features import POSITION_COLUMNS, check_survey, position_features

#: fewest and most nodes along one axis
MIN_NODES = 2
MAX_NODES = 400


@dataclass(frozen=True)
class Axis:
    """One grid axis: a user feature name and its node values (in that name's unit)."""

    name: str
    values: np.ndarray
    #: what an error names: ``x`` (its ends ``x.start``, ``x.stop``) or an option, ``--x``
    field: str = "axis"
    #: name the end (``.start``/``.stop``) in errors; an option's text has no such parts
    named_ends: bool = True

    @classmethod
    def linear(cls, name: str, start: float, stop: float, n: int, field: str = "axis") -> Axis:
        """``n`` evenly spaced nodes from ``start`` to ``stop`` (both included)."""
        for label, v in (("start", start), ("stop", stop)):
            if not isinstance(v, int | float) or not math.isfinite(v):
                raise InputError(f"{field}.{label}", f"{v!r} is not a finite number",
                                 "a finite number")
        if not stop > start:
            raise InputError(field, f"stop {stop:g} is not above start {start:g}",
                             "start < stop")
        if not isinstance(n, int) or not MIN_NODES <= n <= MAX_NODES:
            raise InputError(f"{field}.n", f"got {n!r}", f"{MIN_NODES} <= n <= {MAX_NODES}")
        return cls(name, np.linspace(float(start), float(stop), n), field)

    @classmethod
    def in_domain(cls, name: str, model: Surrogate, n: int = 31, field: str = "axis") -> Axis:
        """``n`` nodes over the model's domain of feature ``name`` (a user name with its unit):
        the design range of a design variable, else the training data's."""
        vocab = Vocabulary(model.features, model.categorical)
        term = vocab.terms.get(name)
        if term is None or term.categorical:
            raise InputError(field, f"{name!r} is not a numeric input of the model",
                             ", ".join(vocab.names_for(c)[0] for c in model.features))
        j = model.features.index(term.column)
        lo, hi = float(model.domain.min_[j]), float(model.domain.max_[j])
        return cls.linear(name, lo / term.factor, hi / term.factor, n, field)

    @classmethod
    def parse(cls, spec: str, option: str) -> Axis:
        """``'rpm=60:200:29'`` (name=start:stop:nodes) as given on the command line."""
        allowed = "NAME=START:STOP:NODES, e.g. rpm=60:200:29"
        if "=" not in spec:
            raise InputError(option, f"{spec!r} has no '='", allowed)
        name, rng = spec.split("=", 1)
        parts = rng.split(":")
        if len(parts) != 3:
            raise InputError(option, f"{spec!r} is not START:STOP:NODES", allowed)
        try:
            start, stop = float(parts[0]), float(parts[1])
            n = int(parts[2])
        except ValueError:
            raise InputError(option, f"{spec!r} has a non-numeric part", allowed) from None
        ax = cls.linear(name.strip().replace("-", "_"), start, stop, n, option)
        return cls(ax.name, ax.values, option, named_ends=False)

    def check_bounds(self, column: str, factor: float) -> None:
        """Raise the one-line InputError of :mod:`drillfatigue.limits` if an end of the
        axis (values in the name's unit, ``factor`` to SI) lies outside the physical
        bound of the model column ``column``."""
        ends = (("start", float(self.values[0])), ("stop", float(self.values[-1])))
        for end, v in ends:
            if first_outside(column, [v * factor]) is not None:
                field = f"{self.field}.{end}" if self.named_ends else self.field
                check_feature_values(self.name, column, [v * factor], factor, field=field,
                                     rows=False)


@dataclass(frozen=True)
class WindowMap:
    """Predicted life over an operating grid (see the module docstring).

    Arrays have shape (n_y, n_x): row ``i`` is ``y.values[i]``, column ``j``
    is ``x.values[j]``.

    Attributes
    ----------
    x, y : Axis
    life_h, life_h_lower, life_h_upper : ndarray, shape (n_y, n_x)
        Life in hours of operation at the node's conditions and its interval
        (calibrated coverage ``coverage``).
    damage_rate_per_h : ndarray, shape (n_y, n_x)
    ood : ndarray of bool, shape (n_y, n_x)
        Node outside the training domain.
    fixed : dict
        The fixed inputs as given (user names), geometry from the survey added.
    criterion : str
    coverage : float
    """

    x: Axis
    y: Axis
    life_h: np.ndarray
    life_h_lower: np.ndarray
    life_h_upper: np.ndarray
    damage_rate_per_h: np.ndarray
    ood: np.ndarray
    fixed: dict[str, Any]
    criterion: str
    coverage: float

    def best_in_domain(self) -> dict[str, float] | None:
        """The in-domain node with the longest lower-bound life (None if all are out)."""
        if np.all(self.ood):
            return None
        lower = np.where(self.ood, -np.inf, self.life_h_lower)
        i, j = np.unravel_index(int(np.argmax(lower)), lower.shape)
        return {self.x.name: float(self.x.values[j]), self.y.name: float(self.y.values[i]),
                "life_h": float(self.life_h[i, j]), "life_h_lower": float(self.life_h_lower[i, j])}

    def to_frame(self) -> pd.DataFrame:
        """One row per node: the two axis values, life (+ interval), rate, OOD flag."""
        xx, yy = np.meshgrid(self.x.values, self.y.values)
        return pd.DataFrame({self.x.name: xx.ravel(), self.y.name: yy.ravel(),
                             "life_h": self.life_h.ravel(),
                             "life_h_lower": self.life_h_lower.ravel(),
                             "life_h_upper": self.life_h_upper.ravel(),
                             "damage_rate_per_h": self.damage_rate_per_h.ravel(),
                             "ood": self.ood.ravel()})


def operating_window(model: Surrogate, x: Axis, y: Axis, fixed: Mapping[str, Any],
                     survey: pd.DataFrame | None = None, max_nodes: int | None = None
                     ) -> WindowMap:
    """Predict the life over the grid ``x`` x ``y`` with the other inputs ``fixed``.

    Parameters
    ----------
    model : Surrogate
    x, y : Axis
        Two numeric model features in user names (e.g. ``rpm`` and ``wob_kN``).
    fixed : mapping
        ``{user name: value}`` of every other feature (``md_m``,
        ``s_from_bit_m``, ``component_type``, ``location``, friction, mud,
        ...), except the hole-geometry columns when ``survey`` is given.
    survey : DataFrame, optional
        Columns ``md_m``, ``dls_deg_per_30m`` (and ``inc_deg`` when the model
        uses inclination features): the geometry at ``md_m`` and at the bit
        (``md_m + s_from_bit_m``) is interpolated from it.
    max_nodes : int, optional
        Largest accepted ``n_x * n_y``.

    Returns
    -------
    WindowMap

    Raises
    ------
    InputError
        Unknown or duplicated names, an axis that is categorical or reaches
        beyond a physical bound (:mod:`drillfatigue.limits`), a missing fixed input,
        a grid larger than ``max_nodes``, a bad survey.
    """
    vocab = Vocabulary(model.features, model.categorical)
    n_x, n_y = x.values.size, y.values.size
    for label, ax in (("x", x), ("y", y)):
        term = vocab.terms.get(ax.name)
        if term is None:
            raise InputError(f"{label}.name", f"unknown feature {ax.name!r}",
                             ", ".join(vocab.names_for(c)[0] for c in model.features))
        if term.categorical:
            raise InputError(f"{label}.name", f"{ax.name!r} is categorical",
                             "a numeric feature")
    for ax in (x, y):  # a value no rig can have is an input error, not a hatched cell
        ax.check_bounds(vocab.terms[ax.name].column, vocab.terms[ax.name].factor)
    if vocab.terms[x.name].column == vocab.terms[y.name].column:
        raise InputError("y.name", f"{y.name!r} is the same feature as x ({x.name!r})",
                         "two different features")
    if max_nodes is not None and n_x * n_y > max_nodes:
        raise InputError("grid", f"{n_x} x {n_y} = {n_x * n_y} nodes", f"at most {max_nodes}")
    geo_cols: tuple[str, ...] = ()
    if survey is not None:
        geo_cols = tuple(c for c in model.features if c in POSITION_COLUMNS)
    axis_cols = {vocab.terms[x.name].column, vocab.terms[y.name].column}
    fixed_si = vocab.frame_from_mapping(dict(fixed), require=()) if fixed else pd.DataFrame(
        index=[0])
    for col in fixed_si.columns:
        name = next(k for k in fixed if k in vocab.terms and vocab.terms[k].column == col)
        if col in axis_cols:
            raise InputError(name, "is also a grid axis", "fix it or vary it, not both")
        if col in geo_cols:
            raise InputError(name, "given together with a survey", "the value or the survey")
    need = [c for c in model.features + model.categorical
            if c not in axis_cols and c not in geo_cols]
    missing = [vocab.names_for(c)[0] for c in need if c not in fixed_si.columns]
    if missing:
        raise InputError(", ".join(missing), "missing fixed input", "give each as NAME=VALUE")
    xx, yy = np.meshgrid(x.values, y.values)
    n = xx.size
    frame = pd.DataFrame({c: np.repeat(fixed_si[c].to_numpy(), n) for c in fixed_si.columns})
    frame[vocab.terms[x.name].column] = xx.ravel() * vocab.terms[x.name].factor
    frame[vocab.terms[y.name].column] = yy.ravel() * vocab.terms[y.name].factor
    added: dict[str, Any] = {}
    if geo_cols and survey is not None:
        for col in ("md_m", "dls_deg_per_30m"):
            if col not in survey.columns:
                raise InputError(f"survey.{col}", "missing column in the survey",
                                 "md_m, dls_deg_per_30m (and inc_deg)")
        for col in ("md_m", "s_from_bit_m"):
            if col not in frame.columns:
                raise InputError(col, "needed to place the location in the survey",
                                 "a model with md_m and s_from_bit_m features")
        md = frame["md_m"].to_numpy(dtype=np.float64)
        bit = md + frame["s_from_bit_m"].to_numpy(dtype=np.float64)
        s = check_survey(survey["md_m"], survey["dls_deg_per_30m"],
                         survey["inc_deg"] if "inc_deg" in survey.columns else None, geo_cols)
        geo = position_features(*s, md, bit, geo_cols)
        for col in geo_cols:
            frame[col] = geo[col]
            added[col] = float(geo[col][0])
    x_num, x_cat = model.encode(frame)
    r = model.predict_array(x_num, x_cat)
    # out of domain: no number (NaN lives), the cell only marked
    pred = prediction_frame(r, np.full(n, "", dtype=object), refuse=True)
    shape = (n_y, n_x)

    def grid(col: str) -> np.ndarray:
        return pred[col].to_numpy().reshape(shape)

    return WindowMap(x=x, y=y, life_h=grid("life_h"), life_h_lower=grid("life_h_lower"),
                     life_h_upper=grid("life_h_upper"),
                     damage_rate_per_h=grid("damage_rate_per_h"),
                     ood=pred["ood"].to_numpy(dtype=bool).reshape(shape),
                     fixed={**dict(fixed), **added},
                     criterion=str(model.metadata.get("criterion", "")),
                     coverage=model.coverage)


def _cell_edges(v: np.ndarray) -> np.ndarray:
    """Cell edges around node values: midpoints inside, half a step beyond the ends."""
    mid = 0.5 * (v[1:] + v[:-1])
    return np.concatenate([[v[0] - (mid[0] - v[0])], mid, [v[-1] + (v[-1] - mid[-1])]])


def window_figure(wmap: WindowMap, title: str | None = None) -> Any:
    """The map as a matplotlib Figure: log10 life colours, out-of-domain cells hatched.

    The colour is the central life estimate; the in-domain node with the
    longest lower-bound life is starred. Built without pyplot (no global
    figure state), so service threads can draw at the same time.
    """
    xe, ye = _cell_edges(wmap.x.values), _cell_edges(wmap.y.values)
    with np.errstate(divide="ignore"):
        z = np.log10(wmap.life_h)
    fig = Figure(figsize=(7.5, 5.2))
    ax = fig.add_subplot()
    mesh = ax.pcolormesh(xe, ye, z, cmap="viridis", shading="flat")
    bar = fig.colorbar(mesh, ax=ax)
    bar.set_label("predicted life, log10(hours)")
    cells = [Rectangle((xe[j], ye[i]), xe[j + 1] - xe[j], ye[i + 1] - ye[i])
             for i, j in zip(*np.nonzero(wmap.ood), strict=True)]
    handles: list[Any] = []
    if cells:
        ax.add_collection(PatchCollection(cells, facecolor="none", edgecolor="white",
                                          hatch="///", linewidth=0.0))
        handles.append(Patch(facecolor="lightgrey", edgecolor="black", hatch="///",
                             label="outside the training domain"))
    best = wmap.best_in_domain()
    if best is not None:
        ax.plot([best[wmap.x.name]], [best[wmap.y.name]], marker="*", ms=14, color="red",
                ls="none")
        handles.append(Line2D([], [], marker="*", ms=10, color="red", ls="none",
                              label="longest life in domain (lower bound)"))
    if handles:
        ax.legend(handles=handles, loc="upper right", fontsize=8, framealpha=0.85)
    ax.set_xlim(xe[0], xe[-1])
    ax.set_ylim(ye[0], ye[-1])
    ax.set_xlabel(wmap.x.name)
    ax.set_ylabel(wmap.y.name)
    ax.set_title(title or f"Operating window ({wmap.criterion}), "
                 f"{100 * wmap.ood.mean():.0f} % of the grid out of domain", fontsize=10)
    fig.tight_layout()
    return fig


def window_png(wmap: WindowMap, title: str | None = None, dpi: int = 120) -> bytes:
    """The map (:func:`window_figure`) as PNG bytes."""
    buf = io.BytesIO()
    window_figure(wmap, title).savefig(buf, dpi=dpi, format="png")
    return buf.getvalue()


def plot_window(wmap: WindowMap, path: str | Path, title: str | None = None,
                dpi: int = 120) -> Path:
    """Write the map (:func:`window_figure`) to ``path`` as a PNG, atomically."""
    return atomic_write_bytes(path, window_png(wmap, title, dpi))
