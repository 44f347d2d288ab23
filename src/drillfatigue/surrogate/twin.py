"""Digital twin: replay an operating log through the surrogate, accumulate damage.

Every component of the string moves with the bit: its measured depth is
``md = bit_md - s_from_bit`` (a component with md < 0 is not in the hole yet
and accumulates nothing). At each log step the estimator is queried for every
in-hole component (batched over steps x components) and Miner damage is
accumulated with a piecewise-constant (previous value held) rule::

    D_c = sum_i rate_c(t_i) * (t_{i+1} - t_i)       (rates per hour, dt in hours)

so a log of constant conditions over T hours gives exactly D = rate * T. The
interval bounds are accumulated the same way from the lower/upper rates
(treating the surrogate error as fully correlated over time: the conservative
choice, since a bias of the estimator does not average out). The time a
component spends at out-of-domain conditions is summed as well.

Log columns: ``time_s`` (seconds) or ``time`` (date-time text or seconds),
``bit_md_m`` (or ``bit_md_ft``), and any model feature in user units
(:mod:`drillfatigue.io.names`), typically ``rpm``, ``wob_kN``,
``rop_m_per_h``; instead of WOB a hook-load channel (``hook_load_kN``, ...)
with the off-bottom hook load as a constant (:func:`wob_from_hook_load`). Component columns:
``serial``, ``s_from_bit_m`` and the
per-component features (``component_type``, ``location``). Features given by
neither (friction, mud, well) come from ``constants``; the hole geometry at
each component's depth and at the bit (the columns of
:mod:`drillfatigue.well.features`: local dogleg, inclination, ...) comes from
an optional survey table (``md_m``, ``dls_deg_per_30m`` and, for the
inclination features, ``inc_deg``), linearly interpolated. The component list and the
survey can also be built from the string and well configuration
(:func:`components_from_string`, :func:`survey_from_well`).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np
import pandas as pd

from drillfatigue import units
from drillfatigue.config.fatigue import FatigueConfig
from drillfatigue.errors import InputError
from drillfatigue.fatigue.run import joint_locations
from drillfatigue.io.display import Display
from drillfatigue.io.logs import log_bit_md_m, log_times_s
from drillfatigue.io.names import Vocabulary, channel_stem, force_column
from drillfatigue.limits import check_feature_values, check_value
from drillfatigue.plotting import subplots
from drillfatigue.string.segments import build_segments
from drillfatigue.surrogate.facade import Surrogate
from drillfatigue.surrogate.io import save_figure
from drillfatigue.well import build_survey
from drillfatigue.well.features import POSITION_COLUMNS, check_survey, position_features

MD_COLUMN = "md_m"
S_COLUMN = "s_from_bit_m"
_STEP_CHUNK = 20_000  # rows per surrogate batch


@dataclass(frozen=True)
class ReplayResult:
    """Outcome of :func:`replay_log`.

    Attributes
    ----------
    components : DataFrame
        One row per tracked location of every item of the string: serial,
        s_from_bit_m, component columns; ``damage``, ``damage_lower``,
        ``damage_upper`` (Miner damage accumulated while in the model's
        domain: an out-of-domain step adds no number, its time goes to
        ``ood_time_s``), ``last_damage_rate_per_h`` and ``remaining_life_h``
        (+ _lower/_upper) at the last in-domain rate, ``time_in_hole_s``,
        ``ood_time_s`` (this location's time in the hole out of domain);
        ``covered`` and ``not_covered_reason``: an item the model does not
        cover (:func:`not_covered_reasons`) is listed with NaN numbers and the
        reason.
    duration_s : float
        Log span (last - first time).
    ignored_channels : tuple of str
        Standard surface channels of the log that the model does not use.
    """

    components: pd.DataFrame
    duration_s: float
    ignored_channels: tuple[str, ...] = ()


def components_from_table(table: pd.DataFrame) -> pd.DataFrame:
    """Validate a component list (serial, s_from_bit_m, per-component features).

    Kept as a small step: later the list will come from the string config
    (``drillfatigue.string.build_segments``).
    """
    for col in ("serial", S_COLUMN):
        if col not in table.columns:
            raise InputError(col, "missing column in the component list",
                             "serial, s_from_bit_m, component_type, location")
    if table["serial"].astype(str).duplicated().any():
        dup = table["serial"].astype(str)[table["serial"].astype(str).duplicated()].iloc[0]
        raise InputError("serial", f"duplicate serial {dup!r}", "unique serials")
    s = pd.to_numeric(table[S_COLUMN], errors="coerce").to_numpy(dtype=np.float64)
    if not np.all(np.isfinite(s)) or np.any(s < 0):
        raise InputError(S_COLUMN, "non-numeric, NaN or negative value", "finite values >= 0 m")
    out = table.copy()
    out["serial"] = out["serial"].astype(str)
    out[S_COLUMN] = s
    return out.reset_index(drop=True)


def components_from_string(string_cfg: Any, locations: tuple[str, ...] | None = None,
                           kinds: tuple[str, ...] | None = None) -> pd.DataFrame:
    """Tracked locations of a string configuration: every joint x location.

    The locations are those the dataset has (:mod:`drillfatigue.fatigue.run`):
    a joint between two rigid segments, at its distance from the bit, of the
    type of its weaker side (:attr:`drillfatigue.string.segments.Segments.joint_component_type`).

    Parameters
    ----------
    string_cfg : drillfatigue.config.StringConfig
        The ``string`` section (components from the bit up).
    locations : tuple of str, optional
        Locations tracked per joint; default those the fatigue chain
        evaluates for the joint's type (body and connection; the upset
        run-out too on drill pipe and heavy-weight pipe,
        :func:`drillfatigue.fatigue.run.joint_locations`).
    kinds : tuple of str, optional
        Per component, what the tally calls it
        (:attr:`drillfatigue.io.tally.TallyImport.kinds`: ``motor`` for a mud
        motor simulated as a sub); default the component types. A joint next
        to a bit is of kind ``bit``: the bit's connection to the string.

    Returns
    -------
    DataFrame
        Columns ``serial`` (``<component>-<joint>-<B|C|U>``, joint counted
        from the bit within its component), ``component`` (the item: a tally
        row's serial or name), ``kind``, ``component_type``, ``location`` and
        ``s_from_bit_m`` (the joint's distance from the bit, m), as
        :func:`components_from_table` expects.
    """
    fat = FatigueConfig()
    seg = build_segments(string_cfg, 1000.0)  # mud density only sets buoyancy: unused here
    rows = []
    counter: dict[int, int] = {}
    for j in range(seg.n_joints):
        ci = int(seg.joint_component[j])
        comp = string_cfg.components[ci]
        label = (comp.name or f"{comp.type}{ci}").strip().replace(" ", "_")
        k = counter.get(ci, 0)
        counter[ci] = k + 1
        ctype = str(seg.joint_component_type[j])
        kind = kinds[ci] if kinds is not None else ctype
        if "bit" in (seg.component_type[j], seg.component_type[j + 1]):
            kind = "bit"
        for loc in (locations if locations is not None else joint_locations(ctype, fat)):
            rows.append({"serial": f"{label}-{k:03d}-{loc[:1].upper()}", "component": label,
                         "kind": kind, "component_type": ctype, "location": loc,
                         S_COLUMN: float(seg.joint_s_from_bit_m[j])})
    # an item without a joint of its own (a bit, a short sub between stiffer neighbours)
    # is listed too: nothing of the string is left out
    for ci, comp in enumerate(string_cfg.components):
        if ci in counter:
            continue
        label = (comp.name or f"{comp.type}{ci}").strip().replace(" ", "_")
        kind = kinds[ci] if kinds is not None else str(comp.type)
        centre = seg.s_from_bit_m[seg.component_index == ci]
        rows.append({"serial": label, "component": label,
                     "kind": kind if kind in NOT_MODELLED else NO_JOINT, "component_type":
                     str(comp.type), "location": "body",
                     S_COLUMN: float(centre[0]) if centre.size else float("nan")})
    return pd.DataFrame(rows).sort_values(S_COLUMN, kind="stable").reset_index(drop=True)


def survey_from_well(well_cfg: Any, profile: str | None = None) -> pd.DataFrame:
    """Survey table (``md_m``, ``inc_deg``, ``dls_deg_per_30m``) of a well configuration.

    Parameters
    ----------
    well_cfg : drillfatigue.config.WellConfig
        The ``well`` section.
    profile : str, optional
        Profile name (default: the section's active profile).
    """
    sv = build_survey(well_cfg, profile)
    return pd.DataFrame({"md_m": sv.md_m, "inc_deg": np.degrees(sv.inc_rad),
                         "dls_deg_per_30m": sv.dls_deg_per_30m})


#: Usual surface channels of a drilling log (any unit suffix). One the model
#: does not use is ignored (and reported); any other unknown column is an error.
SURFACE_CHANNELS: frozenset[str] = frozenset({
    "rpm", "wob", "rop", "hook_load", "off_bottom_hook_load", "surface_torque", "torque",
    "standpipe_pressure", "spp", "flow_rate", "flow", "block_position", "hole_depth",
    "hole_md"})


HOOK_LOAD_STEM = "hook_load"
OFF_BOTTOM_STEM = "off_bottom_hook_load"


def wob_from_hook_load(log: pd.DataFrame, constants: Mapping[str, Any] | None
                       ) -> tuple[pd.DataFrame, dict[str, Any]]:
    """Replace a hook-load channel by the weight on bit it implies.

    WOB = off-bottom (free-rotating) hook load - on-bottom hook load, the
    driller's definition; the off-bottom value comes from the constants
    (``off_bottom_hook_load_kN`` etc.) or from a log column of that name.
    A log that already has a WOB channel (field logs carry both), or no
    hook-load channel, is returned unchanged. Returns the log (with ``wob_N`` instead of the hook
    load) and the constants without the off-bottom entry.
    """
    consts = dict(constants or {})
    hl = force_column(log.columns, HOOK_LOAD_STEM)
    ob_c = force_column(consts, OFF_BOTTOM_STEM)
    ob_l = force_column(log.columns, OFF_BOTTOM_STEM)
    has_wob = any(str(c).startswith("wob_") or str(c) == "operation.wob_N" for c in log.columns)
    if hl is None:
        if ob_c is not None:
            consts.pop(ob_c[0])
        return log, consts
    if has_wob:
        # a measured WOB channel wins; the hook load stays a surface channel (reported)
        if ob_c is not None:
            consts.pop(ob_c[0])
        return log, consts
    if ob_c is None and ob_l is None:
        raise InputError(OFF_BOTTOM_STEM + "_kN", "needed to turn hook load into WOB",
                         "--set off_bottom_hook_load_kN=VALUE (free-rotating hook load)")
    h = pd.to_numeric(log[hl[0]], errors="coerce").to_numpy(dtype=np.float64) * hl[1]
    check_feature_values(hl[0], "hook_load_N", np.nan_to_num(h), hl[1])  # NaN: refused below
    if ob_c is not None:
        try:
            off = float(consts.pop(ob_c[0])) * ob_c[1]
        except (TypeError, ValueError):
            raise InputError(ob_c[0], "non-numeric value", "a finite number") from None
        check_value(ob_c[0], "off_bottom_hook_load_N", off, ob_c[0], ob_c[1])
    else:
        off = pd.to_numeric(log[ob_l[0]], errors="coerce").to_numpy(dtype=np.float64) * ob_l[1]
        check_feature_values(ob_l[0], "off_bottom_hook_load_N", np.nan_to_num(off),
                             ob_l[1])
    wob = off - h
    if not np.all(np.isfinite(wob)):
        raise InputError(hl[0], "non-numeric or NaN value", "finite hook loads")
    if np.any(wob < 0.0):
        raise InputError(hl[0], "hook load above the off-bottom hook load (negative WOB)",
                         f"hook load <= {OFF_BOTTOM_STEM}")
    drop = [hl[0]] + ([ob_l[0]] if ob_l is not None else [])
    out = log.drop(columns=drop)
    out["wob_N"] = wob
    return out, consts


class _ConditionCache:
    """Surrogate answers per distinct operating condition, shared over a replay.

    The float32 network's round-off depends on where a row falls in a batch
    (BLAS blocking, thread shares), so the same conditions asked twice could
    get rates a few 1e-7 apart. Each distinct feature row is therefore
    predicted once, the first time it occurs, and every later occurrence (in
    this or a later chunk) gets that same answer: constant conditions over T
    hours give exactly ``rate * T``. Rows are keyed by their exact bit
    patterns (float64 features, int64 category codes).
    """

    _KEYS = ("log10", "lower", "upper", "ood")

    def __init__(self, model: Surrogate) -> None:
        self.model = model
        self.known: dict[bytes, int] = {}
        # answers by slot, grown by doubling (a replay adds new conditions every chunk)
        self.values: dict[str, np.ndarray] = {
            k: np.empty(1024, dtype=bool if k == "ood" else np.float64) for k in self._KEYS}

    def predict(self, x_num: np.ndarray, x_cat: np.ndarray) -> dict[str, np.ndarray]:
        """``log10``, ``lower``, ``upper`` and ``ood`` per row of ``x_num``/``x_cat``."""
        n = x_num.shape[0]
        if n == 0:
            return {k: np.zeros(0, dtype=bool if k == "ood" else np.float64)
                    for k in self._KEYS}
        rows = np.hstack([np.ascontiguousarray(x_num, dtype=np.float64).view(np.uint64),
                          np.ascontiguousarray(x_cat, dtype=np.int64).view(np.uint64)])
        uniq, first, inverse = np.unique(rows, axis=0, return_index=True, return_inverse=True)
        slot = np.empty(uniq.shape[0], dtype=np.int64)
        new = []
        for u in range(uniq.shape[0]):
            key = uniq[u].tobytes()
            s = self.known.get(key)
            if s is None:
                s = len(self.known)
                self.known[key] = s
                new.append(u)
            slot[u] = s
        if new:
            rows_new = first[np.asarray(new)]
            r = self.model.predict_array(x_num[rows_new], x_cat[rows_new])
            end = len(self.known)
            for k in self._KEYS:
                buf = self.values[k]
                if end > buf.size:
                    grown = np.empty(max(end, 2 * buf.size), dtype=buf.dtype)
                    grown[:end - len(new)] = buf[:end - len(new)]
                    self.values[k] = buf = grown
                buf[end - len(new):end] = r[k]
        pos = slot[np.asarray(inverse).reshape(-1)]
        return {k: self.values[k][pos] for k in self._KEYS}


#: Kind of an item with no joint of its own (:func:`components_from_string`).
NO_JOINT = "no_joint"
#: Why an item of a string is not covered, by what the tally calls it.
NOT_MODELLED = {
    NO_JOINT: "no joint of its own: the joints at both its ends are tracked under its "
              "neighbours, whose sections are the weaker (as the dataset assigns them)",
    "bit": "the bit and its connection to the string: not a location the model was trained "
           "on (the design's strings end in the bit face)",
    "motor": "mud motor or rotary-steerable tool: not modelled by the simulator (placed as a "
             "plain sub of its size for the string's mechanics)",
}


def not_covered_reasons(components: pd.DataFrame, model: Surrogate) -> np.ndarray:
    """Why each tracked location gets no damage from ``model`` ('' where it is covered).

    Not covered: a bit or an unmodelled tool (:data:`NOT_MODELLED`), a component
    type or location the model was not trained on, or a combination of the two
    its training data does not have (a collar ``upset``).
    """
    n = len(components)
    out = np.full(n, "", dtype=object)
    kinds = (components["kind"].astype(str).to_numpy() if "kind" in components.columns
             else np.full(n, "", dtype=object))
    types = (components["component_type"].astype(str).to_numpy()
             if "component_type" in components.columns else np.full(n, "", dtype=object))
    levels = model.categories
    cat_cols = [c for c in model.categorical if c in components.columns]
    # one array per column, read once: this runs on every piece of a followed log
    cats = {col: components[col].astype(str).to_numpy() for col in cat_cols}
    known = np.ones(n, dtype=bool)
    for i in range(n):
        for kind in (kinds[i], types[i]):
            if kind in NOT_MODELLED:
                out[i] = NOT_MODELLED[kind]
                break
        if out[i]:
            known[i] = False
            continue
        for col in cat_cols:
            v = cats[col][i]
            if v not in levels.get(col, []):
                out[i] = (f"{col} {v!r}: not in the model's training data (trained on "
                          f"{', '.join(levels.get(col, []))})")
                known[i] = False
                break
    rows = np.flatnonzero(known)
    if rows.size and len(cat_cols) == len(model.categorical) and model.categorical:
        codes = np.column_stack([model.preprocessor.codes_for(col, cats[col][rows])
                                 for col in model.categorical])
        group = model.domain._group_of(codes, rows.size)
        unseen = np.flatnonzero(group < 0)
        seen = ", ".join(model.domain.seen_combinations()) if unseen.size else ""
        for r in unseen:
            i = rows[r]
            combo = " ".join(cats[c][i] for c in model.categorical)
            out[i] = (f"{combo}: a combination the model was not trained on (trained on "
                      f"{seen})")
    return out


def replay_log(log: pd.DataFrame, components: pd.DataFrame, model: Surrogate,
               constants: Mapping[str, Any] | None = None,
               survey: pd.DataFrame | None = None) -> ReplayResult:
    """Replay an operating log through ``model`` and accumulate damage per component.

    Parameters
    ----------
    log : DataFrame
        Time series, see the module docstring.
    components : DataFrame
        Component list, see :func:`components_from_table`.
    model : Surrogate
    constants : mapping, optional
        ``{user name: value}`` of features constant over the log.
    survey : DataFrame, optional
        Columns ``md_m``, ``dls_deg_per_30m`` and (for the inclination
        features) ``inc_deg``: the hole geometry features of each component
        (:func:`drillfatigue.well.features.position_features`).

    Returns
    -------
    ReplayResult
    """
    all_comps = components_from_table(components)
    reasons = not_covered_reasons(all_comps, model)
    covered = reasons == ""
    comps = all_comps[covered].reset_index(drop=True)
    log, constants = wob_from_hook_load(log, constants)
    t = log_times_s(log)
    bit_md = log_bit_md_m(log)
    vocab = Vocabulary(model.features, model.categorical)
    inputs = _replay_inputs(log, comps, vocab, constants)
    geometry = _survey_geometry(survey, model, bit_md)
    sources = _feature_sources(model, vocab, inputs, {MD_COLUMN, *geometry.columns})
    damage = _accumulate(model, inputs, sources, geometry, comps[S_COLUMN].to_numpy(), t,
                         bit_md)
    return ReplayResult(components=_replay_table(all_comps, comps, covered, reasons, damage),
                        duration_s=float(t[-1] - t[0]), ignored_channels=inputs.ignored)


@dataclass(frozen=True)
class _ReplayInputs:
    """The log, the components and the constants of a replay in the model's units."""

    log: pd.DataFrame
    components: pd.DataFrame
    constants: pd.DataFrame
    #: surface channels of the log the model does not use
    ignored: tuple[str, ...]

    def frame(self, source: str) -> pd.DataFrame:
        return {"log": self.log, "components": self.components,
                "constants": self.constants}[source]


def _replay_inputs(log: pd.DataFrame, comps: pd.DataFrame, vocab: Vocabulary,
                   constants: Mapping[str, Any] | None) -> _ReplayInputs:
    """The log (without its time, bit depth and unused surface channels), the covered
    components and the constants, each as a frame of the model's columns."""
    skip = {"time_s", "time",
            *(c for c in map(str, log.columns) if channel_stem(c) == "bit_md")}
    ignored = tuple(str(c) for c in log.columns
                    if c not in skip and str(c) not in vocab.terms
                    and channel_stem(str(c)) in SURFACE_CHANNELS)
    skip |= set(ignored)
    log_si = vocab.frame_from_table(log[[c for c in log.columns if c not in skip]], require=())
    comp_si = vocab.frame_from_table(comps.drop(columns=["serial"]), require=(),
                                     passthrough=[c for c in comps.columns
                                                  if c not in vocab.terms and c != "serial"])
    const_si = (vocab.frame_from_mapping(dict(constants), require=()) if constants
                else pd.DataFrame(index=[0]))
    return _ReplayInputs(log_si, comp_si, const_si, ignored)


@dataclass(frozen=True)
class _Geometry:
    """The hole geometry features the model takes from the survey, and the survey."""

    columns: tuple[str, ...] = ()
    survey: tuple[np.ndarray, np.ndarray, np.ndarray | None] | None = None


def _survey_geometry(survey: pd.DataFrame | None, model: Surrogate,
                     bit_md: np.ndarray) -> _Geometry:
    """The checked survey; a bit depth of the log beyond its TD is an input error."""
    if survey is None:
        return _Geometry()
    geo_cols = tuple(c for c in model.features if c in POSITION_COLUMNS)
    for col in ("md_m", "dls_deg_per_30m"):
        if col not in survey.columns:
            raise InputError(col, "missing column in the survey",
                             "md_m, dls_deg_per_30m (and inc_deg)")
    survey_cols = check_survey(survey["md_m"], survey["dls_deg_per_30m"],
                               survey["inc_deg"] if "inc_deg" in survey.columns else None,
                               geo_cols)
    td_m = float(np.max(survey_cols[0]))
    if np.any(bit_md > td_m):
        i = int(np.argmax(bit_md > td_m))
        raise InputError("bit_md_m", f"{bit_md[i]:.6g} m at row {i + 1} of the log is "
                         f"beyond the well's total depth {td_m:.6g} m",
                         f"0 <= bit_md_m <= {td_m:.6g} (the survey's last MD)")
    return _Geometry(geo_cols, survey_cols)


def _feature_sources(model: Surrogate, vocab: Vocabulary, inputs: _ReplayInputs,
                     derived: set[str]) -> dict[str, str]:
    """Where each model feature comes from: ``log``, ``components``, ``constants`` or
    ``derived``; a feature from none or from two is an input error."""
    sources: dict[str, str] = {}
    for col in model.features + model.categorical:
        where = [name for name in ("log", "components", "constants")
                 if col in inputs.frame(name).columns]
        if col in derived:
            where.append("derived")
        if not where:
            raise InputError(vocab.names_for(col)[0], "not given by the log, the components, "
                             "the constants or the survey", "add it with --set NAME=VALUE")
        if len(where) > 1:
            raise InputError(vocab.names_for(col)[0], f"given twice ({' and '.join(where)})",
                             "one source per feature")
        sources[col] = where[0]
    return sources


@dataclass(frozen=True)
class _Damage:
    """What a replay accumulates per component (n_components,)."""

    damage: np.ndarray
    lower: np.ndarray
    upper: np.ndarray
    ood_s: np.ndarray
    in_hole_s: np.ndarray
    #: (n_components, 3): rate, lower, upper per hour at the last in-hole step
    last: np.ndarray


def _accumulate(model: Surrogate, inputs: _ReplayInputs, sources: dict[str, str],
                geometry: _Geometry, s_comp: np.ndarray, t: np.ndarray,
                bit_md: np.ndarray) -> _Damage:
    """Rate x time per component over the log's steps, in chunks of rows."""
    pre = model.preprocessor
    n_t, n_c = t.size, s_comp.size
    dt_s = np.diff(t)  # (n_t - 1,)
    dt_h = dt_s / units.HOUR_S
    acc = _Damage(np.zeros(n_c), np.zeros(n_c), np.zeros(n_c), np.zeros(n_c), np.zeros(n_c),
                  np.full((n_c, 3), np.nan))
    # category codes encoded once (per component / constant)
    cat_codes = {col: pre.codes_for(col, inputs.frame(sources[col])[col].to_numpy())
                 for col in model.categorical}
    steps_per_chunk = max(1, _STEP_CHUNK // max(n_c, 1))
    cache = _ConditionCache(model)
    for a in range(0, n_t - 1, steps_per_chunk):
        b = min(a + steps_per_chunk, n_t - 1)
        idx_t = np.repeat(np.arange(a, b), n_c)
        idx_c = np.tile(np.arange(n_c), b - a)
        md = bit_md[idx_t] - s_comp[idx_c]
        in_hole = md >= 0.0
        x_num, x_cat = _chunk_rows(model, inputs, sources, geometry, cat_codes,
                                   (idx_t, idx_c, md, bit_md[idx_t]))
        r = cache.predict(x_num[in_hole], x_cat[in_hole])
        rate = np.zeros(idx_t.size)
        lo = np.zeros(idx_t.size)
        hi = np.zeros(idx_t.size)
        ood = np.zeros(idx_t.size, dtype=bool)
        ood[in_hole] = r["ood"]
        # out of domain: no number, the time is counted instead
        answered = np.flatnonzero(in_hole)[~r["ood"]]
        rate[answered] = 10.0 ** r["log10"][~r["ood"]]
        lo[answered] = 10.0 ** r["lower"][~r["ood"]]
        hi[answered] = 10.0 ** r["upper"][~r["ood"]]
        w = dt_h[idx_t]
        acc.damage[:] += np.bincount(idx_c, rate * w, minlength=n_c)
        acc.lower[:] += np.bincount(idx_c, lo * w, minlength=n_c)
        acc.upper[:] += np.bincount(idx_c, hi * w, minlength=n_c)
        acc.ood_s[:] += np.bincount(idx_c, ood * dt_s[idx_t], minlength=n_c)
        acc.in_hole_s[:] += np.bincount(idx_c, in_hole * dt_s[idx_t], minlength=n_c)
        if answered.size:
            # later rows overwrite earlier ones: the last in-hole step per component
            acc.last[idx_c[answered], 0] = rate[answered]
            acc.last[idx_c[answered], 1] = lo[answered]
            acc.last[idx_c[answered], 2] = hi[answered]
    return acc


def _chunk_rows(model: Surrogate, inputs: _ReplayInputs, sources: dict[str, str],
                geometry: _Geometry, cat_codes: dict[str, np.ndarray],
                rows: tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]
                ) -> tuple[np.ndarray, np.ndarray]:
    """The model's numeric and categorical inputs of a chunk of (step, component) rows.

    ``rows``: per row its step, its component, the component's MD and the bit's MD.
    """
    idx_t, idx_c, md, bit_md = rows
    x_num = np.empty((idx_t.size, len(model.features)))
    geo = (position_features(*geometry.survey, md, bit_md, geometry.columns)
           if geometry.columns and geometry.survey is not None else {})
    for j, col in enumerate(model.features):
        src = sources[col]
        if col == MD_COLUMN:
            x_num[:, j] = md
        elif src == "derived":  # hole geometry from the survey
            x_num[:, j] = geo[col]
        elif src == "log":
            x_num[:, j] = inputs.log[col].to_numpy(dtype=np.float64)[idx_t]
        elif src == "components":
            x_num[:, j] = inputs.components[col].to_numpy(dtype=np.float64)[idx_c]
        else:
            x_num[:, j] = float(inputs.constants[col].iloc[0])
    x_cat = np.zeros((idx_t.size, len(model.categorical)), dtype=np.int64)
    for j, col in enumerate(model.categorical):
        src = sources[col]
        codes = cat_codes[col]
        x_cat[:, j] = (codes[idx_t] if src == "log" else codes[idx_c] if src == "components"
                       else codes[0])
    return x_num, x_cat


def _replay_table(all_comps: pd.DataFrame, comps: pd.DataFrame, covered: np.ndarray,
                  reasons: np.ndarray, acc: _Damage) -> pd.DataFrame:
    """Every item of the string with its damage, remaining life and times; the ones the
    model does not cover with the reason."""
    last = acc.last
    remaining = np.clip(1.0 - acc.damage, 0.0, None)
    res = comps.copy()
    res["damage"] = acc.damage
    res["damage_lower"] = acc.lower
    res["damage_upper"] = acc.upper
    res["last_damage_rate_per_h"] = last[:, 0]
    with np.errstate(divide="ignore", invalid="ignore"):
        res["remaining_life_h"] = remaining / last[:, 0]
        res["remaining_life_h_lower"] = np.clip(1.0 - acc.upper, 0.0, None) / last[:, 2]
        res["remaining_life_h_upper"] = np.clip(1.0 - acc.lower, 0.0, None) / last[:, 1]
    res["time_in_hole_s"] = acc.in_hole_s
    res["ood_time_s"] = acc.ood_s
    out = all_comps.copy()
    for col in res.columns.difference(all_comps.columns, sort=False):
        full = np.full(len(out), np.nan)
        full[covered] = res[col].to_numpy(dtype=np.float64)
        out[col] = full
    out["covered"] = covered
    out["not_covered_reason"] = reasons
    return out


def replay_summary(result: ReplayResult) -> dict[str, Any]:
    """The figures of a replay that its summary (CLI ``summary.json``, the service) reports.

    ``max_damage_in_domain`` is the largest damage accumulated in the model's
    domain (None when no covered location was ever in domain);
    ``ood_location_hours`` sums every covered location's hours out of domain
    (location-hours, not a duration: ``max_ood_time_h`` is the longest of one
    location); ``not_covered`` lists each item the model does not cover, with
    the reason.
    """
    c = result.components
    cov = c[c["covered"]]
    answered = cov[cov["ood_time_s"] < cov["time_in_hole_s"]]
    worst = answered.loc[answered["damage"].idxmax()] if len(answered) else None
    items = c[~c["covered"]].groupby("component", sort=False)["not_covered_reason"].first() \
        if "component" in c.columns else c[~c["covered"]].set_index("serial")["not_covered_reason"]
    return {
        "duration_h": result.duration_s / units.HOUR_S,
        "n_locations": int(len(c)),
        "n_locations_covered": int(len(cov)),
        "n_locations_answered": int(len(answered)),
        "max_damage_in_domain": None if worst is None else float(worst["damage"]),
        "max_damage_serial": None if worst is None else str(worst["serial"]),
        "max_damage_s_from_bit_m": None if worst is None else float(worst[S_COLUMN]),
        "ood_location_hours": float(cov["ood_time_s"].sum()) / units.HOUR_S,
        "max_ood_time_h": float(cov["ood_time_s"].max()) / units.HOUR_S if len(cov) else 0.0,
        "n_locations_some_time_ood": int((cov["ood_time_s"] > 0).sum()),
        "not_covered": [{"item": str(k), "reason": str(v)} for k, v in items.items()],
        "ignored_log_channels": list(result.ignored_channels),
    }


def retire_list(result: ReplayResult, retire_at_damage: float,
                retire_within_h: float | None = None) -> list[dict[str, Any]]:
    """Locations to retire, and every location or item whose damage is not known.

    A covered location is listed to retire when its upper-bound damage reaches
    ``retire_at_damage`` or its lower-bound remaining life is shorter than
    ``retire_within_h``; one that spent time out of the model's domain is
    listed to inspect (its damage then is unknown, none is counted); an item
    the model does not cover is listed with the reason. Most damaged first,
    then the inspections, then the items not covered: nothing is left out
    silently.
    """
    c = result.components
    out: list[dict[str, Any]] = []
    cov = c[c["covered"]].sort_values("damage", ascending=False, kind="stable")
    for _, row in cov.iterrows():
        why = []
        if row["damage_upper"] >= retire_at_damage:
            why.append(f"upper-bound damage {row['damage_upper']:.3g} >= {retire_at_damage:g}")
        life_lo = float(row["remaining_life_h_lower"])
        if retire_within_h is not None and life_lo < retire_within_h:
            why.append(f"lower-bound remaining life {life_lo:.3g} h < {retire_within_h:g} h")
        if why:
            out.append({"serial": str(row["serial"]), "action": "retire",
                        S_COLUMN: float(row[S_COLUMN]), "damage": float(row["damage"]),
                        "damage_upper": float(row["damage_upper"]),
                        "remaining_life_h_lower": life_lo, "reason": "; ".join(why)})
    for _, row in cov[cov["ood_time_s"] > 0].iterrows():
        out.append({"serial": str(row["serial"]), "action": "inspect",
                    S_COLUMN: float(row[S_COLUMN]), "damage": float(row["damage"]),
                    "damage_upper": float(row["damage_upper"]),
                    "remaining_life_h_lower": float(row["remaining_life_h_lower"]),
                    "reason": f"{row['ood_time_s'] / units.HOUR_S:.3g} h out of the model's "
                              "domain: no damage known for that time (the damage shown is "
                              "the in-domain part)"})
    for _, row in c[~c["covered"]].iterrows():
        out.append({"serial": str(row["serial"]), "action": "not covered",
                    S_COLUMN: float(row[S_COLUMN]), "damage": None, "damage_upper": None,
                    "remaining_life_h_lower": None,
                    "reason": f"not covered: {row['not_covered_reason']}"})
    return out


def plot_damage_along_string(result: ReplayResult, path: str, display: Any = None) -> None:
    """Accumulated damage (with interval) versus distance from the bit, log scale, PNG.

    ``display``: a :class:`drillfatigue.io.display.Display` for the distance
    axis (default SI, m).
    """
    display = display if display is not None else Display("si")
    c = result.components.sort_values(S_COLUMN)
    fig, ax = subplots(figsize=(7, 4))
    s = display.value("length", c[S_COLUMN].to_numpy())
    d = c["damage"].to_numpy()
    lo = c["damage_lower"].to_numpy()
    hi = c["damage_upper"].to_numpy()
    pos = d > 0
    ax.errorbar(s[pos], d[pos], yerr=[d[pos] - lo[pos], hi[pos] - d[pos]], fmt="o", ms=4,
                capsize=3, label="accumulated damage (interval)")
    if "ood_time_s" in c and (c["ood_time_s"] > 0).any():
        m = (c["ood_time_s"].to_numpy() > 0) & pos
        ax.plot(s[m], d[m], "rx", ms=8, label="some time out of domain")
    ax.set_yscale("log")
    ax.set_xlabel(f"distance from bit ({display.unit('length')})")
    ax.set_ylabel("Miner damage (-)")
    ax.set_title(f"Accumulated damage over {result.duration_s / units.HOUR_S:.3g} h")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend()
    fig.tight_layout()
    save_figure(fig, path)
