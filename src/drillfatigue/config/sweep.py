"""``sweep`` section of params.yaml: case design and the parallel sweep engine.

A design variable is named by its dotted path in the case configuration
(``operation.rpm``, ``friction.mu_dynamic``, ``string.components[0].od_m``)
and given either a numeric range (``low``/``high``, optionally ``scale: log``
and ``kind: integer``) or a list of ``choices`` (categorical)::

    sweep:
      method: sobol
      n_cases: 32
      seed: 20240601
      variables:
        operation.rpm: {low: 60, high: 180}
        bit.amplitude_m: {low: 1.0e-4, high: 2.0e-3, scale: log}
        bit.lobes: {low: 1, high: 3, kind: integer}
        well.profile: {choices: [1, 2, 3]}

Whether a path exists and whether the bounds are physically allowed is
checked against the case models when the design is built
(:func:`drillfatigue.sweep.design.design_cases`), before any work starts,
with errors named ``sweep.variables.<path>``.
"""

from __future__ import annotations

import math
import re
from typing import Any, Literal

from pydantic import Field, field_validator, model_validator

from drillfatigue.config.base import StrictModel

_ADDRESS = re.compile(r"^(tcp|tls|ucx|inproc)://[^\s/]+(:\d{1,5})?$")
_PATH = re.compile(r"^[A-Za-z_][A-Za-z0-9_]*(\[\d+\])*(\.[A-Za-z_][A-Za-z0-9_]*(\[\d+\])*)+$")

SCHEDULERS = ("serial", "processes", "local-cluster")
FATIGUE_CRITERIA = ("matake", "findley", "fatemi_socie", "uniaxial")


def check_path(path: str) -> str:
    """Check the syntax of a dotted configuration path; return it unchanged."""
    if not isinstance(path, str) or not _PATH.match(path):
        raise ValueError(
            f"bad configuration path {path!r} (allowed: a dotted path such as "
            "operation.rpm or string.components[0].od_m)"
        )
    return path


class VariableSpec(StrictModel):
    """One design variable: a numeric range or a list of categorical choices.

    Attributes
    ----------
    low, high : float, optional
        Bounds of a numeric variable, in the unit of the target field (the
        field name says it). Both inclusive; ``low < high`` (``low <= high``
        for integers).
    scale : {'linear', 'log'}
        ``log`` samples uniformly in log(value): use it for ranges spanning
        decades (needs ``low > 0``).
    kind : {'float', 'integer'}
        ``integer`` samples whole numbers in ``[low, high]`` with equal weight.
    choices : list, optional
        Categorical values (numbers, strings, booleans or mappings), sampled
        with equal weight. Exclusive with ``low``/``high``.
    """

    low: float | None = None
    high: float | None = None
    scale: Literal["linear", "log"] = "linear"
    kind: Literal["float", "integer"] = "float"
    choices: list[Any] | None = None

    @model_validator(mode="after")
    def _check(self) -> VariableSpec:
        if self.choices is not None:
            if self.low is not None or self.high is not None:
                raise ValueError("give either choices or low/high, not both "
                                 "(allowed: {choices: [...]} or {low: ..., high: ...})")
            if len(self.choices) == 0:
                raise ValueError("choices is empty (allowed: a non-empty list)")
            return self
        if self.low is None or self.high is None:
            raise ValueError("a numeric variable needs both low and high "
                             "(allowed: {low: ..., high: ...} or {choices: [...]})")
        if not (math.isfinite(self.low) and math.isfinite(self.high)):
            raise ValueError("bounds must be finite (allowed: finite numbers)")
        if self.kind == "integer":
            if self.low != int(self.low) or self.high != int(self.high):
                raise ValueError(f"integer bounds must be whole numbers, got "
                                 f"[{self.low}, {self.high}] (allowed: whole numbers)")
            if self.low > self.high:
                raise ValueError(f"low > high: [{self.low}, {self.high}] (allowed: low <= high)")
        elif not self.low < self.high:
            raise ValueError(f"low >= high: [{self.low}, {self.high}] (allowed: low < high)")
        if self.scale == "log" and self.low <= 0.0:
            raise ValueError(f"log scale needs low > 0, got {self.low} (allowed: 0 < low < high)")
        return self


