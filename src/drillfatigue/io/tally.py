"""String tallies in field units: descriptions, API grades, the catalogue, CSV tallies.

A one-line description defines a component, e.g. ``5in 19.5ppf G-105 NC50``
(drill pipe), ``5in HWDP NC50``, ``6-3/4in x 2-13/16in DC NC50`` (collar):
sizes in inches (``5in``, ``5"``, ``5-1/2in``, ``6.625in``), nominal weight
(``19.5ppf``, ``19.50#``, ``19.5 lb/ft``), grade (``E-75``, ``X95``,
``G-105``, ``S135``), connection (``NC50``, ``5-1/2FH``, ``6-5/8REG``) and a
kind word (``DP``/``drill pipe``, ``HWDP``/``HW``, ``DC``/``collar``,
``stab``, ``bit``, ``MWD``/``motor``/``jar``/``sub``/``X-O``). The tube,
tool-joint and collar dimensions come from :mod:`drillfatigue.io.catalogue`.

Tally CSV
---------
One row per item, **from the bit up**, columns recognised by name (any case,
units in the header or in a units row below it):

``Description`` (the one-line description), ``Type``, ``Name``/``Serial``,
``Joints``/``Count``/``Qty`` (number of joints, default 1), ``Length``
(total length of the item) or ``Joint Length`` (per joint; ft or m),
``OD``, ``ID``, ``TJ OD``, ``TJ ID`` (in or mm), ``TJ Length`` (combined
pin and box length per joint, in), ``Blade OD`` and ``Blade Length`` (in or mm,
stabilizers: ``OD`` is then the body's), ``Weight`` (lb/ft or kg/m),
``Grade``, ``Connection``, ``Segments``.

Rules:

* A dimension in a column overrides the catalogue's; one missing from both is
  an error naming the row and column.
* ``Weight`` of drill pipe is the nominal weight (it selects the catalogue
  entry; the mass comes from the geometry and the tool joints, as in
  :class:`~drillfatigue.config.string.ComponentConfig`); for every other kind
  it is the linear mass in air. ``Adjusted Weight`` is always the linear mass.
* The tool-joint length fraction is ``TJ Length / joint length`` when given,
  else 0.05 for drill pipe and HWDP (the project's default) and 0 otherwise.
* ``Segments`` defaults to ``ceil(length / 9 m)`` (the default string's
  segment length, docs/model.md#bodies).
* An ``OD`` or ``TJ OD`` outside 25 mm to 1 m (after its unit: the physical
  bound of :mod:`drillfatigue.limits`) is refused naming the row: ``6.75``
  under a unit row that says ``mm`` is an OD in inches, not a 6.75 mm collar.
"""

from __future__ import annotations

import csv
import io
import math
import re
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from drillfatigue import units
from drillfatigue.config.base import validate
from drillfatigue.config.string import ComponentConfig, StringConfig
from drillfatigue.errors import InputError
from drillfatigue.io.catalogue import API_GRADES, COLLARS, DRILL_PIPE, HWDP, TOOL_JOINTS
from drillfatigue.io.headers import normalise_unit, split_header, unit_factor
from drillfatigue.limits import check_value

__all__ = ["ComponentSpec", "describe", "load_tally", "load_tally_text", "parse_description",
           "normalise_grade"]

DEFAULT_SEGMENT_LENGTH_M = 9.0
DEFAULT_TJ_FRACTION = 0.05

_SIZE = re.compile(r"(?<![\d.])(\d+(?:\.\d+)?)(?:[- ](\d+)/(\d+))?\s*(?:in\b|inch\b|\"|'')",
                   re.I)
