"""drillfatigue.io.logs: LAS 2.0, WITSML 1.4.1.1 and CSV operating logs for the twin."""

from __future__ import annotations

import json
import os
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from testkit.tiny_surrogate import open_domain

from drillfatigue import units
from drillfatigue.cli import main
from drillfatigue.config.surrogate import SurrogateConfig
from drillfatigue.errors import InputError
from drillfatigue.io.logs import load_log
from drillfatigue.well.survey_file import twin_survey_table
from drillfatigue.io.tally import load_tally
from drillfatigue.surrogate import Surrogate, fit_surrogate, make_synthetic_dataset
from drillfatigue.surrogate.twin import components_from_string, replay_log

EXAMPLES = Path(__file__).resolve().parents[3] / "data" / "examples" / "field"

LAS = """~VERSION INFORMATION
 VERS.                 2.0 : CWLS LOG ASCII STANDARD - VERSION 2.0
 WRAP.                  NO : ONE LINE PER STEP
~WELL INFORMATION
 STRT.s                  0 : START
 STOP.s                240 : STOP
 STEP.s                 60 : STEP
 NULL.             -999.25 : NULL VALUE
 WELL.              HAND-1 : WELL
~CURVE INFORMATION
 TIME    .s        : elapsed time
 BITDEP  .ft       : bit depth
 DMEA    .ft       : hole depth
 SWOB    .klbf     : weight on bit
 HKLD    .klbf     : hook load
 SURF_RPM.rpm      : rotary speed
 TQA     .kft.lbf  : surface torque
 ROP     .ft/h     : rate of penetration
 GR      .gAPI     : gamma ray
~A  TIME BITDEP DMEA SWOB HKLD SURF_RPM TQA ROP GR
 0     1000.0 1000.0 20.0 150.0 120.0   10.0 60.0 50
 60    1001.0 1001.0 20.0 150.0 -999.25 10.0 60.0 51
 120   1002.0 1002.0 22.0 148.0 130.0   11.0 60.0 52
 120   1002.0 1002.0 22.0 148.0 130.0   11.0 60.0 52
 180   1003.0 1003.0 22.0 148.0 130.0   11.0 60.0 53
 240   1004.0 1004.0 24.0 146.0 140.0   12.0 60.0 54
"""

CSV = """Time (s),Bit Depth (ft),Hole Depth (ft),WOB (klbf),Hook Load (klbf),Surface RPM (rpm),\
Torque (kft.lbf),ROP (ft/h),Gamma (gAPI)
0,1000.0,1000.0,20.0,150.0,120.0,10.0,60.0,50
60,1001.0,1001.0,20.0,150.0,,10.0,60.0,51
120,1002.0,1002.0,22.0,148.0,130.0,11.0,60.0,52
120,1002.0,1002.0,22.0,148.0,130.0,11.0,60.0,52
180,1003.0,1003.0,22.0,148.0,130.0,11.0,60.0,53
240,1004.0,1004.0,24.0,146.0,140.0,12.0,60.0,54
"""

WITSML = """<?xml version="1.0" encoding="UTF-8"?>
<logs xmlns="http://www.witsml.org/schemas/1series" version="1.4.1.1">
 <log uidWell="W" uidWellbore="B" uid="L">
  <nameWell>HAND-1</nameWell><nameWellbore>HAND-1</nameWellbore><name>time log</name>
  <indexType>date time</indexType><indexCurve>TIME</indexCurve>
  <nullValue>-999.25</nullValue>
  <logCurveInfo uid="TIME"><mnemonic>TIME</mnemonic><typeLogData>date time</typeLogData>
  </logCurveInfo>
  <logCurveInfo uid="HKLD"><mnemonic>HKLD</mnemonic><unit>klbf</unit></logCurveInfo>
  <logData>
   <mnemonicList>TIME,BITDEP,DMEA,SWOB,HKLD,SURF_RPM,TQA,ROP,GR</mnemonicList>
   <unitList>unitless,ft,ft,klbf,klbf,rpm,kft.lbf,ft/h,gAPI</unitList>
   <data>2026-03-14T06:00:00.000Z,1000.0,1000.0,20.0,150.0,120.0,10.0,60.0,50</data>
   <data>2026-03-14T06:01:00.000Z,1001.0,1001.0,20.0,150.0,,10.0,60.0,51</data>
   <data>2026-03-14T06:02:00.000Z,1002.0,1002.0,22.0,148.0,130.0,11.0,60.0,52</data>
   <data>2026-03-14T06:02:00.000Z,1002.0,1002.0,22.0,148.0,130.0,11.0,60.0,52</data>
   <data>2026-03-14T06:03:00.000Z,1003.0,1003.0,22.0,148.0,130.0,11.0,60.0,53</data>
   <data>2026-03-14T06:04:00.000Z,1004.0,1004.0,24.0,146.0,-999.25,12.0,60.0,54</data>
  </logData>
 </log>
</logs>
"""

