"""Request and response models of the HTTP API (pydantic; they make the OpenAPI schema).

Feature values use the user vocabulary of :mod:`drillfatigue.io.names`
(``rpm``, ``wob_kN``, ``rop_m_per_h``, ``mud_density_sg``, ``component_type``,
...), as the CLI's flags and CSV columns do. The string, the well and the
well-plan candidates are the CLI's own configuration models
(:class:`~drillfatigue.config.StringConfig`,
:class:`~drillfatigue.config.WellConfig`,
:class:`~drillfatigue.studies.plan.CandidateFile`). The ledger's tables come
as the columns and rows of the DataFrames its query functions return
(:mod:`drillfatigue.ledger.queries`), SI with the unit in each column name.
"""

from __future__ import annotations

from typing import Annotated, Any

from pydantic import BaseModel, BeforeValidator, ConfigDict, Field

from drillfatigue.config import StringConfig, WellConfig
from drillfatigue.studies.plan import CandidateFile
from drillfatigue.surrogate.window import MAX_NODES, MIN_NODES



def _not_a_boolean(value: Any) -> Any:
    """Refuse a JSON ``true``/``false`` where a number is expected (pydantic reads it as 1/0)."""
    if isinstance(value, bool):
        raise ValueError("a JSON boolean is not a number")
    return value


#: a feature value: a number in the unit its name carries, or a category name (never a
#: JSON boolean: true is not rpm 1)
Value = Annotated[float | str, BeforeValidator(_not_a_boolean)]
#: a number (never a JSON boolean)
Number = Annotated[float, BeforeValidator(_not_a_boolean)]
#: one output cell: numbers (None for an infinite life), flags, texts
Cell = float | bool | str | None


class Request(BaseModel):
    """Base of the request bodies: unknown keys are rejected."""

    model_config = ConfigDict(extra="forbid")

    model: str | None = Field(default=None, description="model name (GET /v1/models); default: the "
                              "first one the service was started with")


class Answer(BaseModel):
    """Which model answered."""

    model: str = Field(description="model name")
    generation: int = Field(description="how many times this model was loaded (1 at start, "
                            "+1 per reload)")
    criterion: str = Field(description="fatigue criterion the model predicts")
    coverage: float = Field(description="calibrated coverage of the intervals")


class ErrorResponse(BaseModel):
    """A refused request: one line naming the field, the problem and the allowed values."""

    detail: str = Field(description="'field: problem (allowed: ...)'")
    field: str | None = None
    problem: str | None = None
    allowed: str | None = None


# -- query ------------------------------------------------------------------
class QueryRequest(Request):
    """Operating conditions to predict, one mapping of user names per row."""

    rows: list[dict[str, Value]] = Field(
        min_length=1, description="one condition per row, e.g. {\"rpm\": 120, \"wob_kN\": 80, "
        "\"rop_m_per_h\": 20, ..., \"component_type\": \"collar\"}",
        examples=[[{"rpm": 120, "wob_kN": 80, "rop_m_per_h": 20}]])


class QueryResponse(Answer):
    """The columns of ``drillfatigue query --csv``: the inputs, then the predictions."""

    columns: list[str]
    rows: list[dict[str, Cell]]


# -- twin replay ---------------------------------------------------------------
class LogInput(BaseModel):
    """An operating log as the file's text."""

    model_config = ConfigDict(extra="forbid")

    format: str = Field(default="csv", description="log format (GET /v1/model lists them)")
    text: str = Field(min_length=1, description="the log file's content")


class ReplayRequest(Request):
    """An operating log and the string (and optionally the well) it was drilled with."""

    log: LogInput
    components: list[dict[str, Value]] | None = Field(
        default=None,
        description="component list rows: serial, s_from_bit_m, component_type, location")
    components_csv: str | None = Field(default=None, description="the component list as CSV text")
    string: StringConfig | None = Field(
        default=None, description="a string section: every segment's body and connection "
        "is tracked")
    tally_csv: str | None = Field(default=None, description="a string tally as CSV text, "
                                  "from the bit up (drillfatigue.io.tally): every item is "
                                  "tracked, those the model does not cover listed as such")
    survey: list[dict[str, Number]] | None = Field(
        default=None, description="survey rows: md_m, dls_deg_per_30m (and inc_deg)")
    well: WellConfig | None = Field(default=None, description="a well section, instead of survey")
    constants: dict[str, Value] = Field(default_factory=dict,
                                        description="features constant over the log, user "
                                        "names (mu_static, mud_density_sg, ...)")
    retire_at_damage: float = Field(default=0.5, gt=0.0, le=1.0, description="retire a component "
                                    "whose upper-bound damage reaches this")
    retire_within_h: float | None = Field(default=None, gt=0.0, description="also retire one whose "
                                          "lower-bound remaining life is shorter (h)")


