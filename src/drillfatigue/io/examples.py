"""Synthetic field files: a realistic rig day, its survey and string, in field units.

:func:`write_field_examples` writes the files of ``data/examples/field/``
(regenerate with ``python data/examples/make_field_examples.py``). No field
data: every number comes from the simple rig model below (seeded noise).

The day, sampled every 60 s (1441 rows, 24 h from 6000 ft hole depth):

* 0-7 h drilling: ROP about 60 ft/h, 120 rpm, WOB about 22 klbf, with a
  connection every 93 ft stand (2 min picking up and circulating off bottom,
  4 min in slips with pumps and rotary off, 2 min back to bottom);
* 7-8.5 h off-bottom circulation (bottoms up): bit 15 ft off bottom, 80 rpm,
  reciprocating 30 ft every 10 min;
* 8.5-14.5 h a wiper trip to 3000 ft and back: 3 min per stand moving, 2 min
  in slips, no rotation, pumps off;
* then drilling again to the end of the day.

Hook load = block weight + buoyed string weight x (1 + drag) - WOB, with
drag +8 % pulling out, -8 % running in; torque rises with WOB; standpipe
pressure and flow follow the pumps. Two short dropouts (null values: surface
RPM 2 min, standpipe pressure 3 min) and one row recorded twice exercise the
readers' fill rules.
"""

from __future__ import annotations

import math
import tempfile
from pathlib import Path
from xml.sax.saxutils import escape

import numpy as np
import pandas as pd

from drillfatigue import units
from drillfatigue.files import atomic_write_text
from drillfatigue.well.survey_file import twin_survey_table
from drillfatigue.well.survey import minimum_curvature

NULL = -999.25
START = "2026-03-14T00:00:00+00:00"
STEP_S = 60.0
_BLOCK_KLBF = 45.0
_BF = 0.85  # buoyancy factor, 10.5 ppg mud
_STAND_FT = 93.0
_BHA_FT = 340.0
#: hole depth at midnight and the depth the wiper trip pulls back to, ft
_START_FT = 1900.0
_TRIP_TO_FT = 1000.0

#: LAS mnemonic -> (unit, decimals, description) of the time log.
LOG_CURVES: dict[str, tuple[str, int, str]] = {
    "TIME": ("s", 0, "elapsed time"),
    "BITDEP": ("ft", 2, "bit depth"),
    "DMEA": ("ft", 2, "hole depth"),
    "HKLD": ("klbf", 2, "hook load"),
    "SWOB": ("klbf", 2, "surface weight on bit"),
    "SURF_RPM": ("rpm", 1, "surface rotary speed"),
    "STOR": ("kft.lbf", 2, "surface torque"),
    "ROP": ("ft/h", 2, "rate of penetration"),
    "SPPA": ("psi", 0, "standpipe pressure"),
    "TFLO": ("gpm", 0, "flow rate in"),
    "BPOS": ("ft", 2, "block position"),
}


def _string_weight_klbf(bit_ft: np.ndarray) -> np.ndarray:
    """Buoyed weight of 340 ft of BHA (80 lb/ft) and drill pipe (22 lb/ft) above the bit."""
    bha = np.minimum(bit_ft, _BHA_FT) * 80.0
    dp = np.maximum(bit_ft - _BHA_FT, 0.0) * 22.0
    return (bha + dp) * _BF / 1000.0