DEPTH_LAS = """~VERSION INFORMATION
 VERS.   2.0 : CWLS LOG ASCII STANDARD - VERSION 2.0
 WRAP.   NO  : ONE LINE PER STEP
~WELL INFORMATION
 STRT.ft   1000 : START
 STOP.ft   1003 : STOP
 STEP.ft      1 : STEP
 NULL.  -999.25 : NULL VALUE
~CURVE INFORMATION
 DEPT.ft      : depth
 ROP .ft/h    : rate of penetration
 SWOB.klbf    : weight on bit
 RPM .rpm     : rotary speed
~A
 1000 60 20 120
 1001 30 25 120
 1002 60 20 120
 1003 60 20 120
"""


def _write(tmp_path: Path, name: str, text: str) -> Path:
    p = tmp_path / name
    p.write_text(text)
    return p


def test_hand_made_las_known_values(tmp_path: Path) -> None:
    r = load_log(_write(tmp_path, "h.las", LAS))
    t = r.table
    np.testing.assert_array_equal(t["time_s"], [0, 60, 120, 180, 240])
    np.testing.assert_allclose(t["bit_md_m"], [304.8, 305.1048, 305.4096, 305.7144, 306.0192],
                               rtol=1e-15)
    assert t["wob_N"].iloc[0] == 20.0 * units.KLBF_N
    assert t["hook_load_N"].iloc[-1] == 146.0 * units.KLBF_N
    assert t["surface_torque_Nm"].iloc[0] == 10.0 * units.KFT_LBF_NM
    assert t["rop_m_per_s"].iloc[0] == 60.0 * units.FT_PER_H_M_PER_S
    # the null RPM at t = 60 s holds the 120 rpm of t = 0 (the twin's own rule)
    np.testing.assert_array_equal(t["rpm"], [120.0, 120.0, 130.0, 130.0, 140.0])
    assert r.filled == {"SURF_RPM": {"samples": 1, "longest_gap_s": 120.0}}
    assert r.dropped_repeated_rows == 1
    assert r.ignored == ("GR",)
    assert r.channels["wob_N"] == "SWOB [klbf]"
    assert json.loads(json.dumps(r.report()))["index"] == "time"


def test_las_csv_and_witsml_give_the_same_table(tmp_path: Path) -> None:
    a = load_log(_write(tmp_path, "h.las", LAS)).table
    b = load_log(_write(tmp_path, "h.csv", CSV)).table
    w = load_log(_write(tmp_path, "h.xml", WITSML))
    # the WITSML copy has its null at the last RPM instead: held from 130
    expect = a.copy()
    expect.loc[4, "rpm"] = 130.0
    expect.loc[1, "rpm"] = 120.0
    pd.testing.assert_frame_equal(a, b, check_exact=True)
    pd.testing.assert_frame_equal(w.table.assign(rpm=expect["rpm"]), expect, check_exact=True)
    assert w.start_time == "2026-03-14T06:00:00+00:00"


def test_depth_indexed_log_gets_time_from_rop(tmp_path: Path) -> None:
    r = load_log(_write(tmp_path, "d.las", DEPTH_LAS))
    # 1 ft at 60 ft/h = 60 s, 1 ft at 30 ft/h = 120 s, 1 ft at 60 ft/h = 60 s
    np.testing.assert_allclose(r.table["time_s"], [0.0, 60.0, 180.0, 240.0], rtol=1e-13)
    assert r.index == "depth" and "derived" in r.notes[0]
    np.testing.assert_array_equal(r.table["bit_md_m"], np.array([1000, 1001, 1002, 1003])
                                  * units.FT_M)


def test_twin_style_csv_columns_keep_working(tmp_path: Path) -> None:
    p = _write(tmp_path, "t.csv", "time_s,bit_md_m,rpm,wob_kN,rop_m_per_h,mud_density_sg\n"
               "0,1200,120,80,18,1.2\n60,1200.3,121,81,18,1.2\n")
    t = load_log(p).table
    assert list(t.columns) == ["time_s", "bit_md_m", "rpm", "wob_N", "rop_m_per_s",
                               "mud_density_sg"]
    assert t["wob_N"].tolist() == [80e3, 81e3]
    assert t["rop_m_per_s"].iloc[0] == 18 * units.M_PER_H_M_PER_S


