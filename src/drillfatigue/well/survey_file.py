"""Directional surveys as engineers have them: CSV in m or ft, WITSML 1.4.1.1 trajectories.

CSV (``.csv``, ``.txt``)
    A header row, optionally a units row below it (``ft, deg, deg, deg/100ft``),
    then one station per row. Columns are recognised by name, any order and
    case: measured depth (``MD``, ``Measured Depth``, ``MDepth``, ``Depth``),
    inclination (``Inc``, ``Incl``, ``Inclination``), azimuth (``Azi``, ``Azim``,
    ``Azimuth``, ``Azimuth True``, ``Dir``); optional true vertical depth
    (``TVD``) and dogleg severity (``DLS``, ``Dogleg``, ``Dogleg Severity``).
    The unit comes from the header (``MD (ft)``, ``MD [m]``, ``md_m``) or the
    units row; depths without a unit are an error unless ``depth_unit`` is
    given; angles without a unit are degrees. Other columns (``N/S``, ``E/W``,
    ``VS``, ``Build``, ``Turn``, ``TF``, ...) are ignored and reported.
WITSML (``.xml``)
    One 1.4.1.1 ``trajectory`` object (root ``trajectorys``): each
    ``trajectoryStation``'s ``md``, ``incl``, ``azi`` (and optional ``tvd``,
    ``dls``) with their ``uom`` attributes (``m``, ``ft``, ``ftUS``, ``dega``,
    ``rad``, ``dega/100ft``, ``dega/30m``, ``rad/m``).

Every depth and angle is converted once to SI (:mod:`drillfatigue.units`
factors through :data:`drillfatigue.io.headers.UNIT_SPELLINGS`) and the
positions are recomputed by minimum curvature
(:func:`drillfatigue.well.survey.minimum_curvature`).

Cross-checks
------------
A given dogleg severity and TVD must agree with the minimum-curvature
recomputation within what the file's printed precision allows; otherwise the
file is rejected naming the row and column (typically a wrong depth unit: a
survey in ft read as m has doglegs 3.28 times too large). Per station i the
tolerances are, with ``d_x`` the number of decimals printed in column x:

* dogleg: ``0.5 10^-d_dls + 2 10^-d_ang C / dMD_i + DLS_i 10^-d_md / dMD_i``
  (C = the dogleg's course length, 30 m or 100 ft): the cell's own rounding,
  the four rounded angles that enter the dogleg (each off by at most half a
  unit of their last decimal), and the rounded course length;
* TVD: ``0.5 10^-d_tvd (station and tie-in) + sum_k dMD_k (pi/180) 10^-d_ang
  + n 10^-d_md``: inclination rounding moves each interval's TVD by at most
  ``dMD sin(I) dI``, accumulated down the well.

The first station's dogleg is not checked (it is the tie-in). A dogleg unit of
deg/30 m and one of deg/100 ft differ by 1.6 % only: the check catches wrong
depth units, not a mix-up of these two.

References
----------
WITSML 1.4.1.1 data schema, ``obj_trajectory.xsd`` (Energistics, 2011).
"""

from __future__ import annotations

import csv
import math
import xml.etree.ElementTree as ET
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pandas as pd

from drillfatigue.errors import InputError
from drillfatigue.files import atomic_write_text
from drillfatigue.io.display import check_system
from drillfatigue.io.headers import field_text, si_from_text, split_header, unit_factor
from drillfatigue.limits import MD_MAX_M
from drillfatigue.well.survey import Survey, minimum_curvature, write_survey_csv

__all__ = ["SurveyImport", "load_survey", "read_survey", "survey_table", "twin_survey_table"]