class RetireEntry(BaseModel):
    serial: str
    action: str = Field(description="retire, inspect (time out of the model's domain) or "
                        "not covered (an item the model does not cover)")
    s_from_bit_m: float
    damage: float | None
    damage_upper: float | None
    remaining_life_h_lower: float | None
    reason: str


class NotCovered(BaseModel):
    item: str
    reason: str


class ExampleResponse(BaseModel):
    """The field example, as the replay request takes it."""

    log: LogInput
    tally_csv: str
    survey: list[dict[str, float]]
    constants: dict[str, float]
    description: str


class ReplayResponse(Answer):
    duration_h: float
    n_locations: int
    n_locations_covered: int
    n_locations_answered: int
    max_damage_in_domain: float | None = Field(description="largest damage accumulated in the "
                                               "model's domain; null: none was in domain")
    max_damage_serial: str | None
    max_damage_s_from_bit_m: float | None
    ood_location_hours: float = Field(description="sum over covered locations of their hours "
                                      "out of domain (location-hours, not a duration)")
    max_ood_time_h: float = Field(description="longest time one location spent out of domain")
    n_locations_some_time_ood: int
    not_covered: list[NotCovered]
    last_bit_md_m: float = Field(description="the bit's measured depth at the log's end, m")
    ignored_log_channels: list[str]
    columns: list[str]
    components: list[dict[str, Cell]] = Field(description="one row per component, columns "
                                              "of components_damage.csv")
    retire: list[RetireEntry] = Field(description="components to retire, most damaged first")


# -- plan ranking -----------------------------------------------------------------
class PlanRankRequest(Request):
    """Candidate well plans: the candidates file as an object or as YAML text."""

    candidates: CandidateFile | None = None
    candidates_yaml: str | None = Field(default=None, description="a candidates file's YAML text")


class PlanRankResponse(Answer):
    best: str
    window_s: float
    columns: list[str]
    rows: list[dict[str, Cell]] = Field(description="best first, columns of ranking.csv")


# -- operating window -------------------------------------------------------------
class AxisSpec(BaseModel):
    model_config = ConfigDict(extra="forbid")

    name: str = Field(description="numeric feature, user name (rpm, wob_kN, rop_m_per_h, ...)")
    start: Number
    stop: Number
    n: int = Field(default=21, ge=MIN_NODES, le=MAX_NODES, description="nodes, ends included")


class WindowRequest(Request):
    """Grid of two operating parameters at one location and depth, the rest fixed."""

    x: AxisSpec = Field(examples=[{"name": "rpm", "start": 40, "stop": 200, "n": 33}])
    y: AxisSpec = Field(examples=[{"name": "wob_kN", "start": 20, "stop": 200, "n": 31}])
    fixed: dict[str, Value] = Field(description="every other feature, user names: md_m, "
                                    "s_from_bit_m, component_type, location, ...")
    survey: list[dict[str, Number]] | None = Field(
        default=None, description="survey rows (md_m, dls_deg_per_30m, inc_deg): the hole geometry "
        "at md_m and at the bit instead of fixed values")


class AxisValues(BaseModel):
    name: str
    values: list[float]


class WindowResponse(Answer):
    x: AxisValues
    y: AxisValues
    life_h: list[list[float | None]] = Field(description="[i_y][i_x], hours; null: infinite")
    life_h_lower: list[list[float | None]]
    life_h_upper: list[list[float | None]]
    ood: list[list[bool]]
    ood_fraction: float
    best_in_domain: dict[str, float] | None
    fixed: dict[str, Any]


# -- models -------------------------------------------------------------------------
class FeatureInfo(BaseModel):
    column: str = Field(description="SI column of the training data")
    names: list[str] = Field(description="accepted user names (first: the short SI one)")
    min: float | None = Field(default=None, description="training minimum, SI")
    max: float | None = Field(default=None, description="training maximum, SI")
    levels: list[str] | None = Field(default=None, description="categories seen in training")