def test_channel_choice_between_two_candidates(tmp_path: Path) -> None:
    text = LAS.replace(" GR      .gAPI     : gamma ray", " RPM     .rpm      : second rpm")
    p = _write(tmp_path, "two.las", text)
    with pytest.raises(InputError, match="--channel rpm=MNEMONIC"):
        load_log(p)
    r = load_log(p, {"rpm": "RPM"})
    assert r.table["rpm"].tolist() == [50.0, 51.0, 52.0, 53.0, 54.0]
    assert "SURF_RPM" in r.ignored


def _las_row_edit(old: str, new: str) -> str:
    assert old in LAS
    return LAS.replace(old, new)


# (id, file name, text, channel the error names, a word of the message)
BAD = [
    ("las_garbage", "x.las", "this is not a LAS file\n1 2 3\n", "x.las", "LAS"),
    ("las_version_3", "x.las", LAS.replace("VERS.                 2.0", "VERS. 3.0"),
     "x.las:~VERSION", "LAS version"),
    ("las_hook_load_in_ft", "x.las", LAS.replace("HKLD    .klbf", "HKLD    .ft  "), "x.las:HKLD",
     "not a force unit"),
    ("las_time_backwards", "x.las", _las_row_edit(" 180   1003.0", " 100   1003.0"), "x.las:TIME",
     "backwards"),
    ("las_same_time_other_values", "x.las",
     _las_row_edit(" 120   1002.0 1002.0 22.0 148.0 130.0   11.0 60.0 52\n 180",
                   " 120   1002.0 1002.0 22.0 148.0 130.0   11.0 60.0 52\n 120   1002.0 1002.0 "
                   "23.0 148.0 130.0   11.0 60.0 52\n 180"), "x.las:SWOB", "different values"),
    ("las_gap", "x.las", _las_row_edit(" 240   1004.0", " 2400   1004.0"), "x.las:TIME",
     "no sample"),
    ("las_long_null_run", "x.las",
     LAS.replace("130.0   11.0", "-999.25   11.0").replace("140.0   12.0", "-999.25   12.0"),
     "x.las:SURF_RPM", "null values"),
    ("las_no_bit_depth", "x.las", LAS.replace("BITDEP  .ft", "BITX    .ft"), "x.las",
     "no bit depth"),
    ("las_rop_in_m_per_h_labelled_ft_per_h", "x.las", LAS.replace(" 60.0 5", " 18.3 5"),
     "x.las:ROP", "ROP unit"),
    ("las_bit_depth_in_ft_labelled_m", "x.las", LAS.replace("BITDEP  .ft", "BITDEP  .m "),
     "x.las:BITDEP", "depth units"),
    ("xml_not_xml", "x.xml", "<logs><log>", "x.xml", "XML"),
    ("xml_no_log", "x.xml", "<trajectorys/>", "x.xml", "no log"),
    ("xml_short_row", "x.xml", WITSML.replace(",60.0,54</data>", "</data>"),
     "x.xml:logData/data[6]", "values"),
    ("xml_unit_disagrees", "x.xml", WITSML.replace("<unit>klbf</unit>", "<unit>kN</unit>"),
     "x.xml:HKLD", "unitList"),
    ("csv_unknown_unit", "x.csv", CSV.replace("WOB (klbf)", "WOB (stone)"), "x.csv:wob",
     "not a force unit"),
    ("csv_text_in_a_channel", "x.csv", CSV.replace("0,1000.0,1000.0,20.0", "0,1000.0,1000.0,x"),
     "x.csv:wob", "not a number"),
    ("csv_rpm_twice", "x.csv", CSV.replace("Gamma (gAPI)", "rpm"), "x.csv", "rpm"),
    ("unknown_file_type", "x.dat", "1,2\n", "x.dat", "log file type"),
]


@pytest.mark.parametrize(("name", "text", "field", "word"), [b[1:] for b in BAD],
                         ids=[b[0] for b in BAD])
def test_malformed_log_one_line_exit_2_nothing_written(tmp_path, monkeypatch, capsys, name, text,
                                                       field, word) -> None:
    monkeypatch.chdir(tmp_path)
    _write(tmp_path, name, text)
    before = set(os.listdir(tmp_path))
    # --max-fill-s 150: the single null (120 s) is held, the long run (240 s) is not
    rc = main(["twin", "replay", name, "--model", "nomodel", "--components", "c.csv",
               "--max-fill-s", "150", "--out", "out"])
    out, err = capsys.readouterr()
    assert rc == 2 and out == "", err
    assert len(err.splitlines()) == 1, err
    assert err.startswith(f"error: {field}"), err
    assert word in err, err
    assert set(os.listdir(tmp_path)) == before


# --- the twin on field files --------------------------------------------------------------

TINY = SurrogateConfig(hidden_layers=(16,), max_epochs=6, patience=6, batch_size=128,
                       n_threads=1)