#: Recognised survey column names (normalised) per role.
SURVEY_ALIASES: dict[str, tuple[str, ...]] = {
    "md": ("md", "measured depth", "meas depth", "mdepth", "depth", "dmea", "md m", "md ft"),
    "inc": ("inc", "incl", "inclination", "angle", "inc deg"),
    "azi": ("azi", "azim", "azimuth", "azimuth true", "azi true", "true azimuth", "azimuth grid",
            "azi grid", "grid azimuth", "dir", "direction"),
    "tvd": ("tvd", "true vertical depth"),
    "dls": ("dls", "dogleg", "dog leg", "dogleg severity", "dog leg severity"),
}
_ROLE_WORD = {"md": "measured depth", "inc": "inclination", "azi": "azimuth", "tvd": "TVD",
              "dls": "dogleg"}
_QUANTITY = {"md": "length", "tvd": "length", "inc": "angle", "azi": "angle", "dls": "dogleg"}


@dataclass(frozen=True)
class SurveyImport:
    """A survey read from a field file, with what the reader did.

    Attributes
    ----------
    survey : Survey
        Stations in SI with minimum-curvature positions (first station at
        north = east = 0, TVD = the file's first TVD or 0).
    units : dict
        Role (``md``, ``inc``, ``azi``, ``tvd``, ``dls``) -> unit read.
    ignored_columns : tuple of str
        Columns the reader did not use.
    max_dls_diff_deg_per_30m : float
        Largest |given - recomputed| dogleg (NaN when the file has none).
    max_tvd_diff_m : float
        Largest |given - recomputed| TVD (NaN when the file has none).
    source : str
        The file read.
    """

    survey: Survey
    units: dict[str, str]
    ignored_columns: tuple[str, ...] = ()
    max_dls_diff_deg_per_30m: float = float("nan")
    max_tvd_diff_m: float = float("nan")
    source: str = ""


def _decimals(cell: str) -> int:
    """Decimals printed in a number's text (``'12.50'`` -> 2; exponent forms -> 6)."""
    c = cell.strip().lower()
    if "e" in c:
        return 6
    return len(c.split(".", 1)[1]) if "." in c else 0


