"""Case design: sample operating conditions over ranges and give each case a stable id.

The design maps a quasi-random sample in the unit hypercube (scrambled Sobol
or Latin hypercube, ``scipy.stats.qmc``, seeded) to the design variables of
:class:`drillfatigue.config.SweepConfig`, applies them by dotted path to the
base case and validates every resulting case with the strict case models
before any simulation runs.

Case id: the first 12 hex digits of the SHA-256 of the case's canonical JSON
(sorted keys, no whitespace) over the simulation sections only (every
``CaseConfig`` section except ``fatigue``, which the fatigue stage applies to
all cases). The same inputs always get the same id, independent of row order,
seed or design method. Rows that give identical cases are merged (warning).

References
----------
Owen, A. B. (1998). Scrambling Sobol' and Niederreiter-Xing points. J. Complexity 14.
McKay, Beckman, Conover (1979). Latin hypercube sampling. Technometrics 21(2).
"""

from __future__ import annotations

import copy
import hashlib
import json
import math
import re
import warnings
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd
from scipy.stats import qmc

from pydantic import BaseModel

from drillfatigue.config import CaseConfig, OperationConfig, case_from_dict, validate
from drillfatigue.config.sweep import SweepConfig, VariableSpec
from drillfatigue.errors import InputError
from drillfatigue.files import atomic_output

__all__ = [
    "CASE_ID_LENGTH",
    "apply_overrides",
    "base_case_from_params",
    "canonical_json",
    "case_id_of",
    "DesignSpace",
    "design_cases",
    "design_space",
    "inputs_sha256",
    "RIG_PATHS",
    "read_cases",
    "rig_case",
    "simulation_inputs",
    "sobol_unit",
    "write_cases",
]

CASE_ID_LENGTH = 12
#: Operation inputs the rig section takes over (``sweep.boundaries: rig``): the value of the
#: operation path is moved to the rig path and the operation field is reset to its default.
#: The ROP goes to the block's set-point in ``block_mode: rop`` and to the autodriller's ROP
#: limit in ``block_mode: autodriller`` (:data:`ROP_TARGETS`).
RIG_PATHS = {"operation.rop_m_per_s": "rig.rop_set_m_per_s",
             "operation.wob_N": "rig.autodriller.wob_set_N",
             "operation.lobe_amplitude_m": "rig.rock.lobe_amplitude_m",
             "operation.lobe_count": "rig.rock.lobe_count"}
#: Where the designed ROP goes, per block mode: the ``rop`` block lowers at it; the
#: autodriller drills at it unless the WOB limit (its set-point) is reached first, as a
#: driller's autodriller with an ROP target and a WOB limit does.
ROP_TARGETS = {"rop": "rig.rop_set_m_per_s",
               "autodriller": "rig.autodriller.rop_limit_m_per_s"}
_TOKEN = re.compile(r"([A-Za-z_][A-Za-z0-9_]*)((?:\[\d+\])*)")


def case_sections() -> tuple[str, ...]:
    """Names of the case sections of :class:`CaseConfig`, in model order."""
    return tuple(CaseConfig.model_fields)


def base_case_from_params(params: Any) -> dict[str, Any]:
    """The base case of a ``Params`` object as a JSON-ready dict (case sections only)."""
    dump = params.model_dump(mode="json")
    return {name: dump[name] for name in case_sections() if name in dump}


def canonical_json(data: Any) -> str:
    """Canonical JSON text: sorted keys, no whitespace, NaN/inf rejected."""
    return json.dumps(data, sort_keys=True, separators=(",", ":"), ensure_ascii=True,
                      allow_nan=False)


#: Optional fields (section, key) left out of a case's identity while not given (None),
#: so that a case that does not use them keeps its id.
_OPTIONAL_FIELDS = (("operation", "wob_N"), ("string", "bha"))


def simulation_inputs(case: Mapping[str, Any]) -> dict[str, Any]:
    """The part of a case that identifies a simulation (all sections but ``fatigue``; an
    absent ``rig`` section and the :data:`_OPTIONAL_FIELDS` not given are left out, so
    cases without them keep their ids)."""
    out = {k: v for k, v in case.items() if k != "fatigue" and not (k == "rig" and v is None)}
    for section, key in _OPTIONAL_FIELDS:
        part = out.get(section)
        if isinstance(part, dict) and key in part and part[key] is None:
            out[section] = {k: v for k, v in part.items() if k != key}
    return out