CONSTANTS = {"mu_static": 0.35, "mu_dynamic": 0.28, "mud_density_sg": 1.25,
             "amplitude_mm": 1.0, "lobes": 3, "kop_m": 500, "dls_deg_per_30m": 5,
             "profile": "build_hold"}


@pytest.fixture(scope="module")
def model() -> Surrogate:
    # the same numbers from each file is under test, not the domain
    return open_domain(fit_surrogate(make_synthetic_dataset(30, seed=4), TINY))


def _tally_components() -> pd.DataFrame:
    """The example tally's tracked locations (every 8th keeps the test short)."""
    comps = components_from_string(load_tally(EXAMPLES / "tally.csv").string)
    return comps.iloc[::8].reset_index(drop=True)


def test_las_and_csv_of_one_log_give_the_same_twin_result(model: Surrogate) -> None:
    comps = _tally_components()
    survey = twin_survey_table(EXAMPLES / "survey_ft.csv")
    res = {}
    for name in ("rig_day.las", "rig_day.csv", "rig_day_witsml.xml"):
        res[name] = replay_log(load_log(EXAMPLES / name).table, comps, model, CONSTANTS,
                               survey).components
    las = res["rig_day.las"]
    # the bit, the types and the upset rows this toy model was not trained on are listed,
    # not covered; the covered rows have damage
    assert "bit" in set(las.loc[~las["covered"], "kind"])
    assert (las.loc[las["covered"], "damage"] > 0).all() and las["covered"].sum() > 15
    for other in ("rig_day.csv", "rig_day_witsml.xml"):
        pd.testing.assert_frame_equal(res["rig_day.las"], res[other], check_exact=True)


def test_cli_replays_a_las_day_in_field_units(model: Surrogate, tmp_path: Path, capsys) -> None:
    model.save(tmp_path / "m")
    _tally_components().to_csv(tmp_path / "c.csv", index=False)
    sets = [a for k, v in CONSTANTS.items() for a in ("--set", f"{k}={v}")]
    out = tmp_path / "twin"
    rc = main(["twin", "replay", str(EXAMPLES / "rig_day.las"), "--model", str(tmp_path / "m"),
               "--components", str(tmp_path / "c.csv"), "--survey",
               str(EXAMPLES / "survey_witsml.xml"), *sets, "--units", "field", "--out", str(out)])
    text = capsys.readouterr().out
    assert rc == 0, text
    assert "ft from the bit" in text and "SURF_RPM: 2 null value(s) held" in text
    assert "1 repeated row(s) dropped" in text
    summary = json.loads((out / "summary.json").read_text())
    assert summary["duration_h"] == 24.0
    assert summary["log"]["filled_null_values"]["SPPA"]["samples"] == 3
    assert summary["log"]["channels"]["hook_load_N"] == "HKLD [klbf]"
    assert "hook_load_N" in summary["ignored_log_channels"]


def test_example_files_are_what_the_script_writes(tmp_path: Path) -> None:
    from drillfatigue.io.examples import write_field_examples

    for p in write_field_examples(tmp_path):
        assert p.read_bytes() == (EXAMPLES / p.name).read_bytes(), p.name


def test_depth_indexed_witsml_log(tmp_path: Path) -> None:
    text = """<logs xmlns="http://www.witsml.org/schemas/1series" version="1.4.1.1">
 <log uidWell="W" uidWellbore="B" uid="L"><indexType>measured depth</indexType>
  <indexCurve>DEPTH</indexCurve>
  <logData><mnemonicList>DEPTH,ROPA,WOBA,RPMA</mnemonicList><unitList>m,m/h,kN,rpm</unitList>
   <data>1000.0,20,80,120</data><data>1000.5,10,80,120</data><data>1001.0,20,80,120</data>
  </logData></log></logs>"""
    r = load_log(_write(tmp_path, "d.xml", text))
    # 0.5 m at 20 m/h = 90 s, then 0.5 m at 10 m/h = 180 s
    np.testing.assert_allclose(r.table["time_s"], [0.0, 90.0, 270.0], rtol=1e-13)
    assert r.table["bit_md_m"].tolist() == [1000.0, 1000.5, 1001.0]
    assert r.table["wob_N"].tolist() == [80e3] * 3 and r.index == "depth"


def test_csv_with_a_units_row(tmp_path: Path) -> None:
    p = _write(tmp_path, "u.csv", "Time,Bit Depth,WOB,RPM,ROP\ns,ft,klbf,rpm,ft/h\n"
               "0,1000,20,120,60\n60,1001,20,120,60\n")
    t = load_log(p).table
    assert t["bit_md_m"].tolist() == [304.8, 1001 * units.FT_M]
    assert t["wob_N"].tolist() == [20 * units.KLBF_N] * 2