def synthetic_day(seed: int = 11) -> pd.DataFrame:
    """The rig day in field units, columns as :data:`LOG_CURVES` (NaN = null)."""
    rng = np.random.default_rng(seed)
    t = np.arange(0.0, 24 * 3600 + STEP_S / 2, STEP_S)
    n = t.size
    bit = np.zeros(n)
    hole = np.zeros(n)
    rpm = np.zeros(n)
    wob = np.zeros(n)
    rop = np.zeros(n)
    flow = np.zeros(n)
    drag = np.zeros(n)
    hole_ft = _START_FT
    since_conn = 40.0  # ft drilled in the current stand
    phase_left = 0
    phase = "drill"
    trip_depth = 0.0
    for i in range(n):
        h = t[i] / 3600.0
        if 7.0 <= h < 8.5:
            k = int((t[i] - 7 * 3600) // 600)
            off = 15.0 + (30.0 if k % 2 else 0.0) * ((t[i] % 600) / 600.0)
            bit[i], rpm[i], flow[i] = hole_ft - off, 80.0, 600.0
        elif 8.5 <= h < 14.5:
            tt = t[i] - 8.5 * 3600
            half = 3 * 3600
            stands = (hole_ft - _TRIP_TO_FT) / _STAND_FT
            per_stand = 300.0  # 3 min moving + 2 min slips
            if tt < half:
                k, r = divmod(tt, per_stand)
                moved = min(k * _STAND_FT + min(r / 180.0, 1.0) * _STAND_FT,
                            stands * _STAND_FT)
                bit[i], drag[i] = hole_ft - 15.0 - moved, 0.08 if r < 180 else 0.0
            else:
                k, r = divmod(tt - half, per_stand)
                moved = min(k * _STAND_FT + min(r / 180.0, 1.0) * _STAND_FT,
                            stands * _STAND_FT - 15.0)
                bit[i], drag[i] = _TRIP_TO_FT + moved, -0.08 if r < 180 else 0.0
            trip_depth = bit[i]
        else:
            if phase == "drill" and since_conn >= _STAND_FT:
                phase, phase_left, since_conn = "conn", 8, 0.0
            if phase == "conn":
                step = 8 - phase_left
                bit[i] = hole_ft - (10.0 if step in (0, 1, 6, 7) else 30.0)
                if step in (0, 1, 6, 7):
                    rpm[i], flow[i] = 40.0, 600.0
                phase_left -= 1
                if phase_left == 0:
                    phase = "drill"
            elif h >= 14.5 and trip_depth and hole_ft - trip_depth > 1.0:
                bit[i] = min(hole_ft, trip_depth + 40.0)  # washing down the last stand
                rpm[i], flow[i] = 40.0, 600.0
                trip_depth = bit[i]
            else:
                r_fth = max(10.0, (30.0 if h < 7 else 25.0) + rng.normal(0.0, 3.0))
                hole_ft += r_fth * STEP_S / 3600.0
                since_conn += r_fth * STEP_S / 3600.0
                bit[i], rop[i], flow[i] = hole_ft, r_fth, 650.0
                rpm[i] = 120.0 + rng.normal(0.0, 2.0)
                wob[i] = max(0.0, 22.0 + rng.normal(0.0, 1.5))
        hole[i] = hole_ft
    weight = _string_weight_klbf(bit)
    hkld = _BLOCK_KLBF + weight * (1.0 + drag) - wob
    slips = (rpm == 0) & (flow == 0) & (np.abs(np.gradient(bit)) < 1e-9)
    hkld = np.where(slips, _BLOCK_KLBF, hkld) + rng.normal(0.0, 0.3, n)
    torque = np.where(rpm > 0, 6.0 + 0.004 * bit / 10.0 + 0.12 * wob, 0.0)
    torque = np.where(rpm > 0, torque + rng.normal(0.0, 0.2, n), 0.0)
    spp = np.where(flow > 0, 2400.0 + 0.05 * bit / 10.0 + 40.0 * wob / 22.0, 0.0)
    spp = np.where(flow > 0, spp + rng.normal(0.0, 15.0, n), 0.0)
    bpos = 5.0 + np.mod(-bit, _STAND_FT)
    frame = pd.DataFrame({"TIME": t, "BITDEP": bit, "DMEA": hole, "HKLD": hkld, "SWOB": wob,
                          "SURF_RPM": rpm, "STOR": torque, "ROP": rop, "SPPA": spp,
                          "TFLO": flow, "BPOS": bpos})
    for name, (_, dec, _) in LOG_CURVES.items():
        frame[name] = frame[name].round(dec)
    frame.loc[180:181, "SURF_RPM"] = np.nan  # 2 min dropout while drilling
    frame.loc[600:602, "SPPA"] = np.nan  # 3 min dropout
    dup = frame.iloc[[300]]
    return pd.concat([frame.iloc[:301], dup, frame.iloc[301:]], ignore_index=True)


def _fmt(v: float, dec: int) -> str:
    return "" if not math.isfinite(v) else f"{v:.{dec}f}"


def las_text(frame: pd.DataFrame, curves: dict[str, tuple[str, int, str]],
             index_desc: str = "elapsed time") -> str:
    """LAS 2.0 text (unwrapped, null -999.25) of ``frame`` with ``curves``' units."""
    idx = next(iter(curves))
    first, last = frame[idx].iloc[0], frame[idx].iloc[-1]
    step = frame[idx].diff().iloc[1:]
    step_v = float(step.iloc[0]) if step.nunique() == 1 else 0.0
    u0 = curves[idx][0]
    lines = ["~VERSION INFORMATION",
             " VERS.                 2.0 : CWLS LOG ASCII STANDARD - VERSION 2.0",
             " WRAP.                  NO : ONE LINE PER STEP",
             "~WELL INFORMATION",
             f" STRT.{u0:<8} {first:>12g} : START",
             f" STOP.{u0:<8} {last:>12g} : STOP",
             f" STEP.{u0:<8} {step_v:>12g} : STEP",
             f" NULL.         {NULL:>12g} : NULL VALUE",
             " COMP.   DRILLFATIGUE EXAMPLES : COMPANY",
             " WELL.   SYNTHETIC-1 : WELL",
             " FLD .   NONE : FIELD",
             " LOC .   NONE : LOCATION",
             " SRVC.   SYNTHETIC RIG : SERVICE COMPANY",
             f" DATE.   {START[:10]} : LOG DATE",
             f" UWI .   SYNTHETIC-1 : UNIQUE WELL ID ({index_desc} from {START})",
             "~CURVE INFORMATION"]
    for name, (unit, _, desc) in curves.items():
        lines.append(f" {name:<9}.{unit:<8} : {desc}")
    lines.append("~A " + " ".join(f"{n:>10}" for n in curves))
    cols = [(frame[n].to_numpy(dtype=float), d) for n, (_, d, _) in curves.items()]
    for i in range(len(frame)):
        cells = [(_fmt(v[i], d) or f"{NULL:g}") for v, d in cols]
        lines.append(" " + " ".join(f"{c:>10}" for c in cells))
    return "\n".join(lines) + "\n"


def csv_text(frame: pd.DataFrame, curves: dict[str, tuple[str, int, str]],
             headers: dict[str, str]) -> str:
    """CSV with field headers (``Bit Depth (ft)``) and empty cells for nulls."""
    names = list(curves)
    out = [",".join(f"{headers[n]} ({curves[n][0]})" for n in names)]
    cols = [(frame[n].to_numpy(dtype=float), curves[n][1]) for n in names]
    for i in range(len(frame)):
        out.append(",".join(_fmt(v[i], d) for v, d in cols))
    return "\n".join(out) + "\n"


_WITSML_NS = "http://www.witsml.org/schemas/1series"
_WITSML_UNITS = {"s": "s", "ft": "ft", "klbf": "klbf", "rpm": "rpm", "kft.lbf": "kft.lbf",
                 "ft/h": "ft/h", "psi": "psi", "gpm": "galUS/min"}


def witsml_log_text(frame: pd.DataFrame, curves: dict[str, tuple[str, int, str]]) -> str:
    """WITSML 1.4.1.1 ``log`` (date-time index from :data:`START`, empty cell = null)."""
    t0 = pd.Timestamp(START)
    times = [(t0 + pd.Timedelta(seconds=float(s))).strftime("%Y-%m-%dT%H:%M:%S.000Z")
             for s in frame["TIME"]]
    names = [n for n in curves if n != "TIME"]
    out = ['<?xml version="1.0" encoding="UTF-8"?>',
           f'<logs xmlns="{_WITSML_NS}" version="1.4.1.1">',
           '  <log uidWell="W-SYN-1" uidWellbore="WB-SYN-1" uid="L-SYN-1">',
           "    <nameWell>SYNTHETIC-1</nameWell>", "    <nameWellbore>SYNTHETIC-1</nameWellbore>",
           "    <name>surface time log</name>", "    <indexType>date time</indexType>",
           f"    <startDateTimeIndex>{times[0]}</startDateTimeIndex>",
           f"    <endDateTimeIndex>{times[-1]}</endDateTimeIndex>",
           "    <direction>increasing</direction>", "    <indexCurve>TIME</indexCurve>",
           "    <nullValue>-999.25</nullValue>",
           '    <logCurveInfo uid="TIME"><mnemonic>TIME</mnemonic>'
           "<typeLogData>date time</typeLogData></logCurveInfo>"]
    for n in names:
        unit = _WITSML_UNITS[curves[n][0]]
        out.append(f'    <logCurveInfo uid="{n}"><mnemonic>{n}</mnemonic><unit>{unit}</unit>'
                   f"<curveDescription>{escape(curves[n][2])}</curveDescription>"
                   "<typeLogData>double</typeLogData></logCurveInfo>")
    out.append("    <logData>")
    out.append("      <mnemonicList>" + ",".join(["TIME", *names]) + "</mnemonicList>")
    out.append("      <unitList>" + ",".join(["unitless", *(_WITSML_UNITS[curves[n][0]]
                                                            for n in names)]) + "</unitList>")
    cols = [(frame[n].to_numpy(dtype=float), curves[n][1]) for n in names]
    for i in range(len(frame)):
        out.append(f"      <data>{times[i]},"
                   + ",".join(_fmt(v[i], d) for v, d in cols) + "</data>")
    out += ["    </logData>", "  </log>", "</logs>"]
    return "\n".join(out) + "\n"


def depth_log(frame: pd.DataFrame) -> pd.DataFrame:
    """The drilling rows of the day resampled to one row per new foot of hole (no time)."""
    drilling = frame[(frame["ROP"] > 0) & frame["BITDEP"].diff().gt(0)]
    depth = np.arange(math.ceil(drilling["DMEA"].iloc[0]), math.floor(drilling["DMEA"].iloc[-1]))
    out = {"DEPT": depth.astype(float)}
    for n in ("ROP", "SWOB", "SURF_RPM", "STOR", "HKLD", "SPPA", "TFLO"):
        v = drilling[n].interpolate(limit_direction="both").to_numpy()
        out[n] = np.round(np.interp(depth, drilling["DMEA"].to_numpy(), v), LOG_CURVES[n][1])
    return pd.DataFrame(out)


def survey_stations_ft() -> pd.DataFrame:
    """A build to horizontal in ft: vertical to 1150 ft, build 5.8 deg/100 ft to 90 deg at
    azimuth 135 (2702 ft), hold to 3350 ft (the shape of ``params.yaml``'s profile_1)."""
    kop, dls, td = 1150.0, 5.8, 3350.0
    end = kop + 90.0 / dls * 100.0
    md = np.arange(0.0, td + 1, 95.0)
    md = np.unique(np.concatenate([md, [kop, end, td]]))
    inc = np.clip((md - kop) * dls / 100.0, 0.0, 90.0)
    azi = np.where(md > kop, 135.0, 0.0)
    sv = minimum_curvature(md * units.FT_M, np.radians(inc), np.radians(azi))
    return pd.DataFrame({"MD": md, "Inc": inc, "Azi": azi, "TVD": sv.pos_m[:, 2] / units.FT_M,
                         "NS": sv.pos_m[:, 0] / units.FT_M, "EW": sv.pos_m[:, 1] / units.FT_M,
                         "DLS": sv.dls_deg_per_100ft})


def survey_csv_text(st: pd.DataFrame) -> str:
    """A directional company's export: ft, deg/100 ft, two decimals, extra columns."""
    lines = ["MD,Incl,Azim,TVD,N/S,E/W,DLS", "ft,deg,deg,ft,ft,ft,deg/100ft"]
    for r in st.itertuples():
        lines.append(f"{r.MD:.2f},{r.Inc:.2f},{r.Azi:.2f},{r.TVD:.2f},{r.NS:.2f},{r.EW:.2f},"
                     f"{r.DLS:.2f}")
    return "\n".join(lines) + "\n"


def witsml_trajectory_text(st: pd.DataFrame) -> str:
    """WITSML 1.4.1.1 ``trajectory`` of the stations (uom attributes, ft and dega)."""
    out = ['<?xml version="1.0" encoding="UTF-8"?>',
           f'<trajectorys xmlns="{_WITSML_NS}" version="1.4.1.1">',
           '  <trajectory uidWell="W-SYN-1" uidWellbore="WB-SYN-1" uid="T-SYN-1">',
           "    <nameWell>SYNTHETIC-1</nameWell>", "    <nameWellbore>SYNTHETIC-1</nameWellbore>",
           "    <name>definitive survey</name>"]
    for k, r in enumerate(st.itertuples()):
        out += [f'    <trajectoryStation uid="S{k + 1:03d}">',
                "      <typeTrajStation>" + ("tie in point" if k == 0 else "MWD")
                + "</typeTrajStation>",
                f'      <md uom="ft">{r.MD:.2f}</md>', f'      <tvd uom="ft">{r.TVD:.2f}</tvd>',
                f'      <incl uom="dega">{r.Inc:.2f}</incl>',
                f'      <azi uom="dega">{r.Azi:.2f}</azi>',
                f'      <dls uom="dega/100ft">{r.DLS:.2f}</dls>',
                "    </trajectoryStation>"]
    out += ["  </trajectory>", "</trajectorys>"]
    return "\n".join(out) + "\n"


TALLY_CSV = """Description,Joints,Length,OD,ID,Blade OD,Blade Length,Grade,Serial
,,ft,in,in,in,in,,
8-1/2in PDC bit,1,1.0,,,,,,BIT-01
near-bit stabilizer,1,5.9,6.75,2.8125,8.4375,17.7,,NBS-01
MWD,1,29.5,6.75,3.25,,,,MWD-01
string stabilizer,1,5.9,6.75,2.8125,8.4375,17.7,,STB-01
6-3/4in x 2-13/16in DC NC50,3,88.6,,,,,,DC-01
drilling jar,1,30.8,6.5,2.75,,,,JAR-01
6-3/4in x 2-13/16in DC NC50,1,29.5,,,,,,DC-02
5in HWDP NC50,5,150.0,,,,,,HW-01
5in 19.5ppf G-105 NC50,60,1860.0,,,,,G-105,DP-01
"""

_CSV_HEADERS = {"TIME": "Time", "BITDEP": "Bit Depth", "DMEA": "Hole Depth",
                "HKLD": "Hook Load", "SWOB": "WOB", "SURF_RPM": "Surface RPM",
                "STOR": "Surface Torque", "ROP": "ROP", "SPPA": "Standpipe Pressure",
                "TFLO": "Flow In", "BPOS": "Block Position"}


def write_field_examples(folder: str | Path) -> list[Path]:
    """Write the example field files into ``folder``; returns their paths."""
    d = Path(folder)
    day = synthetic_day()
    depth = depth_log(day)
    depth_curves = {"DEPT": ("ft", 0, "hole depth (index)"),
                    **{n: LOG_CURVES[n] for n in depth.columns if n != "DEPT"}}
    st = survey_stations_ft()
    files = {
        "rig_day.las": las_text(day, LOG_CURVES),
        "rig_day.csv": csv_text(day, LOG_CURVES, _CSV_HEADERS),
        "rig_day_witsml.xml": witsml_log_text(day, LOG_CURVES),
        "drilling_depth.las": las_text(depth, depth_curves, "measured depth"),
        "survey_ft.csv": survey_csv_text(st),
        "survey_witsml.xml": witsml_trajectory_text(st),
        "tally.csv": TALLY_CSV,
    }
    out = []
    for name, text in files.items():
        out.append(atomic_write_text(d / name, text))
    return out


#: Constant inputs of the field example's replay (user units): what the log does not carry.
FIELD_EXAMPLE_CONSTANTS: dict[str, float] = {"mu_dynamic": 0.28, "mud_density_sg": 1.25,
                                             "lobe_amplitude_mm": 1.0}


def field_example() -> dict[str, object]:
    """The field example as a twin replay takes it: the rig day's LAS text, the tally CSV,
    the survey as SI rows (``md_m``, ``inc_deg``, ``dls_deg_per_30m``, read from the
    example's field-unit CSV by :func:`drillfatigue.well.survey_file.twin_survey_table`) and
    the constant inputs (:data:`FIELD_EXAMPLE_CONSTANTS`)."""
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "survey_ft.csv"
        path.write_text(survey_csv_text(survey_stations_ft()), encoding="utf-8")
        survey = twin_survey_table(path)
    return {"log": {"format": "las", "text": las_text(synthetic_day(), LOG_CURVES)},
            "tally_csv": TALLY_CSV,
            "survey": [{k: float(v) for k, v in row.items()}
                       for row in survey.to_dict(orient="records")],
            "constants": dict(FIELD_EXAMPLE_CONSTANTS),
            "description": "data/examples/field: a synthetic 24 h rig day (LAS 2.0), the "
                           "string tally (bit, collars, heavy-weight and drill pipe) and a J "
                           "well survey in ft"}
