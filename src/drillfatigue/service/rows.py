"""Query rows (user-named values) to model arrays and back, without pandas.

``POST /v1/query`` is the service's hot path: most requests carry one
condition, and building DataFrames for one row costs several times the
network's own time. These functions apply the rules of
:meth:`drillfatigue.io.names.Vocabulary.frame_from_table` (one name
per feature, every feature given, finite numbers, known categories) with the
same messages, directly on the parsed JSON rows, and the physical bounds of
:mod:`drillfatigue.limits` (HTTP 422 for a value no rig can have, in a batch as in
a single row; the field names the row, ``rows[3].rpm``, counted from 0 as JSON
arrays are).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

import numpy as np

from drillfatigue.errors import InputError
from drillfatigue.limits import check_feature_values, first_outside
from drillfatigue.service.registry import LoadedModel
from drillfatigue.surrogate.facade import PREDICTION_COLUMNS, prediction_columns
from drillfatigue.io.names import Term, unseen_levels


def _plan(lm: LoadedModel, names: Sequence[str], field: str) -> list[Term]:
    """The model column (and unit factor) of each name; unknown/double/missing names raise."""
    vocab = lm.vocab
    terms: list[Term] = []
    source: dict[str, str] = {}
    for name in names:
        term = vocab.terms.get(name)
        if term is None:
            raise InputError(f"{field}.{name}", "unknown name (or unit)", vocab.allowed())
        if term.column in source:
            raise InputError(f"{field}.{name}", f"given twice (also as {source[term.column]!r})",
                             "one name per feature")
        source[term.column] = name
        terms.append(term)
    need = lm.surrogate.features + lm.surrogate.categorical
    missing = [c for c in need if c not in source]
    if missing:
        raise InputError(f"{field}." + ", ".join(vocab.names_for(c)[0] for c in missing),
                         "missing", "give each, e.g. " + " or ".join(
                             vocab.names_for(missing[0])[:3]))
    return terms


def _number(value: Any, name: str, field: str) -> float:
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise InputError(f"{field}.{name}", f"non-numeric value {value!r}",
                         "a finite number") from None
    if not math.isfinite(v):
        raise InputError(f"{field}.{name}", f"value {value!r} is NaN or infinite",
                         "a finite number")
    return v


def encode_rows(lm: LoadedModel, rows: Sequence[dict[str, Any]], field: str = "rows",
                unseen: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Model arrays of ``rows`` (every row with the same names, user units).

    ``unseen``: rows with a categorical level the model never saw
    (:func:`drillfatigue.io.names.unseen_levels`) get the first level's code,
    for the caller to answer them "no answer"; without it such a level is an
    InputError.

    Returns
    -------
    x_num : ndarray, shape (n, n_numeric)
        SI values in the model's feature order.
    x_cat : ndarray of int64, shape (n, n_categorical)
        Level codes.
    """
    names = list(rows[0])
    for i, row in enumerate(rows):
        if row.keys() != rows[0].keys():
            odd = sorted(set(row) ^ set(rows[0]))[0]
            raise InputError(f"{field}[{i}].{odd}", "names differ from the first row's",
                             "the same names in every row")
    terms = _plan(lm, names, field)
    sur = lm.surrogate
    num_index = {c: j for j, c in enumerate(sur.features)}
    cat_index = {c: j for j, c in enumerate(sur.categorical)}
    n = len(rows)
    x_num = np.empty((n, len(sur.features)))
    x_cat = np.empty((n, len(sur.categorical)), dtype=np.int64)
    for name, term in zip(names, terms, strict=True):
        values = [row[name] for row in rows]
        if term.categorical:
            text = [str(v).strip() for v in values]
            levels = sur.preprocessor.categories_[term.column]
            if unseen is not None:
                text = [levels[0] if u else t for t, u in zip(text, unseen, strict=True)]
            new = set(text).difference(levels)
            if new:
                raise InputError(f"{field}.{name}", f"value {sorted(new)[0]!r} not seen in "
                                 "training", ", ".join(levels))
            x_cat[:, cat_index[term.column]] = sur.preprocessor.codes_for(term.column, text)
        else:
            col = x_num[:, num_index[term.column]]
            col[:] = [_number(v, name, field) * term.factor for v in values]
            bad = first_outside(term.column, col)
            if bad is not None:
                where = f"{field}[{bad}].{name}" if n > 1 else f"{field}.{name}"
                check_feature_values(name, term.column, col[bad:bad + 1], term.factor,
                                     field=where, rows=False)
    return x_num, x_cat


def predict_rows(lm: LoadedModel, rows: Sequence[dict[str, Any]], field: str = "rows"
                 ) -> tuple[list[str], list[dict[str, Any]]]:
    """Columns and rows of a query answer: the inputs as given, then the predictions.

    The predictions are those of :meth:`Surrogate.predict` (same arrays, same
    formulas); infinite or NaN numbers become None (JSON null). Outside the
    surrogate's domain there is no number, as with ``drillfatigue query``: a
    single row is refused with the InputError of :meth:`DomainChecker.refusal`
    naming the variable and its range (HTTP 422, the same one line as the
    CLI); in a batch the row's numbers are null, with ``ood`` and the reason.
    """
    sur = lm.surrogate
    unseen = None
    if len(rows) > 1:  # a batch answers a level the model never saw "no answer", row by row
        cats = {}
        for name in rows[0]:
            term = lm.vocab.terms.get(name)
            if term is not None and term.categorical:
                cats[term.column] = [row.get(name) for row in rows]  # odd rows: refused below
        unseen, why = unseen_levels(cats, sur.categories)
    x_num, x_cat = encode_rows(lm, rows, field, unseen)
    r = sur.predict_array(x_num, x_cat)
    if len(rows) == 1 and r["ood"][0]:
        raise sur.domain.refusal(x_num[0], float(r["knn_distance"][0]), f"{field}[0].",
                                 cat_row=x_cat[0])
    reasons = sur.domain.reasons(x_num, r["knn_distance"], r["ood"], x_cat)
    if unseen is not None and unseen.any():
        r = {**r, "ood": r["ood"] | unseen}
        reasons = np.where(unseen, why, reasons)
    cols = prediction_columns(r, reasons, refuse=True)
    lists = {c: np.asarray(cols[c]).tolist() for c in PREDICTION_COLUMNS}
    out = []
    for i, row in enumerate(rows):
        rec = dict(row)
        for c in PREDICTION_COLUMNS:
            v = lists[c][i]
            rec[c] = None if isinstance(v, float) and not math.isfinite(v) else v
        out.append(rec)
    return list(rows[0]) + list(PREDICTION_COLUMNS), out