def inputs_sha256(data: Any) -> str:
    """Full SHA-256 hex digest of the canonical JSON of ``data``."""
    return hashlib.sha256(canonical_json(data).encode("ascii")).hexdigest()


def case_id_of(case: Mapping[str, Any]) -> str:
    """Stable short id of a case: hash of its simulation inputs (see module doc)."""
    return inputs_sha256(simulation_inputs(case))[:CASE_ID_LENGTH]


def _split_path(path: str) -> list[str | int]:
    keys: list[str | int] = []
    for part in path.split("."):
        m = _TOKEN.fullmatch(part)
        if m is None:
            raise InputError(path, "bad configuration path",
                             "a dotted path such as operation.rpm")
        keys.append(m.group(1))
        keys.extend(int(i) for i in re.findall(r"\[(\d+)\]", m.group(2)))
    return keys


def apply_overrides(base: Mapping[str, Any], overrides: Mapping[str, Any],
                    prefix: str = "sweep.variables") -> dict[str, Any]:
    """Return a deep copy of ``base`` with values set by dotted path.

    Parameters
    ----------
    base : mapping
        Full case dict (every field present, as from ``model_dump``).
    overrides : mapping of str to value
        ``{"operation.rpm": 120.0, "string.components[0].od_m": 0.127}``.
    prefix : str
        Prefix of the field name in errors.

    Raises
    ------
    InputError
        ``<prefix>.<path>`` when the path does not exist in ``base``.
    """
    out = copy.deepcopy(dict(base))
    for path, value in overrides.items():
        keys = _split_path(path)
        node: Any = out
        for i, key in enumerate(keys):
            last = i == len(keys) - 1
            if isinstance(key, int):
                ok = isinstance(node, list) and key < len(node)
            else:
                ok = isinstance(node, dict) and key in node
            if not ok:
                where = ".".join(str(k) for k in keys[: i + 1])
                raise InputError(f"{prefix}.{path}", f"unknown configuration path (no '{where}' "
                                 "in the case configuration)",
                                 "a field of the case sections, see params.yaml")
            if last:
                node[key] = copy.deepcopy(value)
            else:
                node = node[key]
    return out


def rig_case(case: Mapping[str, Any], rig: Mapping[str, Any]) -> dict[str, Any]:
    """``case`` driven by the rig section ``rig``, with the operation inputs of
    :data:`RIG_PATHS` moved onto it.

    The ROP goes where :data:`ROP_TARGETS` says for the block mode (the other
    modes have no ROP input; :func:`design_cases` refuses the ROP as a design
    variable for them). The operation fields are reset to their defaults,
    which the rig-section check of :class:`CaseConfig` reads as "not given".
    """
    out = copy.deepcopy(dict(case))
    section = copy.deepcopy(dict(rig))
    op = out.setdefault("operation", {})
    defaults = OperationConfig.model_fields
    for src, dst in RIG_PATHS.items():
        key = src.split(".", 1)[1]
        if key not in op:
            continue
        value = op[key]
        op[key] = defaults[key].default
        if value is None:  # an optional input not given (operation.wob_N)
            continue
        if dst == "rig.rop_set_m_per_s":
            target = ROP_TARGETS.get(section.get("block_mode", "autodriller"))
            if target is None:
                continue
            dst = target
        *parents, leaf = dst.split(".")[1:]
        node = section
        for name in parents:
            node = node.setdefault(name, {})
        node[leaf] = value
    out["rig"] = section
    return out


def _validate_case(case: dict[str, Any], field: str,
                   model: type[BaseModel] = CaseConfig,
                   variables: Sequence[str] = ()) -> dict[str, Any]:
    """Validate a case dict; on error re-raise naming ``field``; return the JSON dump.

    An error in one of the design's ``variables`` (a probe case carries them at
    an extreme) names ``sweep.variables.<path>`` instead of ``field``.
    """
    try:
        cfg = case_from_dict(case) if model is CaseConfig else validate(model, case)
    except InputError as exc:
        if exc.field in variables:
            raise InputError(f"sweep.variables.{exc.field}", exc.problem, exc.allowed) from None
        raise InputError(field, f"gives an invalid case: {exc.field}: {exc.problem}",
                         exc.allowed) from None
    return cfg.model_dump(mode="json")


