"""Names with units: the one parser of unit suffixes (``_ft``, ``_klbf``, ``_ppg``, ...).

User-facing query vocabulary: names with units, converted to the model's SI columns.

Every numeric model column gets user names from its last dotted part: the SI
unit suffix of the column (``_N``, ``_m_per_s``, ``_m``, ``_kg_per_m3``,
``_deg_per_30m``) may be replaced by another unit of the same quantity, e.g.
``operation.wob_N`` -> ``wob_N``, ``wob_kN``, ``wob_klbf``;
``operation.rop_m_per_s`` -> ``rop_m_per_s``, ``rop_m_per_h``, ``rop_ft_per_h``.
Columns without a unit suffix (``rpm``, ``mu_static``, ``lobes``) keep their
name. If two columns would share a short name, the full column name with dots
turned into underscores is used instead. The full SI column name itself is
always accepted. CLI flags are the same names with ``-`` for ``_``
(``--wob-kN``). Unit factors come from :mod:`drillfatigue.units` only.

Log channels (:func:`channel_stem`, :func:`force_column`) use the same
suffixes plus those of quantities no model column has (torque, pressure,
flow rate, :data:`CHANNEL_FAMILIES`).
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass

import numpy as np
import pandas as pd

from drillfatigue import units
from drillfatigue.errors import InputError
from drillfatigue.io.headers import UNIT_SPELLINGS, normalise_unit, split_header
from drillfatigue.limits import check_feature_values

#: SI suffix -> {accepted suffix: factor to SI}; longest suffixes are tried first.
UNIT_FAMILIES: dict[str, dict[str, float]] = {
    "_m_per_s": {"_m_per_s": 1.0, "_m_per_h": units.M_PER_H_M_PER_S,
                 "_ft_per_h": units.FT_PER_H_M_PER_S},
    "_kg_per_m3": {"_kg_per_m3": 1.0, "_sg": units.SG_KG_PER_M3, "_ppg": units.PPG_KG_PER_M3},
    "_deg_per_30m": {"_deg_per_30m": 1.0, "_deg_per_100ft": units.DEG_PER_100FT_DEG_PER_30M},
    "_N": {"_N": 1.0, "_kN": units.KN_N, "_klbf": units.KLBF_N},
    "_m": {"_m": 1.0, "_mm": units.MM_M, "_ft": units.FT_M, "_in": units.INCH_M},
}


@dataclass(frozen=True)
class Term:
    """One accepted user name: the model column it fills and the factor to SI."""

    column: str
    factor: float
    categorical: bool = False


def _stem_and_family(column: str) -> tuple[str, dict[str, float] | None]:
    last = column.rsplit(".", 1)[-1]
    for suffix in sorted(UNIT_FAMILIES, key=len, reverse=True):
        if last.endswith(suffix) and len(last) > len(suffix):
            return last[: -len(suffix)], UNIT_FAMILIES[suffix]
    return last, None


class Vocabulary:
    """Accepted user names of a model's features.

    Parameters
    ----------
    features : sequence of str
        Numeric SI columns of the model.
    categorical : sequence of str
        Categorical columns (values passed through as text).
    """

    def __init__(self, features: Sequence[str], categorical: Sequence[str] = ()) -> None:
        self.features = list(features)
        self.categorical = list(categorical)
        def stem_of(col: str, full: bool) -> tuple[str, dict[str, float] | None]:
            name = col.replace(".", "_") if full else col
            if col in self.categorical:
                return name.rsplit(".", 1)[-1], None
            return _stem_and_family(name)

        short: dict[str, list[str]] = {}
        for col in self.features + self.categorical:
            short.setdefault(stem_of(col, False)[0], []).append(col)
        self.terms: dict[str, Term] = {}
        for col in self.features + self.categorical:
            is_cat = col in self.categorical
            stem, fam = stem_of(col, False)
            if len(short[stem]) > 1:
                stem, fam = stem_of(col, True)
            if fam is None:
                self.terms[stem] = Term(col, 1.0, is_cat)
            else:
                for suf, fac in fam.items():
                    self.terms[stem + suf] = Term(col, fac, is_cat)
            self.terms.setdefault(col, Term(col, 1.0, is_cat))

    def names_for(self, column: str) -> list[str]:
        """User names that fill ``column`` (short names first)."""
        return [n for n, t in self.terms.items() if t.column == column]

    def allowed(self) -> str:
        """Short text listing the accepted names (one per column, SI first)."""
        return ", ".join(self.names_for(c)[0] for c in self.features + self.categorical)

    @staticmethod
    def flag(name: str) -> str:
        return "--" + name.replace("_", "-")

    # -- conversion ---------------------------------------------------------
    def _number(self, name: str, value: object) -> float:
        # a numpy scalar from a table reads as its Python value in the message
        shown = value.item() if hasattr(value, "item") else value
        try:
            v = float(value)  # type: ignore[arg-type]
        except (TypeError, ValueError):
            raise InputError(name, f"non-numeric value {shown!r}", "a finite number") from None
        if not math.isfinite(v):
            raise InputError(name, f"value {shown!r} is NaN or infinite", "a finite number")
        return v

    def frame_from_mapping(self, values: Mapping[str, object],
                           require: Sequence[str] | None = None) -> pd.DataFrame:
        """One-row SI frame from ``{user name: value}`` (a CLI query).

        ``require``: model columns that must be given (default: all).
        """
        return self.frame_from_table(pd.DataFrame({k: [v] for k, v in values.items()}),
                                     require=require)

    def frame_from_table(self, table: pd.DataFrame, require: Sequence[str] | None = None,
                         passthrough: Sequence[str] = ()) -> pd.DataFrame:
        """SI frame (model column names) from a table with user-named columns.

        Columns in ``passthrough`` are copied unchanged; any other unknown
        column raises InputError, as do two names for one column, a missing
        required column, a non-numeric, NaN or infinite value and a value
        outside its physical range (:mod:`drillfatigue.limits`; a physical
        value outside the training data is left to the out-of-domain flag).
        """
        out: dict[str, object] = {}
        source: dict[str, str] = {}
        for name in table.columns:
            key = str(name)
            if key in passthrough:
                out[key] = table[name].to_numpy()
                continue
            term = self.terms.get(key)
            if term is None:
                raise InputError(key, "unknown name (or unit)", self.allowed())
            if term.column in source:
                raise InputError(key, f"given twice (also as {source[term.column]!r})",
                                 "one name per feature")
            source[term.column] = key
            col = table[name]
            many = len(col) > 1  # a table: name the data row (from 1) of an error
            if term.categorical:
                vals = col.to_numpy(dtype=object)
                gaps = [v is None or (isinstance(v, float) and math.isnan(v)) for v in vals]
                if any(gaps):
                    where = f" (row {gaps.index(True) + 1})" if many else ""
                    raise InputError(key, f"missing value{where}", "a category name")
                out[term.column] = np.asarray([str(v).strip() for v in vals], dtype=object)
                continue
            num = pd.to_numeric(col, errors="coerce").to_numpy(dtype=np.float64)
            bad = ~np.isfinite(num)
            if bad.any():
                i = int(np.argmax(bad))
                where = f" (row {i + 1})" if many else ""
                try:
                    self._number(key, col.iloc[i])  # raises with the offending value
                except InputError as exc:
                    raise InputError(key, exc.problem + where, exc.allowed) from None
                raise InputError(key, f"NaN or infinite value{where}", "a finite number")
            si = num * term.factor
            check_feature_values(key, term.column, si, term.factor)
            out[term.column] = si
        need = self.features + self.categorical if require is None else list(require)
        missing = [self.names_for(c)[0] for c in need if c not in out]
        if missing:
            first = next(c for c in need if c not in out)
            raise InputError(", ".join(missing), "missing", "give each, e.g. "
                             + " or ".join(self.names_for(first)[:3]))
        return pd.DataFrame(out, index=table.index)


#: Unit families of surface channels that no model column has (SI suffix first).
CHANNEL_FAMILIES: dict[str, dict[str, float]] = {
    "_Nm": {"_Nm": 1.0, "_kNm": units.KNM_NM, "_kft_lbf": units.KFT_LBF_NM,
            "_ft_lbf": units.LBF_FT_NM},
    "_Pa": {"_Pa": 1.0, "_kPa": units.KPA_PA, "_MPa": units.MPA_PA, "_psi": units.PSI_PA,
            "_bar": units.BAR_PA},
    "_m3_per_s": {"_m3_per_s": 1.0, "_m3_per_min": units.M3_PER_MIN_M3_PER_S,
                  "_l_per_min": units.L_PER_MIN_M3_PER_S, "_gpm": units.US_GPM_M3_PER_S,
                  "_bbl_per_min": units.BBL_PER_MIN_M3_PER_S},
}


def channel_stem(name: str) -> str:
    """``wob_kN`` -> ``wob``: a log column name without its unit suffix."""
    suffixes = {suf for fams in (UNIT_FAMILIES, CHANNEL_FAMILIES)
                for fam in fams.values() for suf in fam}
    for suf in sorted(suffixes, key=len, reverse=True):
        if name.endswith(suf) and len(name) > len(suf):
            return name[: -len(suf)]
    return name


def force_column(names: Iterable[object], stem: str) -> tuple[str, float] | None:
    """(name, factor to N) of the first ``<stem>_N|_kN|_klbf`` name in ``names``."""
    for name in names:
        for suf, fac in UNIT_FAMILIES["_N"].items():
            if str(name) == stem + suf:
                return str(name), fac
    return None


def vocabulary_name(header: str, vocab: Vocabulary) -> str:
    """The vocabulary name of a field-style header: ``'WOB (klbf)'`` -> ``'wob_klbf'``.

    A header the vocabulary knows, or one it cannot match to exactly one name
    (stem and unit factor both equal), is returned unchanged, so the
    vocabulary's own error names it.
    """
    if header in vocab.terms:
        return header
    name, unit = split_header(header)
    if unit is None:  # 'RPM', 'Component Type'
        key = name.replace(" ", "_")
        return key if key in vocab.terms else header
    u = normalise_unit(unit)
    factors = {t[u] for t in UNIT_SPELLINGS.values() if u in t}
    stem = name.replace(" ", "_")
    hits = [k for k, term in vocab.terms.items()
            if k.startswith(stem + "_") and "." not in k and term.factor in factors
            and channel_stem(k) == stem]
    return hits[0] if len(hits) == 1 else header


def unseen_levels(values: Mapping[str, Sequence[object]],
                  categories: Mapping[str, Sequence[str]]) -> tuple[np.ndarray, np.ndarray]:
    """Rows whose categorical values a model was not trained on, and why.

    Parameters
    ----------
    values : mapping
        Per categorical column, the rows' values (any type, compared as text).
    categories : mapping
        Per categorical column, the model's levels.

    Returns
    -------
    mask : ndarray of bool, shape (n,)
        Rows with a level the model has not seen (a batch answers them "no answer").
    reasons : ndarray of object, shape (n,)
        ``"component_type 'bit': not in the model's training data (trained on ...)"``,
        '' for the other rows.
    """
    n = len(next(iter(values.values()))) if values else 0
    mask = np.zeros(n, dtype=bool)
    reasons = np.full(n, "", dtype=object)
    for col, vals in values.items():
        levels = [str(v) for v in categories[col]]
        text = np.asarray([str(v).strip() for v in vals], dtype=object)
        bad = ~np.isin(text, levels) & ~mask
        for i in np.flatnonzero(bad):
            reasons[i] = (f"{col} {text[i]!r}: not in the model's training data (trained on "
                          f"{', '.join(levels)})")
        mask |= bad
    return mask, reasons