def _assemble(source: str, cells: dict[str, list[str]], unit_of: dict[str, str],
              rows: list[str], ignored: tuple[str, ...],
              label_of: dict[str, str]) -> SurveyImport:
    """Check and convert raw text columns (role -> cells) into a :class:`SurveyImport`.

    ``rows``: the location of each station for errors (``file:row``);
    ``label_of``: the file's name of each role's column (for errors).
    """
    n = len(rows)
    if n < 2:
        raise InputError(source, f"{n} station(s)", "at least 2 stations")
    vals: dict[str, np.ndarray] = {}
    dec: dict[str, np.ndarray] = {}
    for role, col in cells.items():
        unit_factor(_QUANTITY[role], unit_of[role], f"{source}:{label_of[role]}")
        # exact conversion of the written decimals: a survey exported in ft
        # (drillfatigue.io.headers.field_text) reads back to the same SI bits
        vals[role] = np.array([si_from_text(c, _QUANTITY[role], unit_of[role],
                                            f"{rows[i]}:{label_of[role]}")
                               for i, c in enumerate(col)])
        dec[role] = np.array([_decimals(c) for c in col])
    md, inc, azi = vals["md"], vals["inc"], vals["azi"]
    for i in range(n):
        if not 0.0 <= inc[i] <= 180.0:
            raise InputError(f"{rows[i]}:{label_of['inc']}", f"inclination {inc[i]:g} deg out "
                             "of range", f"0 <= {label_of['inc']} <= 180 (deg)")
        if not 0.0 <= azi[i] <= 360.0:
            raise InputError(f"{rows[i]}:{label_of['azi']}", f"azimuth {azi[i]:g} deg out of "
                             "range", f"0 <= {label_of['azi']} <= 360 (deg)")
        if not 0.0 <= md[i] <= MD_MAX_M:
            raise InputError(f"{rows[i]}:{label_of['md']}", f"MD {md[i]:.6g} m out of range",
                             f"0 <= md_m <= {MD_MAX_M:.0f} (the deepest wells are about 15 km)")
        if i and md[i] <= md[i - 1]:
            raise InputError(f"{rows[i]}:{label_of['md']}", f"MD {md[i]:g} m not greater than "
                             f"the previous {md[i - 1]:g} m", "strictly increasing measured depth")
    azi = np.where(azi >= 360.0, azi - 360.0, azi)
    tvd0 = float(vals["tvd"][0]) if "tvd" in vals else 0.0
    sv = minimum_curvature(md, np.radians(inc), np.radians(azi), (0.0, 0.0, tvd0))
    d_ang = np.minimum(dec["inc"], dec["azi"])
    # decimals of a row's angles and of the one before (both ends of the interval)
    d_ang_pair = np.minimum(d_ang[1:], d_ang[:-1])
    md_step_f = 10.0 ** -np.minimum(dec["md"][1:], dec["md"][:-1])
    md_unit = unit_factor("length", unit_of["md"], f"{source}:{label_of['md']}")
    dmd = np.diff(md)
    dls_diff = float("nan")
    if "dls" in vals:
        given = vals["dls"]
        calc = sv.dls_deg_per_30m
        fac = unit_factor("dogleg", unit_of["dls"], f"{source}:{label_of['dls']}")
        # in deg/30 m: the cell's rounding, the dogleg angle's (<= 2 10^-d_ang deg)
        # over the interval, the course length's
        tol = (0.5 * 10.0 ** -dec["dls"][1:] * fac
               + 2.0 * 10.0 ** -d_ang_pair * 30.0 / dmd
               + calc[1:] * md_step_f * md_unit / dmd + 1e-9)
        diff = np.abs(given[1:] - calc[1:])
        dls_diff = float(diff.max())
        bad = np.flatnonzero(diff > tol)
        if bad.size:
            i = int(bad[0]) + 1
            raise InputError(f"{rows[i]}:{label_of['dls']}",
                             f"dogleg {given[i] / fac:.4g} {unit_of['dls']} differs from the "
                             f"minimum-curvature {calc[i] / fac:.4g} {unit_of['dls']} "
                             f"(tolerance {tol[i - 1] / fac:.2g}); check the depth and dogleg "
                             "units", "a dogleg consistent with MD, inc, azi")
    tvd_diff = float("nan")
    if "tvd" in vals:
        given = vals["tvd"]
        calc = sv.pos_m[:, 2]
        tvd_unit = unit_factor("length", unit_of["tvd"], f"{source}:{label_of['tvd']}")
        acc = np.concatenate([[0.0], np.cumsum(dmd * math.radians(1.0) * 10.0 ** -d_ang_pair
                                               + md_step_f * md_unit)])
        tol = 0.5 * (10.0 ** -dec["tvd"] + 10.0 ** -dec["tvd"][0]) * tvd_unit + acc + 1e-9
        diff = np.abs(given - calc)
        tvd_diff = float(diff.max())
        bad = np.flatnonzero(diff > tol)
        if bad.size:
            i = int(bad[0])
            raise InputError(f"{rows[i]}:{label_of['tvd']}",
                             f"TVD {given[i] / tvd_unit:.6g} {unit_of['tvd']} differs from the "
                             f"minimum-curvature {calc[i] / tvd_unit:.6g} {unit_of['tvd']} "
                             f"(tolerance {tol[i] / tvd_unit:.2g}); check the depth units",
                             "a TVD consistent with MD, inc, azi")
    return SurveyImport(survey=sv, units=dict(unit_of), ignored_columns=ignored,
                        max_dls_diff_deg_per_30m=dls_diff, max_tvd_diff_m=tvd_diff,
                        source=source)


def _role_of(name: str) -> str | None:
    for role, names in SURVEY_ALIASES.items():
        if name in names:
            return role
    return None