class ModelCard(Answer):
    path: str
    loaded_at_utc: str
    target: str
    n_calibration: int | None
    features: list[FeatureInfo]
    categorical: list[FeatureInfo]
    training: dict[str, Any]
    split: dict[str, int] = Field(description="number of cases per part of the split")
    architecture: dict[str, Any]
    metrics: dict[str, Any] | None = Field(default=None, description="metrics.json of the evaluate "
                                           "stage, when next to the model folder")
    log_formats: list[str]
    limits: dict[str, int]


class ModelSummary(BaseModel):
    name: str
    generation: int
    criterion: str
    loaded_at_utc: str


class ModelsResponse(BaseModel):
    default: str
    models: list[ModelSummary]


class ReloadRequest(BaseModel):
    model_config = ConfigDict(extra="forbid")

    model: str | None = Field(default=None, description="model to reload; default: all")


class ReloadResponse(BaseModel):
    reloaded: list[ModelSummary]


class HealthResponse(BaseModel):
    status: str
    models: dict[str, int] = Field(description="model name -> generation")
    ledger: str | None = Field(default=None, description="back-end of the ledger served "
                               "(sqlite, postgresql); null: none")


# -- fatigue ledger -------------------------------------------------------------------
#: one cell of a ledger table: counts stay integers, NaN and infinities are null
LedgerCell = bool | int | float | str | None


class LedgerLog(BaseModel):
    """A log chunk as the file's text, read as ``drillfatigue ledger ingest`` reads files."""

    model_config = ConfigDict(extra="forbid")

    format: str = Field(default="csv", description="csv, las (LAS 2.0) or witsml "
                        "(WITSML 1.4.1.1 log XML)")
    text: str = Field(min_length=1, description="the chunk's content: a time channel, the bit "
                      "depth, RPM (or the run's constant), WOB ... with units in the headers")


class LedgerIngestRequest(BaseModel):
    """One chunk of an open run's log; ingested exactly once (docs/ledger.md)."""

    model_config = ConfigDict(extra="forbid")

    run: str = Field(min_length=1, description="an open run (GET /v1/ledger/runs)")
    log: LedgerLog
    source: str = Field(default="upload", min_length=1, max_length=200,
                        description="what the chunk is (a file name, a feed and its time "
                        "range): recorded with it, and named in its errors")


class LedgerIngestResponse(BaseModel):
    """What the chunk did (the line ``drillfatigue ledger ingest`` prints for it)."""

    run: str
    source: str
    status: str = Field(description="ingested, duplicate (this content was ingested before) "
                        "or nothing new (every sample at or before the run's last one)")
    seq: int | None = Field(description="the run's chunk number it was recorded as (null: "
                            "nothing new)")
    n_rows: int
    n_new_rows: int = Field(description="samples after the run's last ingested one, counted")
    t_first_s: float
    t_last_s: float
    line: str


class LedgerTable(BaseModel):
    columns: list[str]
    rows: list[dict[str, LedgerCell]]


class LedgerInfo(BaseModel):
    """The ledger this server opened (``drillfatigue serve --ledger``)."""

    backend: str = Field(description="sqlite or postgresql")
    database: str = Field(description="file path, or URL without the password")
    schema_revision: str | None
    joints: int
    runs: int
    open_runs: int
    chunks: int
    inspections: int


class LedgerJointsResponse(LedgerTable):
    """The inventory (``drillfatigue ledger joints``): least remaining life first."""

    units: str


class JointHistoryResponse(BaseModel):
    """One joint over its runs (``drillfatigue ledger history SERIAL``)."""

    serial: str
    component_type: str
    units: str
    runs: LedgerTable = Field(description="per run and location: position from the bit, "
                              "damage with its interval, hours, revolutions, time out of domain")
    events: LedgerTable = Field(description="serial corrections and swaps, with the reason")
    inspections: LedgerTable


class RetireRulesOut(BaseModel):
    retire_at: float
    inspect_at: float
    reinspect_after: float
    downgraded_retire_at: float
    retire_results: list[str]


class LedgerRetireResponse(BaseModel):
    """Joints to retire and to inspect under the rules (``drillfatigue ledger retire``)."""

    rules: RetireRulesOut
    units: str
    columns: list[str]
    retire: list[dict[str, LedgerCell]]
    inspect: list[dict[str, LedgerCell]]