class WindowConfig(StrictModel):
    """How long each case is simulated (``sweep.window``; ``docs/pipeline.md``).

    Attributes
    ----------
    mode : {'fixed', 'converged'}
        ``fixed``: every case runs ``sweep.window_s``. ``converged``: a case
        first runs ``sweep.window_s``; while the damage rate of its governing
        location (largest uniaxial damage rate of any joint and location over
        the recorded window) changes by more than ``tol_rel`` between the
        first two thirds of the recorded window and all of it, the case is
        simulated again with the window times ``growth``, up to ``max_s``.
        The window used and the last change are recorded per case.
    tol_rel : float
        Largest relative change of the running damage rate over the last
        third of the recorded window for a converged case, 0 < tol_rel <= 10.
    growth : float
        Factor on the window at each extension, 1 < growth <= 10.
    max_s : float
        Longest window, s (a case that has not converged by then keeps it and
        is recorded as not converged).
    """

    mode: Literal["fixed", "converged"] = "fixed"
    tol_rel: float = Field(0.25, gt=0.0, le=10.0)
    growth: float = Field(2.0, gt=1.0, le=10.0)
    max_s: float = Field(36.0, gt=0.0, le=1.0e5)


class AdaptiveConfig(StrictModel):
    """Adaptive design (``sweep.method: adaptive``, block ``sweep.adaptive``; ``docs/pipeline.md``).

    ``n_initial`` scrambled Sobol cases (seed ``sweep.seed``) are simulated
    and evaluated first; then, round after round, an ensemble of
    ``n_members`` gradient-boosting models fitted on bootstrap resamples of
    the finished cases scores a seeded Sobol pool of ``candidates`` cases by
    its disagreement on the governing damage rate per component type, and
    ``batch_size`` cases are added: the most disputed candidate, then greedily
    the one farthest (in the unit design space) from every case already
    chosen, among the ``pool_factor * batch_size`` most disputed. Rounds run
    until ``sweep.n_cases`` cases.

    Attributes
    ----------
    n_initial : int
        Space-filling cases before the first round (a power of two: rounded up
        with a warning), 2 ... n_cases.
    batch_size : int
        Cases added per round, 1 ... candidates.
    candidates : int
        Size of the Sobol candidate pool of each round (power of two: rounded
        up), >= batch_size.
    seed : int
        Seed of the candidate pools (round ``r`` draws with ``seed + r``) and
        of the bootstrap.
    n_members : int
        Bootstrap members of the acquisition ensemble, 2 ... 64.
    pool_factor : float
        Diversity rule: the batch is chosen among the ``pool_factor *
        batch_size`` most disputed candidates, 1 ... 64.
    cache_dir : str, optional
        Run and fatigue folders of the designed cases (``sweep/``,
        ``fatigue/``), keyed by case id: an interrupted design resumes from
        the cases already done. None: ``adaptive/`` beside the case table
        (``sweep.cases_path``).
    acquisition : {'governing', 'rows', 'mix'}
        What the ensemble disagrees on: ``governing`` the governing rate per
        case and component type (inputs: the design point); ``rows`` every
        row's rate (inputs: the surrogate's features; a candidate's rows built
        from its inputs), summed over the case's rows; ``mix`` a share
        ``space_filling_share`` of each batch by max-min distance alone, the
        rest as ``rows``.
    space_filling_share : float
        Share of each batch taken space-filling with ``mix`` (rounded half
        up to whole cases), 0 ... 1.
    """

    n_initial: int = Field(16, ge=2, le=1_000_000)
    batch_size: int = Field(8, ge=1, le=100_000)
    candidates: int = Field(1024, ge=1, le=1_000_000)
    seed: int = Field(20240602, ge=0, le=2**63 - 1)
    n_members: int = Field(8, ge=2, le=64)
    pool_factor: float = Field(4.0, ge=1.0, le=64.0)
    cache_dir: str | None = Field(None, min_length=1)
    acquisition: Literal["governing", "rows", "mix"] = "governing"
    space_filling_share: float = Field(0.5, ge=0.0, le=1.0)

    @model_validator(mode="after")
    def _check(self) -> AdaptiveConfig:
        if self.candidates < self.batch_size:
            raise ValueError(f"candidates: {self.candidates} candidates cannot fill a batch of "
                             f"{self.batch_size} (allowed: candidates >= batch_size)")
        return self