def _load_csv(p: Path, depth_unit: str | None) -> SurveyImport:
    try:
        with p.open(newline="", encoding="utf-8-sig") as fh:
            rows = [r for r in csv.reader(fh)]
    except UnicodeDecodeError:
        raise InputError(str(p), "not a UTF-8 text file", "a CSV survey") from None
    rows = [r for r in rows if r and any(c.strip() for c in r)]
    if not rows:
        raise InputError(f"{p}:1", "empty survey file", "a header row, then one station per row")
    header = rows[0]
    first_data = 1
    units_row: list[str] | None = None
    if len(rows) > 1:
        def numeric(c: str) -> bool:
            try:
                float(c)
                return True
            except ValueError:
                return False
        if not any(numeric(c) for c in rows[1] if c.strip()):
            units_row, first_data = rows[1], 2
    col_of: dict[str, int] = {}
    unit_of: dict[str, str] = {}
    ignored = []
    for j, h in enumerate(header):
        name, unit = split_header(h)
        role = _role_of(name)
        if role is None:
            ignored.append(h.strip())
            continue
        if role in col_of:
            raise InputError(f"{p}:1", f"columns {header[col_of[role]].strip()!r} and "
                             f"{h.strip()!r} both give the {role}", "one column per quantity")
        col_of[role] = j
        if units_row is not None and j < len(units_row) and units_row[j].strip():
            unit = units_row[j].strip().strip("()[]")
        if unit is None:
            if role in ("md", "tvd"):
                if depth_unit is None:
                    raise InputError(f"{p}:1:{h.strip()}", "depth without a unit",
                                     "a unit in the header (MD (ft), md_m), a units row, or "
                                     "depth_unit: m|ft in the survey_file profile")
                unit = depth_unit
            elif role == "dls":
                raise InputError(f"{p}:1:{h.strip()}", "dogleg without a unit",
                                 "DLS (deg/100ft), DLS (deg/30m) or a units row")
            else:
                unit = "deg"
        unit_of[role] = unit
    for role in ("md", "inc", "azi"):
        if role not in col_of:
            raise InputError(f"{p}:1", f"no {_ROLE_WORD[role]} column",
                             "columns md_m, inc_deg, azi_deg, or field headers such as "
                             "MD (ft), Incl, Azim")
    cells: dict[str, list[str]] = {r: [] for r in col_of}
    where = []
    for r, row in enumerate(rows[first_data:], start=first_data + 1):
        if len(row) < len(header):
            raise InputError(f"{p}:{r}", f"{len(row)} cells", f"{len(header)} cells per row")
        if "dls" in col_of and not row[col_of["dls"]].strip() and not cells["md"]:
            row = list(row)
            row[col_of["dls"]] = "0"  # tie-in station without a dogleg
        for role, j in col_of.items():
            cells[role].append(row[j].strip())
        where.append(f"{p}:{r}")
    label_of = {role: header[j].strip() for role, j in col_of.items()}
    return _assemble(str(p), cells, unit_of, where, tuple(ignored), label_of)


def _local(tag: str) -> str:
    return tag.rsplit("}", 1)[-1]