def _column_values(spec: VariableSpec, u: np.ndarray) -> list[Any]:
    """Map unit-interval samples ``u`` (shape (n,)) to the variable's values."""
    if spec.choices is not None:
        k = len(spec.choices)
        idx = np.minimum((u * k).astype(np.int64), k - 1)
        return [copy.deepcopy(spec.choices[i]) for i in idx]
    lo, hi = float(spec.low), float(spec.high)  # type: ignore[arg-type]
    if spec.kind == "integer":
        if spec.scale == "log":
            x = np.exp(math.log(lo) + u * (math.log(hi + 1.0) - math.log(lo)))
        else:
            x = lo + u * (hi - lo + 1.0)
        return [int(v) for v in np.clip(np.floor(x), lo, hi)]
    if spec.scale == "log":
        x = np.exp(math.log(lo) + u * (math.log(hi) - math.log(lo)))
    else:
        x = lo + u * (hi - lo)
    return [float(v) for v in np.clip(x, lo, hi)]


def _extremes(spec: VariableSpec) -> list[Any]:
    if spec.choices is not None:
        return list(spec.choices)
    if spec.kind == "integer":
        return [int(spec.low), int(spec.high)]  # type: ignore[arg-type]
    return [float(spec.low), float(spec.high)]  # type: ignore[arg-type]


def sobol_unit(n: int, d: int, seed: int, field: str = "sweep.n_cases") -> np.ndarray:
    """Scrambled Sobol sample of ``n`` points rounded up to a power of two (warning), (2^m, d)."""
    m = max(0, math.ceil(math.log2(n)))
    if 2**m != n:
        warnings.warn(f"{field}={n} rounded up to {2**m}: a Sobol design "
                      "is balanced only for a power of two", UserWarning, stacklevel=4)
    return qmc.Sobol(d=d, scramble=True, seed=seed).random_base2(m)


def _unit_sample(cfg: SweepConfig, d: int) -> np.ndarray:
    """Unit-hypercube sample, shape (n, d); see :class:`SweepConfig` for the rules."""
    if cfg.method == "sobol":
        return sobol_unit(cfg.n_cases, d, cfg.seed)
    if cfg.method == "adaptive":
        return sobol_unit(cfg.adaptive.n_initial, d, cfg.seed, "sweep.adaptive.n_initial")
    return qmc.LatinHypercube(d=d, seed=cfg.seed).random(cfg.n_cases)


def _column_frame_value(values: list[Any]) -> list[Any]:
    """Make a categorical column Parquet-friendly: JSON text unless one scalar type."""
    types = {type(v) for v in values}
    if types <= {int, float} or types == {str} or types == {bool}:
        return values
    return [canonical_json(v) for v in values]


class DesignSpace:
    """The checked design variables of a sweep and the map from the unit hypercube to cases.

    Built by :func:`design_space` (which validates every variable at its
    extremes first); :meth:`cases` turns unit-cube points into the case table.
    """

    def __init__(self, cfg: SweepConfig, names: list[str], base: dict[str, Any],
                 finish: Any, model: type[BaseModel]) -> None:
        self.cfg = cfg
        self.names = names
        self.base = base
        self.finish = finish
        self.model = model

    @property
    def dim(self) -> int:
        """Number of design variables (columns of a unit sample)."""
        return len(self.names)

    def cases(self, unit: np.ndarray, first_index: int = 0,
              skip: set[str] | frozenset[str] = frozenset()) -> pd.DataFrame:
        """Case table of the unit-cube points ``unit`` (shape (n, dim)).

        Row ``i`` gets ``design_index = first_index + i``; a point whose case
        id is in ``skip`` or repeats an earlier point is left out (the rows
        kept are the first of each case). Columns as :func:`design_cases`.
        """
        names = self.names
        columns = {p: _column_values(self.cfg.variables[p], unit[:, j])
                   for j, p in enumerate(names)}
        rows: list[dict[str, Any]] = []
        seen = set(skip)
        for i in range(unit.shape[0]):
            overrides = {p: columns[p][i] for p in names}
            case = _validate_case(self.finish(apply_overrides(self.base, overrides)),
                                  "sweep.variables", self.model)
            cid = case_id_of(case)
            if cid in seen:
                continue
            seen.add(cid)
            rows.append({"case_id": cid, "design_index": first_index + i, **overrides,
                         "case_json": canonical_json(simulation_inputs(case))})
        frame = pd.DataFrame(rows, columns=["case_id", "design_index", *names, "case_json"])
        for p in names:
            frame[p] = _column_frame_value(list(frame[p]))
        return frame


