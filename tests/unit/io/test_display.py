"""``--units field`` on the CLI tables: the same numbers as SI, divided by the exact factors."""

from __future__ import annotations

import re
from pathlib import Path

import pytest
import yaml

from drillfatigue import units
from drillfatigue.cli import main

CASE = {"well": {"profiles": {"j": {"kind": "j", "kop_m": 300.0, "dls_deg_per_30m": 3.0,
                                    "inc_deg": 40.0, "td_m": 1500.0}}},
        "string": {"components": [
            {"type": "collar", "od_m": 0.17145, "id_m": 0.0714, "length_m": 180.0,
             "n_segments": 20},
            {"type": "drill_pipe", "od_m": 0.127, "id_m": 0.1086, "length_m": 900.0,
             "tool_joint_od_m": 0.1683, "tool_joint_id_m": 0.0826,
             "tool_joint_length_fraction": 0.05, "n_segments": 100}]},
        "operation": {"bit_md_m": 1400.0}}


def _numbers(line: str) -> list[float]:
    return [float(x) for x in re.findall(r"-?\d+\.\d+", line)]


def _rows(text: str, labels: tuple[str, ...]) -> dict[str, list[float]]:
    return {lab: _numbers(next(ln for ln in text.splitlines() if lab in ln)) for lab in labels}


def test_well_show_in_field_units(tmp_path: Path, capsys) -> None:
    p = tmp_path / "case.yaml"
    p.write_text(yaml.safe_dump(CASE))
    assert main(["well", "show", str(p)]) == 0
    si = _rows(capsys.readouterr().out, ("end of build", "TD "))
    assert main(["well", "show", str(p), "--units", "field"]) == 0
    out = capsys.readouterr().out
    assert "MD ft" in out and "DLS deg/100ft" in out
    field = _rows(out, ("end of build", "TD "))
    for lab in si:
        md_si, inc, azi, tvd_si, n_si, e_si, dls_si = si[lab]
        md_f, inc_f, azi_f, tvd_f, n_f, e_f, dls_f = field[lab]
        # printed to 0.1 / 0.01: compare within half a unit of the printed digit
        assert md_f == pytest.approx(md_si / units.FT_M, abs=0.05 / units.FT_M + 0.05)
        assert tvd_f == pytest.approx(tvd_si / units.FT_M, abs=0.005 / units.FT_M + 0.005)
        assert (inc_f, azi_f) == (inc, azi)
        assert dls_f == pytest.approx(dls_si / units.DEG_PER_100FT_DEG_PER_30M, abs=0.011)


def test_tnd_table_in_field_units(tmp_path: Path, capsys) -> None:
    p = tmp_path / "case.yaml"
    p.write_text(yaml.safe_dump(CASE))
    labels = ("pick-up", "slack-off", "rotating off bottom")
    assert main(["tnd", str(p)]) == 0
    si = _rows(capsys.readouterr().out, labels)
    assert main(["tnd", str(p), "--units", "field"]) == 0
    out = capsys.readouterr().out
    assert "hook load, klbf" in out and "surface torque, kft lbf" in out
    field = _rows(out, labels)
    for lab in labels:
        # hook load printed to 0.1 kN / 0.1 klbf
        assert field[lab][0] == pytest.approx(si[lab][0] * units.KN_N / units.KLBF_N,
                                              abs=0.05 + 0.05 * units.KN_N / units.KLBF_N)
    assert field["rotating off bottom"][1] == pytest.approx(
        si["rotating off bottom"][1] * units.KNM_NM / units.KFT_LBF_NM,
        abs=0.005 + 0.005 * units.KNM_NM / units.KFT_LBF_NM)
