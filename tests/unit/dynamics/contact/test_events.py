"""Event detection written into summary.json and the contact history files."""

from __future__ import annotations

import json
import math
from pathlib import Path

import pyarrow.parquet as pq
import pytest

import drillfatigue
from drillfatigue.config import case_from_dict
from drillfatigue.dynamics.run.simulation import EVENT_KEYS, classify_whirl
from drillfatigue.dynamics.run.examples import j_well_rotating_case
from drillfatigue.dynamics.run.model import straight_path

TURN = 2.0 * math.pi


@pytest.mark.parametrize(("orbit", "orbit_abs", "spin", "expected"), [
    (0.5, 0.5, 100.0, "none"),                 # less than a turn of orbit
    (-3 * TURN, 3 * TURN, 40.0, "backward"),   # steady orbit against the spin
    (3 * TURN, 3 * TURN, 40.0, "forward"),     # steady orbit with the spin
    (0.5 * TURN, 4 * TURN, 40.0, "chaotic"),   # back and forth: net << travelled
])
def test_whirl_classes(orbit: float, orbit_abs: float, spin: float, expected: str) -> None:
    assert classify_whirl(orbit, orbit_abs, spin) == expected
    if expected in ("forward", "backward"):  # the class follows the spin direction
        flipped = {"forward": "backward", "backward": "forward"}[expected]
        assert classify_whirl(orbit, orbit_abs, -spin) == flipped


def test_summary_events_and_contact_files(tmp_path: Path) -> None:
    cfg = j_well_rotating_case(n_segments=15, duration_s=1.5)
    drillfatigue.simulate(cfg, tmp_path / "run", progress=False)
    summary = json.loads((tmp_path / "run" / "summary.json").read_text())
    # the keys the sweep's dataset reads, at the top level and under "events"
    for key in EVENT_KEYS:
        assert key in summary and summary[key] == summary["events"][key]
    assert summary["whirl_class"] in ("none", "forward", "backward", "chaotic")
    assert summary["max_contact_force_N"] > 0.0
    assert summary["rms_surface_torque_Nm"] > 0.0
    assert summary["peak_surface_torque_Nm"] >= summary["rms_surface_torque_Nm"]
    onset = summary["events"]["contact_onset"]
    assert onset and all(o["time_s"] >= 0.0 for o in onset)
    # MD of the touching segment's centre: between the rig floor and the bit
    assert all(0.0 < o["md_m"] < cfg.operation.bit_md_m for o in onset)
    con = pq.read_table(tmp_path / "run" / "contacts.parquet").to_pandas()
    assert list(con.columns) == ["time_s", "segment", "normal_N", "dist_from_centre_m"]
    assert (con.normal_N > 0.0).all()
    # in contact: a contact point sits about one clearance (44.5 mm) off the hole centre
    clearance = 0.2159 / 2 - 0.127 / 2
    assert con.dist_from_centre_m.median() == pytest.approx(clearance, rel=0.05)
    kin = pq.read_table(tmp_path / "run" / "kinematics.parquet")
    assert {"normal_N", "dist_from_centre_m"} <= set(kin.column_names)


def _bounce_count(lobe_m: float) -> int:
    cfg = case_from_dict({
        "string": {"components": [{"type": "collar", "od_m": 0.17145, "id_m": 0.0714,
                                   "length_m": 20.0, "n_segments": 4}]},
        "operation": {"bit_md_m": 25.0, "duration_s": 1.5, "rpm": 120.0, "rpm_ramp_s": 0.3,
                      "top_axial": "neutral_point", "neutral_point_s_from_bit_m": 5.0,
                      "lobe_count": 3, "lobe_amplitude_m": lobe_m},
        "recording": {"channels_rate_hz": 100.0, "kinematics_rate_hz": 10.0,
                      "loads_rate_hz": 10.0},
    })
    res = drillfatigue.simulate(cfg, None, progress=False, path=straight_path(100.0))
    return res.summary["bit_bounce_count"]


def test_bit_bounce_is_counted_when_the_lobes_lift_the_bit() -> None:
    assert _bounce_count(0.0) == 0
    assert _bounce_count(0.005) > 0  # 5 mm lobes at 6 Hz: 0.7 g of lift