def design_space(cfg: SweepConfig, base_case: Mapping[str, Any], *,
                 model: type[BaseModel] = CaseConfig) -> DesignSpace:
    """Check the fixed overrides and every variable at its extremes; return the space.

    Raises
    ------
    InputError
        ``sweep.variables.<path>`` for an unknown path or a bound the case
        models reject, ``sweep.fixed.<path>`` / ``sweep.window_path`` likewise.
    """
    fixed = dict(cfg.fixed)
    if cfg.window_s is not None:
        fixed[cfg.window_path] = cfg.window_s
    names = list(cfg.variables)
    finish = _boundaries(cfg, names)
    base = apply_overrides(base_case, fixed, prefix="sweep.fixed")
    _check_window(cfg, base)
    if cfg.boundaries == "rig":
        # The variables address the operation form of the case; each case is
        # moved onto the rig section before it is validated, with the
        # variables at their first extreme (a base value a variable replaces,
        # such as a zero ROP, is no error).
        probe = apply_overrides(base, {p: _extremes(cfg.variables[p])[0] for p in names})
        for path, value in fixed.items():
            _validate_case(finish(apply_overrides(probe, {path: value}, "sweep.fixed")),
                           f"sweep.fixed.{path}", model, names)
        _validate_case(finish(probe), "sweep.rig", model, names)
    else:
        for path, value in fixed.items():
            trial = apply_overrides(base, {path: value}, "sweep.fixed")
            _validate_case(trial, f"sweep.fixed.{path}", model)
        base = probe = _validate_case(base, "sweep.fixed", model)

    # Check every variable at each of its extremes first: a bad path or an
    # out-of-range bound fails here, naming the variable, before any work.
    for path in names:
        for value in _extremes(cfg.variables[path]):
            trial = apply_overrides(probe, {path: value})
            _validate_case(finish(trial), f"sweep.variables.{path}", model)
    if model is CaseConfig:
        _check_bit_in_wells(cfg, finish(probe))
    return DesignSpace(cfg, names, base, finish, model)


def _check_bit_in_wells(cfg: SweepConfig, probe: Mapping[str, Any]) -> None:
    """The deepest bit of the design must lie within every well profile it can be paired
    with (``well.profile`` choices, or the base case's profile): a case whose bit starts
    below TD fails when it is simulated (:func:`drillfatigue.limits.check_bit_in_well`),
    so a design that samples one is refused before any work, naming the variable and
    the shallowest TD."""
    from drillfatigue.well import build_survey  # start-up: scipy, only when a real case is designed

    case = case_from_dict(dict(probe))
    spec = cfg.variables.get("operation.bit_md_m")
    if spec is not None and spec.choices is None:
        deepest = float(max(_extremes(spec)))
        field = "sweep.variables.operation.bit_md_m"
    else:
        deepest = float(case.operation.bit_md_m)
        field = ("sweep.fixed.operation.bit_md_m" if "operation.bit_md_m" in cfg.fixed
                 else "operation.bit_md_m")
    pspec = cfg.variables.get("well.profile")
    profiles = ([str(c) for c in pspec.choices] if pspec is not None and pspec.choices
                else [case.well.profile])
    tds = {name: float(build_survey(case.well, name).md_m[-1]) for name in profiles}
    name, td = min(tds.items(), key=lambda kv: kv[1])
    if deepest > td * (1.0 + 1e-12):
        raise InputError(field, f"{deepest:g} m is beyond the total depth {td:.6g} m of well "
                         f"profile {name!r}", f"bit_md_m <= {td:.6g} m (the shallowest TD of "
                         "the design's well profiles)")


def _check_window(cfg: SweepConfig, base: Mapping[str, Any]) -> None:
    """``sweep.window_s`` (each case's ``operation.duration_s``) must end after the record
    starts (``recording.start_s``, at its largest if it is a design variable): a case
    that records nothing completes without loads and its fatigue fails."""
    if cfg.window_s is None or cfg.window_path != "operation.duration_s":
        return
    spec = cfg.variables.get("recording.start_s")
    start = (max(_extremes(spec)) if spec is not None and spec.choices is None
             else float((base.get("recording") or {}).get("start_s", 0.0)))
    if cfg.window_s <= start:
        raise InputError("sweep.window_s", f"{cfg.window_s:g} s ends at or before the record "
                         f"starts (recording.start_s = {start:g} s): no case would record "
                         "anything", f"window_s > {start:g} s")