_WEIGHT = re.compile(r"(\d+(?:\.\d+)?)\s*(?:ppf|#|lbs?/ft|lbm/ft)", re.I)
_GRADE = re.compile(r"\b([EXGS])\s*-?\s*(75|95|105|135)\b", re.I)
_CONN = re.compile(r"\b(NC\s*\d{2})\b|\b(\d(?:-\d/\d)?)\s*(FH|IF|REG)\b", re.I)
#: Tally kinds the string model has no type for, and the type simulated in their place.
UNMODELLED_KINDS = {"motor": "sub"}
_KINDS: tuple[tuple[str, str], ...] = (
    (r"\b(hwdp|hw|heavy[- ]?weight)\b", "hwdp"),
    (r"\b(dc|collars?|drill collars?|nmdc)\b", "collar"),
    (r"\b(stab|stabili[sz]er|nb stab|string stab)\b", "stabilizer"),
    (r"\b(bit|pdc|tricone)\b", "bit"),
    (r"\b(mwd|lwd)\b", "mwd"),
    (r"\b(jar|jars)\b", "jar"),
    (r"\b(motor|pdm|mud motor|turbine|rss|rotary steerable)\b", "motor"),
    (r"\b(sub|x-?o|crossover|shock sub|float sub)\b", "sub"),
    (r"\b(dp|drill ?pipe|pipe)\b", "drill_pipe"),
)


def normalise_grade(text: str, where: str) -> str:
    """``'g105'``, ``'G-105'``, ``'G 105'`` -> ``'G-105'``; InputError otherwise."""
    m = _GRADE.fullmatch(text.strip())
    if m is None:
        raise InputError(where, f"unknown grade {text.strip()!r}", ", ".join(API_GRADES))
    g = f"{m.group(1).upper()}-{m.group(2)}"
    if g not in API_GRADES:
        raise InputError(where, f"unknown grade {text.strip()!r}", ", ".join(API_GRADES))
    return g


def _size_in(m: re.Match[str]) -> float:
    v = float(m.group(1))
    if m.group(2):
        v += float(m.group(2)) / float(m.group(3))
    return v


def _normalise_connection(m: re.Match[str]) -> str:
    if m.group(1):
        return m.group(1).upper().replace(" ", "")
    return f"{m.group(2)}{m.group(3).upper()}"


@dataclass
class ComponentSpec:
    """What a description (and a tally row) says about a component, field units.

    ``None`` where nothing was said; :func:`describe` fills from the catalogue.
    """

    type: str = "drill_pipe"
    od_in: float | None = None
    id_in: float | None = None
    nominal_weight_lb_per_ft: float | None = None
    linear_weight_lb_per_ft: float | None = None
    grade: str | None = None
    connection: str | None = None
    tj_od_in: float | None = None
    tj_id_in: float | None = None
    references: tuple[str, ...] = ()
    #: what the tally calls it where the string model has no such type: a mud motor or
    #: rotary-steerable tool is simulated as a sub of its size (its power section or
    #: steering is not modelled), and the twin lists it as not covered
    kind: str | None = None


def parse_description(text: str, where: str = "description") -> ComponentSpec:
    """Read the kind, sizes, weight, grade and connection of a one-line description."""
    t = text.strip()
    if not t:
        raise InputError(where, "empty description", "e.g. '5in 19.5ppf G-105 NC50'")
    spec = ComponentSpec()
    low = t.lower()
    for pattern, kind in _KINDS:
        if re.search(pattern, low):
            spec.type = kind
            break
    if spec.type in UNMODELLED_KINDS:
        spec.kind, spec.type = spec.type, UNMODELLED_KINDS[spec.type]
    conn = _CONN.search(t)
    rest = t
    if conn is not None:
        spec.connection = _normalise_connection(conn)
        rest = t[:conn.start()] + " " + t[conn.end():]
    sizes = [_size_in(m) for m in _SIZE.finditer(rest)]
    if sizes:
        spec.od_in = sizes[0]
    if len(sizes) > 1:
        spec.id_in = sizes[1]
    w = _WEIGHT.search(rest)
    if w is not None:
        spec.nominal_weight_lb_per_ft = float(w.group(1))
    g = _GRADE.search(rest)
    if g is not None:
        spec.grade = normalise_grade(g.group(0), where)
    return spec


def _close(a: float, b: float) -> bool:
    return abs(a - b) < 0.01