def _load_witsml(p: Path) -> SurveyImport:
    try:
        root = ET.parse(p).getroot()
    except ET.ParseError as exc:
        raise InputError(str(p), f"not well-formed XML ({exc})", "a WITSML 1.4.1.1 trajectory "
                         "file") from None
    trajs = [e for e in root.iter() if _local(e.tag) == "trajectory"]
    if _local(root.tag) not in ("trajectorys", "trajectory") or not trajs:
        raise InputError(str(p), f"root element {_local(root.tag)!r} holds no trajectory",
                         "a WITSML 1.4.1.1 <trajectorys> with one <trajectory>")
    if len(trajs) > 1:
        raise InputError(str(p), f"{len(trajs)} trajectory objects", "one trajectory per file")
    version = root.get("version")
    if version is not None and not version.startswith("1.4"):
        raise InputError(str(p), f"WITSML version {version!r}", "1.4.1.1 (or another 1.4.x)")
    stations = [e for e in trajs[0] if _local(e.tag) == "trajectoryStation"]
    tags = {"md": "md", "inc": "incl", "azi": "azi", "tvd": "tvd", "dls": "dls"}
    cells: dict[str, list[str]] = {}
    unit_of: dict[str, str] = {}
    where = []
    for k, st in enumerate(stations):
        uid = st.get("uid") or str(k + 1)
        loc = f"{p}:trajectoryStation[{uid}]"
        children = {_local(c.tag): c for c in st}
        for role, tag in tags.items():
            el = children.get(tag)
            if el is None or not (el.text or "").strip():
                if role in ("md", "inc", "azi"):
                    raise InputError(f"{loc}:{tag}", "missing", "md, incl and azi in every "
                                     "trajectoryStation")
                if role == "dls" and k == 0 and "dls" in [_local(c.tag) for s in stations[1:2]
                                                          for c in s]:
                    cells.setdefault(role, []).append("0")
                    continue
                if role in cells:
                    raise InputError(f"{loc}:{tag}", "missing in this station only",
                                     f"{tag} in every station or in none")
                continue
            uom = el.get("uom")
            if not uom:
                raise InputError(f"{loc}:{tag}", "no uom attribute", "uom=\"m\", \"ft\", "
                                 "\"dega\", ...")
            if role in unit_of and unit_of[role] != uom:
                raise InputError(f"{loc}:{tag}", f"uom {uom!r} differs from {unit_of[role]!r} "
                                 "of the earlier stations", "one uom per quantity")
            unit_of[role] = uom
            if role not in cells and k > 0:
                raise InputError(f"{loc}:{tag}", "given from this station on only",
                                 f"{tag} in every station or in none")
            cells.setdefault(role, []).append((el.text or "").strip())
        where.append(loc)
    for role in ("tvd", "dls"):
        if role in cells and len(cells[role]) != len(where):
            raise InputError(f"{p}:{tags[role]}", "missing in some stations",
                             f"{tags[role]} in every station or in none")
    if not where:
        raise InputError(str(p), "no trajectoryStation", "at least 2 stations")
    return _assemble(str(p), cells, unit_of, where, (), {r: tags[r] for r in tags})


def load_survey(path: str | Path, depth_unit: str | None = None) -> SurveyImport:
    """Read a survey file (CSV in m or ft, or WITSML 1.4.1.1 trajectory XML).

    Parameters
    ----------
    path : path-like
        ``.csv``/``.txt`` or ``.xml``.
    depth_unit : str, optional
        Unit of depth columns whose header gives none (``m`` or ``ft``).

    Raises
    ------
    InputError
        Missing file or column, unknown unit, unparsable cell, MD not strictly
        increasing, angle out of range, dogleg or TVD inconsistent with the
        minimum-curvature recomputation (see the module docstring).
    """
    p = Path(path)
    if not p.is_file():
        raise InputError(str(p), "survey file not found", "an existing .csv or .xml file")
    if depth_unit is not None:
        unit_factor("length", depth_unit, "depth_unit")
    if p.suffix.lower() == ".xml":
        return _load_witsml(p)
    if p.suffix.lower() in (".csv", ".txt"):
        return _load_csv(p, depth_unit)
    raise InputError(str(p), f"unknown survey file type {p.suffix or '(none)'!r}",
                     ".csv, .txt (CSV) or .xml (WITSML trajectory)")


def read_survey(path: str | Path, depth_unit: str | None = None) -> Survey:
    """The :class:`~drillfatigue.well.survey.Survey` of a survey file (:func:`load_survey`)."""
    return load_survey(path, depth_unit).survey


def survey_table(survey: Survey) -> pd.DataFrame:
    """The twin's survey table (``md_m``, ``inc_deg``, ``dls_deg_per_30m``) of a survey."""
    return pd.DataFrame({"md_m": survey.md_m, "inc_deg": np.degrees(survey.inc_rad),
                         "dls_deg_per_30m": survey.dls_deg_per_30m})