def design_cases(cfg: SweepConfig, base_case: Mapping[str, Any], *,
                 model: type[BaseModel] = CaseConfig) -> pd.DataFrame:
    """Sample the design and return the case table.

    With ``method: adaptive`` this is the initial space-filling design of
    ``sweep.adaptive.n_initial`` Sobol cases (the rounds that follow need
    simulations: :func:`drillfatigue.sweep.adaptive.adaptive_design`).

    Parameters
    ----------
    cfg : SweepConfig
        Design method, size, seed and variables.
    base_case : mapping
        The base case (case sections as a JSON-ready dict, see
        :func:`base_case_from_params`).
    model : pydantic model class
        Model every case must satisfy (default :class:`CaseConfig`; tests
        pass a small stand-in).

    Returns
    -------
    DataFrame
        One row per distinct case: ``case_id`` (str), ``design_index`` (row of
        the unit sample), one column per variable named by its dotted path
        (the field name carries the unit), and ``case_json`` (the full,
        validated case as canonical JSON, without the ``fatigue`` section,
        which the fatigue stage applies to every case).

    Raises
    ------
    InputError
        Before any sampling result is used: ``sweep.variables.<path>`` for an
        unknown path or a bound the case models reject, ``sweep.fixed.<path>``
        / ``sweep.window_path`` likewise.
    """
    space = design_space(cfg, base_case, model=model)
    unit = np.zeros((1, 0)) if not space.names else _unit_sample(cfg, space.dim)
    frame = space.cases(unit)
    if len(frame) < unit.shape[0]:
        warnings.warn(f"{unit.shape[0] - len(frame)} design rows repeat an earlier case and "
                      f"were merged; {len(frame)} distinct cases", UserWarning, stacklevel=2)
    frame.attrs["design"] = {"method": cfg.method, "seed": cfg.seed, "boundaries": cfg.boundaries,
                             "n_requested": cfg.n_cases, "n_sampled": int(unit.shape[0])}
    return frame


def _boundaries(cfg: SweepConfig, names: list[str]) -> Any:
    """The function that turns a case in operation form into the case simulated
    (``sweep.boundaries``); InputError for a rig section that sets what the
    operation inputs give."""
    if cfg.boundaries != "rig":
        return lambda case: case
    rig = dict(cfg.rig)
    for src, dst in RIG_PATHS.items():
        *parents, leaf = dst.split(".")[1:]
        node: Any = rig
        for name in parents:
            node = node.get(name) if isinstance(node, dict) else None
        if isinstance(node, dict) and leaf in node:
            raise InputError(f"sweep.{dst}", f"is set from {src} with boundaries rig",
                             f"{src} in the base case or as a design variable")
    mode = rig.get("block_mode", "autodriller")
    if mode not in ROP_TARGETS and "operation.rop_m_per_s" in names:
        raise InputError("sweep.variables.operation.rop_m_per_s",
                         f"the block has no ROP set-point or limit in block_mode {mode}",
                         f"sweep.rig.block_mode {' or '.join(ROP_TARGETS)}, "
                         "or no ROP design variable")
    if mode == "autodriller":
        ad = rig.get("autodriller") or {}
        if "rop_limit_m_per_s" in ad:
            raise InputError("sweep.rig.autodriller.rop_limit_m_per_s",
                             "is set from operation.rop_m_per_s with boundaries rig",
                             "operation.rop_m_per_s in the base case or as a design variable")
    return lambda case: rig_case(case, rig)


def write_cases(frame: pd.DataFrame, path: str | Path) -> Path:
    """Write the case table to Parquet atomically; return the path."""
    path = Path(path)
    with atomic_output(path) as tmp:
        frame.to_parquet(tmp, index=False)
    return path


def read_cases(path: str | Path) -> pd.DataFrame:
    """Read a case table written by :func:`write_cases`."""
    path = Path(path)
    if not path.is_file():
        raise InputError(str(path), "case table not found", "a cases.parquet from the design stage")
    frame = pd.read_parquet(path)
    missing = {"case_id", "case_json"} - set(frame.columns)
    if missing:
        raise InputError(str(path), f"not a case table, missing columns {sorted(missing)}",
                         "a cases.parquet from the design stage")
    return frame