def describe(spec: ComponentSpec, where: str = "description") -> ComponentSpec:
    """Fill a spec's missing dimensions from the catalogue (a new, complete spec)."""
    s = ComponentSpec(**{k: getattr(spec, k) for k in spec.__dataclass_fields__})
    refs: list[str] = list(s.references)
    if s.od_in is None:
        raise InputError(where, "no outside diameter", "a size such as 5in, 6-3/4in or an OD "
                         "column")
    if s.type == "drill_pipe":
        body = None
        if s.nominal_weight_lb_per_ft is not None:
            body = next((b for (od, w), b in DRILL_PIPE.items()
                         if _close(od, s.od_in) and _close(w, s.nominal_weight_lb_per_ft)), None)
        if body is not None:
            if s.id_in is None:
                s.id_in = body.id_in
            refs.append(body.reference)
            if s.connection is not None and (s.tj_od_in is None or s.tj_id_in is None):
                if s.grade is None:
                    raise InputError(where, "a tool joint needs the grade",
                                     ", ".join(API_GRADES))
                tj = TOOL_JOINTS.get((body.od_in, body.nominal_weight_lb_per_ft, s.grade,
                                      s.connection))
                if tj is None:
                    known = sorted({f"{od:g}in {w:g}ppf {g} {c}"
                                    for (od, w, g, c) in TOOL_JOINTS})
                    raise InputError(where, f"no catalogue tool joint for {s.od_in:g}in "
                                     f"{s.nominal_weight_lb_per_ft:g}ppf {s.grade} "
                                     f"{s.connection}", "TJ OD and TJ ID columns, or one of: "
                                     + "; ".join(known))
                s.tj_od_in = s.tj_od_in if s.tj_od_in is not None else tj.od_in
                s.tj_id_in = s.tj_id_in if s.tj_id_in is not None else tj.id_in
                refs.append(tj.reference)
        elif s.id_in is None:
            sizes = ", ".join(f"{od:g}in {w:g}ppf" for od, w in DRILL_PIPE)
            raise InputError(where, f"drill pipe {s.od_in:g}in "
                             f"{s.nominal_weight_lb_per_ft or '?'}ppf not in the catalogue",
                             f"an ID column, or one of: {sizes}")
    elif s.type == "hwdp":
        hw = next((h for od, h in HWDP.items() if _close(od, s.od_in)), None)
        if hw is not None:
            s.id_in = s.id_in if s.id_in is not None else hw.id_in
            if s.linear_weight_lb_per_ft is None and s.nominal_weight_lb_per_ft is None:
                s.linear_weight_lb_per_ft = hw.adjusted_weight_lb_per_ft
            s.connection = s.connection or hw.tool_joint.connection
            s.tj_od_in = s.tj_od_in if s.tj_od_in is not None else hw.tool_joint.od_in
            s.tj_id_in = s.tj_id_in if s.tj_id_in is not None else hw.tool_joint.id_in
            refs.append(hw.reference)
        elif s.id_in is None:
            raise InputError(where, f"HWDP {s.od_in:g}in not in the catalogue",
                             "an ID column, or " + ", ".join(f"{od:g}in" for od in HWDP))
    elif s.type == "collar":
        cands = [c for (od, _), c in COLLARS.items() if _close(od, s.od_in)
                 and (s.id_in is None or _close(c.id_in, s.id_in))]
        if len(cands) == 1:
            c = cands[0]
            s.id_in = s.id_in if s.id_in is not None else c.id_in
            s.connection = s.connection or c.connection
            refs.append(c.reference)
        elif s.id_in is None:
            raise InputError(where, f"collar {s.od_in:g}in: bore not given and not in the "
                             "catalogue", "an ID (e.g. '6-3/4in x 2-13/16in DC') or one of "
                             + ", ".join(f"{od:g}x{i:g}in" for od, i in COLLARS))
    if s.id_in is None:
        s.id_in = 0.0 if s.type == "bit" else None
    if s.id_in is None:
        raise InputError(where, f"no inside diameter for a {s.type}", "an ID column")
    if s.type != "drill_pipe" and s.nominal_weight_lb_per_ft is not None \
            and s.linear_weight_lb_per_ft is None:
        s.linear_weight_lb_per_ft = s.nominal_weight_lb_per_ft
    s.references = tuple(dict.fromkeys(refs))
    return s