def twin_survey_table(path: str | Path, depth_unit: str | None = None) -> pd.DataFrame:
    """The twin's survey table from a file: a full survey, or a geometry table.

    A file with an azimuth (any CSV :func:`load_survey` reads, or WITSML) is
    read as a survey and its doglegs recomputed; a CSV without azimuth is the
    twin's own geometry table (MD, dogleg and optionally inclination, in any
    unit the headers name), converted to ``md_m``, ``dls_deg_per_30m``,
    ``inc_deg``.
    """
    p = Path(path)
    if p.suffix.lower() == ".xml" or not p.is_file():
        return survey_table(read_survey(p, depth_unit))
    try:
        head = pd.read_csv(p, nrows=0, encoding="utf-8-sig")
    except (pd.errors.ParserError, pd.errors.EmptyDataError, UnicodeDecodeError) as exc:
        raise InputError(str(p), f"unreadable CSV ({type(exc).__name__})",
                         "a comma-separated table with a header") from None
    roles = {_role_of(split_header(str(h))[0]) for h in head.columns}
    if "azi" in roles:
        return survey_table(read_survey(p, depth_unit))
    table = pd.read_csv(p, encoding="utf-8-sig")
    out: dict[str, np.ndarray] = {}
    target = {"md": "md_m", "dls": "dls_deg_per_30m", "inc": "inc_deg"}
    for h in table.columns:
        name, unit = split_header(str(h))
        role = _role_of(name)
        if role not in target:
            raise InputError(f"{p}:1:{h}", "unknown column in a survey table",
                             "MD, DLS and Inc (with units), or a survey with azimuth")
        if unit is None:
            if role == "inc":
                unit = "deg"
            elif role == "md" and depth_unit is not None:
                unit = depth_unit
            else:
                raise InputError(f"{p}:1:{h}", "no unit in the header",
                                 "e.g. md_m, MD (ft), DLS (deg/100ft)")
        v = pd.to_numeric(table[h], errors="coerce").to_numpy(dtype=np.float64)
        if not np.all(np.isfinite(v)):
            r = int(np.argmax(~np.isfinite(v))) + 2
            raise InputError(f"{p}:{r}:{h}", "non-numeric or empty cell", "a finite number")
        out[target[role]] = v * unit_factor(_QUANTITY[role], unit, f"{p}:1:{h}")
    return pd.DataFrame(out)


#: Header of a survey written in field units (read back by :func:`load_survey`).
FIELD_SURVEY_HEADER = ("MD (ft)", "Inc (deg)", "Azi (deg)", "TVD (ft)", "DLS (deg/100ft)")


def write_survey(survey: Survey, path: str | Path, unit_system: str = "si") -> None:
    """Write a survey CSV atomically: SI (``md_m,inc_deg,azi_deg``) or field units.

    The field file has MD and TVD in ft and the dogleg in deg/100 ft, written
    with :func:`drillfatigue.io.headers.field_text`, so :func:`load_survey`
    gives back the same SI stations bit for bit (and its dogleg and TVD
    checks pass exactly).
    """
    if check_system(unit_system) == "si":
        write_survey_csv(survey, path)
        return
    azi = np.degrees(survey.azi_rad) % 360.0
    azi = np.where(azi >= 360.0, 0.0, azi)
    lines = [",".join(FIELD_SURVEY_HEADER)]
    for i in range(survey.n):
        lines.append(",".join([
            field_text(float(survey.md_m[i]), "length", "ft"),
            repr(float(np.degrees(survey.inc_rad[i]))), repr(float(azi[i])),
            field_text(float(survey.pos_m[i, 2]), "length", "ft"),
            field_text(float(survey.dls_deg_per_30m[i]), "dogleg", "deg/100ft")]))
    atomic_write_text(path, "\n".join(lines) + "\n")