class SweepConfig(StrictModel):
    """Settings of the ``sweep`` section (case design and the sweep engine).

    Attributes
    ----------
    method : {'sobol', 'lhs', 'adaptive'}
        Scrambled Sobol sequence (default; ``n_cases`` is rounded UP to the
        next power of two, with a warning, because Sobol balance holds only
        for 2^m points) or Latin hypercube (exactly ``n_cases``), both from
        ``scipy.stats.qmc`` and seeded; or ``adaptive`` (exactly ``n_cases``):
        a Sobol start, then batches where an ensemble disagrees most
        (:class:`AdaptiveConfig`, block :attr:`adaptive`; the design stage
        simulates and evaluates the cases it chooses).
    adaptive : AdaptiveConfig
        Settings of ``method: adaptive`` (ignored by the other methods).
    n_cases : int
        Requested number of cases, 1 ... 1,000,000.
    seed : int
        Seed of the design (same seed → same cases, same ids).
    variables : dict[str, VariableSpec]
        Design variables by dotted case path. ``fatigue.*`` paths are not
        allowed: fatigue settings apply to all cases in the fatigue stage.
    fixed : dict[str, Any]
        Overrides applied to every case before the variables (e.g. a shorter
        window ``operation.duration_s: 20``).
    window_s : float, optional
        Simulated window per case, s (0 < window_s <= 1e5); when given it is
        written to ``window_path`` of every case. Choose it long enough for
        stable damage statistics: at least ~20 revolutions of the slowest rpm
        and several stick-slip periods (documented in the dataset card).
    window_path : str
        Case path that holds the simulated duration.
    window : WindowConfig
        Fixed window, or one chosen per case by the convergence of its
        governing damage rate (then ``window_s`` is the first window).
    scheduler : str
        ``processes`` (local process pool, default), ``serial`` (in-process,
        for debugging), ``local-cluster`` (Dask ``LocalCluster``) or a Dask
        scheduler address ``tcp://host:port``.
    n_workers : int
        Parallel workers (processes) for ``processes`` and ``local-cluster``.
    max_retries : int
        Extra attempts for a failed case (0 ... 10).
    failure_threshold : float
        The sweep fails (exit code 1) if more than this fraction of cases
        finally fails, 0 ... 1.
    fatigue_criteria : list of str
        Criteria evaluated per case in the fatigue stage (each a column
        ``damage_rate_per_h_<criterion>`` of the dataset); each costs one
        evaluation, the critical-plane ones most.
    api_rp7g : bool
        Add the API RP7G (Lubinski) damage rate of each pipe body beside them.
    cases_path, sweep_dir, fatigue_dir, dataset_dir : str
        Output locations of the design, simulate, fatigue and dataset stages.
    boundaries : {'operation', 'rig'}
        What drives each case's string. ``operation`` (the library default):
        the ``operation`` section's prescribed ROP and lobed bit motion.
        ``rig`` (params.yaml's setting): every case gets the rig section
        :attr:`rig` (``docs/rig.md``), and the operation inputs the rig takes
        over are moved onto it (:data:`drillfatigue.sweep.design.RIG_PATHS`):
        ``operation.rop_m_per_s`` becomes the block's ROP set-point
        ``rig.rop_set_m_per_s`` (``block_mode: rop``: the block lowers at it,
        the bit cuts what the bit law lets it, the WOB is the result), the
        lobes go to ``rig.rock``. Design variables and the dataset keep the
        ``operation.*`` names, so the surrogate's features and the query
        vocabulary mean the same set-point.
    rig : dict
        The rig section of every case with ``boundaries: rig`` (without the
        set-point, which comes from ``operation.rop_m_per_s``); validated with
        each case.
    """

    method: Literal["sobol", "lhs", "adaptive"] = "sobol"
    adaptive: AdaptiveConfig = Field(default_factory=AdaptiveConfig)
    n_cases: int = Field(default=32, ge=1, le=1_000_000)
    seed: int = Field(default=20240601, ge=0, le=2**63 - 1)
    variables: dict[str, VariableSpec] = Field(default_factory=dict)
    fixed: dict[str, Any] = Field(default_factory=dict)
    window_s: float | None = Field(default=None, gt=0.0, le=1.0e5)
    window_path: str = "operation.duration_s"
    window: WindowConfig = Field(default_factory=WindowConfig)
    scheduler: str = "processes"
    n_workers: int = Field(default=2, ge=1, le=1024)
    max_retries: int = Field(default=1, ge=0, le=10)
    failure_threshold: float = Field(default=0.1, ge=0.0, le=1.0)
    fatigue_criteria: list[str] = Field(default_factory=lambda: ["matake", "uniaxial"],
                                        min_length=1)
    api_rp7g: bool = True
    cases_path: str = "data/design/cases.parquet"
    sweep_dir: str = "data/sweep"
    fatigue_dir: str = "data/fatigue"
    dataset_dir: str = "data/dataset"
    boundaries: Literal["operation", "rig"] = "operation"
    rig: dict[str, Any] = Field(default_factory=lambda: {"block_mode": "rop"})

    @model_validator(mode="after")
    def _check_adaptive(self) -> SweepConfig:
        if self.method == "adaptive" and self.adaptive.n_initial > self.n_cases:
            raise ValueError(f"adaptive.n_initial: {self.adaptive.n_initial} initial cases exceed "
                             f"n_cases = {self.n_cases} (allowed: 2 <= n_initial <= n_cases)")
        return self

    @model_validator(mode="after")
    def _check_window(self) -> SweepConfig:
        if self.window.mode == "converged":
            if self.window_s is None:
                raise ValueError("window_s: window.mode converged starts from window_s "
                                 "(allowed: a first window 0 < window_s <= window.max_s)")
            if self.window.max_s < self.window_s:
                raise ValueError(f"window.max_s: {self.window.max_s} s is shorter than the first "
                                 f"window window_s = {self.window_s} s (allowed: max_s >= window_s)")
        return self

    @field_validator("variables", "fixed")
    @classmethod
    def _check_paths(cls, value: dict[str, Any]) -> dict[str, Any]:
        for path in value:
            check_path(path)
            if path.split(".")[0].split("[")[0] == "fatigue":
                raise ValueError(f"{path}: fatigue settings cannot vary per case "
                                 "(allowed: paths outside the fatigue section)")
        return value

    @field_validator("fatigue_criteria")
    @classmethod
    def _check_criteria(cls, value: list[str]) -> list[str]:
        for name in value:
            if name not in FATIGUE_CRITERIA:
                raise ValueError(f"unknown fatigue criterion {name!r} "
                                 f"(allowed: {', '.join(FATIGUE_CRITERIA)})")
        if len(set(value)) != len(value):
            raise ValueError("a criterion is listed twice (allowed: distinct criteria)")
        return value

    @field_validator("window_path")
    @classmethod
    def _check_window_path(cls, value: str) -> str:
        return check_path(value)

    @field_validator("scheduler")
    @classmethod
    def _check_scheduler(cls, value: str) -> str:
        if value in SCHEDULERS or _ADDRESS.match(value):
            return value
        raise ValueError(f"unknown scheduler {value!r} (allowed: serial, processes, "
                         "local-cluster or a Dask address tcp://host:port)")