def component_config(spec: ComponentSpec, length_m: float, name: str = "",
                     n_segments: int | None = None, tj_length_fraction: float | None = None,
                     field: str = "tally", extra: dict[str, float] | None = None
                     ) -> ComponentConfig:
    """A :class:`ComponentConfig` (SI) from a complete spec and a length in metres;
    ``extra``: further fields in SI (a stabilizer's ``blade_od_m``, ``blade_length_m``)."""
    if spec.od_in is None or spec.id_in is None:
        raise InputError(field, f"{spec.type}: outside and inside diameters are needed",
                         "OD and ID columns, or a catalogue size")
    od_m = spec.od_in * units.INCH_M
    data: dict[str, Any] = {
        "type": spec.type, "name": name, "od_m": od_m, "id_m": spec.id_in * units.INCH_M,
        "length_m": length_m,
        "n_segments": n_segments if n_segments is not None
        else max(1, math.ceil(length_m / DEFAULT_SEGMENT_LENGTH_M - 1e-9)),
    }
    if spec.linear_weight_lb_per_ft is not None:
        data["linear_mass_kg_per_m"] = spec.linear_weight_lb_per_ft * units.LB_PER_FT_KG_PER_M
    if spec.tj_od_in is not None:
        data["tool_joint_od_m"] = spec.tj_od_in * units.INCH_M
        if spec.tj_id_in is not None:
            data["tool_joint_id_m"] = spec.tj_id_in * units.INCH_M
        frac = tj_length_fraction
        if frac is None:
            frac = DEFAULT_TJ_FRACTION if spec.type in ("drill_pipe", "hwdp") else 0.0
        data["tool_joint_length_fraction"] = frac
    if spec.grade is not None:
        data["material"] = {"grade": spec.grade}
    data.update(extra or {})
    return validate(ComponentConfig, data, field)


#: Tally column names (normalised) per role.
TALLY_ALIASES: dict[str, tuple[str, ...]] = {
    "description": ("description", "desc", "item", "component", "size"),
    "type": ("type", "kind", "component type"),
    "name": ("name", "serial", "serial number", "id number", "sn"),
    "joints": ("joints", "jts", "count", "qty", "quantity", "number of joints", "no"),
    "length": ("length", "total length", "len", "item length"),
    "joint_length": ("joint length", "length per joint", "jt length"),
    "od": ("od", "outside diameter", "body od", "tube od"),
    "id": ("id", "inside diameter", "bore", "body id", "tube id"),
    "tj_od": ("tj od", "tool joint od", "connection od", "tool joint outside diameter"),
    "tj_id": ("tj id", "tool joint id", "connection id", "tool joint inside diameter"),
    "tj_length": ("tj length", "tool joint length"),
    "blade_od": ("blade od", "stab od", "gauge od", "blade outside diameter"),
    "blade_length": ("blade length",),
    "weight": ("weight", "nominal weight", "wt", "ppf", "unit weight"),
    "adjusted_weight": ("adjusted weight", "adj weight", "air weight", "linear weight",
                        "weight in air"),
    "grade": ("grade", "steel grade"),
    "connection": ("connection", "conn", "thread"),
    "segments": ("segments", "n segments", "n_segments"),
}
_TALLY_UNITS = {"length": ("length", "ft"), "joint_length": ("length", "ft"),
                "od": ("length", "in"), "id": ("length", "in"), "tj_od": ("length", "in"),
                "tj_id": ("length", "in"), "tj_length": ("length", "in"),
                "blade_od": ("length", "in"), "blade_length": ("length", "in")}
#: Diameter columns checked against the physical bounds of :mod:`drillfatigue.limits`
#: in SI: an OD below 25 mm or above 1 m is refused whatever its unit.
_DIAMETER_BOUNDS = {"od": "od_m", "tj_od": "tool_joint_od_m", "blade_od": "od_m"}
_TYPE_WORDS = {"drill_pipe": "drill_pipe", "dp": "drill_pipe", "drill pipe": "drill_pipe",
               "hwdp": "hwdp", "hw": "hwdp", "collar": "collar", "dc": "collar",
               "stabilizer": "stabilizer", "stab": "stabilizer", "bit": "bit", "sub": "sub",
               "mwd": "mwd", "lwd": "mwd", "motor": "motor", "jar": "jar"}


@dataclass(frozen=True)
class TallyImport:
    """A string read from a tally: the config and where each row's numbers came from."""

    string: StringConfig
    references: tuple[tuple[str, ...], ...]
    ignored_columns: tuple[str, ...] = ()
    #: per component: what the tally calls it (the string type, or an unmodelled kind
    #: such as ``motor``, :data:`UNMODELLED_KINDS`)
    kinds: tuple[str, ...] = ()


def load_tally(path: str | Path) -> TallyImport:
    """Read a tally CSV (rows from the bit up) into a :class:`StringConfig`.

    Raises
    ------
    InputError
        Missing file, unknown unit, unparsable cell, a dimension neither in a
        column nor in the catalogue, or a component the string model rejects;
        the field names ``file:row:column``.
    """
    p = Path(path)
    if not p.is_file():
        raise InputError(str(p), "tally file not found", "an existing CSV file")
    try:
        text = p.read_text(encoding="utf-8-sig")
    except UnicodeDecodeError:
        raise InputError(str(p), "not a UTF-8 text file", "a CSV tally") from None
    return load_tally_text(text, str(p))


def load_tally_text(text: str, name: str = "tally") -> TallyImport:
    """:func:`load_tally` of the CSV text ``text``; ``name`` stands for the file in errors."""
    p = Path(name)
    rows = [r for r in csv.reader(io.StringIO(text)) if r and any(c.strip() for c in r)]
    if len(rows) < 2:
        raise InputError(str(p), "no items", "a header row, then one row per item")
    header = rows[0]
    first = 1
    if not any(re.fullmatch(r"\s*-?\d+(\.\d+)?\s*", c) for c in rows[1]) and \
            any(split_header(c)[0] in ("ft", "m", "in", "mm", "lb/ft", "kg/m") for c in rows[1]):
        first = 2
    col: dict[str, int] = {}
    unit: dict[str, str | None] = {}
    ignored = []
    for j, h in enumerate(header):
        name, u = split_header(h)
        role = next((r for r, names in TALLY_ALIASES.items() if name in names), None)
        if role is None:
            ignored.append(h.strip())
            continue
        if role in col:
            raise InputError(f"{p}:1", f"columns {header[col[role]].strip()!r} and "
                             f"{h.strip()!r} mean the same", "one column per quantity")
        col[role] = j
        if first == 2 and j < len(rows[1]) and rows[1][j].strip():
            u = rows[1][j].strip().strip("()[]")
        unit[role] = u
    if "description" not in col and "od" not in col:
        raise InputError(f"{p}:1", "neither a description nor an OD column",
                         "Description (e.g. '5in 19.5ppf G-105 NC50') or OD, ID, ... columns")
    if "length" not in col and "joint_length" not in col:
        raise InputError(f"{p}:1", "no length column", "Length (ft) or Joint Length (ft)")
    comps = []
    refs = []
    kinds: list[str] = []
    for r, row in enumerate(rows[first:], start=first + 1):
        where = f"{p}:{r}"

        def cell(role: str, row: list[str] = row) -> str:
            j = col.get(role)
            return row[j].strip() if j is not None and j < len(row) else ""

        def num(role: str, where: str = where) -> float | None:
            c = cell(role)
            if not c:
                return None
            try:
                v = float(c)
            except ValueError:
                raise InputError(f"{where}:{header[col[role]].strip()}", f"not a number: {c!r}",
                                 "a finite number") from None
            if not math.isfinite(v) or v < 0:
                raise InputError(f"{where}:{header[col[role]].strip()}", f"{c!r}",
                                 "a finite number >= 0")
            return v

        def si(role: str, where: str = where) -> float | None:
            v = num(role)
            if v is None:
                return None
            quantity, default = _TALLY_UNITS[role]
            u = unit[role]
            if u is None:
                raise InputError(f"{where}:{header[col[role]].strip()}", "no unit in the header",
                                 f"e.g. '{header[col[role]].strip()} ({default})'")
            factor = unit_factor(quantity, u, f"{p}:1:{header[col[role]].strip()}")
            if role in _DIAMETER_BOUNDS:  # 6.75 under 'mm' is no 6.75 mm collar
                try:
                    check_value(f"{where}:{header[col[role]].strip()}", _DIAMETER_BOUNDS[role],
                                v * factor, f"{role}_{normalise_unit(u)}", factor)
                except InputError as exc:
                    raise InputError(exc.field, f"{exc.problem}: no drill-string item is that "
                                     "size (a value in another unit than the header's?)",
                                     exc.allowed) from None
            return v * factor

        desc = cell("description")
        spec = parse_description(desc, f"{where}:description") if desc else ComponentSpec()
        t = cell("type").lower()
        if t:
            if t not in _TYPE_WORDS:
                raise InputError(f"{where}:type", f"unknown type {t!r}", ", ".join(_TYPE_WORDS))
            spec.type = _TYPE_WORDS[t]
            if spec.type in UNMODELLED_KINDS:
                spec.kind, spec.type = spec.type, UNMODELLED_KINDS[spec.type]
        for role, attr in (("od", "od_in"), ("id", "id_in"), ("tj_od", "tj_od_in"),
                           ("tj_id", "tj_id_in")):
            v = si(role)
            if v is not None:
                setattr(spec, attr, v / units.INCH_M)
        for role, attr in (("weight", "nominal_weight_lb_per_ft"),
                           ("adjusted_weight", "linear_weight_lb_per_ft")):
            v = num(role)
            if v is not None:
                u = (unit.get(role) or "lb/ft").replace(" ", "").lower()
                if u in ("kg/m", "kgm"):
                    v = v / units.LB_PER_FT_KG_PER_M
                elif u not in ("lb/ft", "ppf", "lbm/ft", "lbs/ft", "#/ft"):
                    raise InputError(f"{p}:1:{header[col[role]].strip()}",
                                     f"unit {u!r} is not a linear weight unit", "lb/ft, kg/m")
                setattr(spec, attr, v)
        if cell("grade"):
            spec.grade = normalise_grade(cell("grade"), f"{where}:grade")
        if cell("connection"):
            spec.connection = cell("connection").upper().replace(" ", "")
        spec = describe(spec, where)
        joints = num("joints")
        n_joints = 1 if joints is None else joints
        if joints is not None and (n_joints < 1 or n_joints != int(n_joints)):
            raise InputError(f"{where}:joints", f"{cell('joints')!r}", "a whole number >= 1")
        total = si("length")
        per_joint = si("joint_length")
        if total is None and per_joint is None:
            raise InputError(f"{where}:length", "no length", "a length > 0")
        length_m = total if total is not None else n_joints * per_joint  # type: ignore[operator]
        if total is not None and per_joint is not None and \
                abs(total - n_joints * per_joint) > 0.01 * total:
            raise InputError(f"{where}:length", f"{total:.2f} m is not joints x joint length "
                             f"{n_joints * per_joint:.2f} m", "consistent lengths (1 %)")
        tj_len = si("tj_length")
        frac = None
        if tj_len is not None:
            joint_m = per_joint if per_joint is not None else length_m / n_joints
            frac = tj_len / joint_m
        seg = num("segments")
        if seg is not None and (seg < 1 or seg != int(seg)):
            raise InputError(f"{where}:segments", f"{cell('segments')!r}", "a whole number >= 1")
        name = cell("name") or desc
        blades = {k: v for k, v in (("blade_od_m", si("blade_od")),
                                    ("blade_length_m", si("blade_length"))) if v is not None}
        if blades and spec.type != "stabilizer":
            raise InputError(f"{where}:blade od", f"a blade on a {spec.type}",
                             "blade OD and length on stabilizer rows only")
        comps.append(component_config(spec, length_m, name=name,
                                      n_segments=None if seg is None else int(seg),
                                      tj_length_fraction=frac, field=where, extra=blades))
        refs.append(spec.references)
        kinds.append(spec.kind or spec.type)
    string = validate(StringConfig, {"components": [c.model_dump() for c in comps]}, str(p))
    return TallyImport(string=string, references=tuple(refs), ignored_columns=tuple(ignored),
                       kinds=tuple(kinds))
