"""A short drilling run shared by the step tests: 30 m of collars and 90 m of drill
pipe (12 segments) in a straight hole, turned at 120 rpm against a given torque on bit."""

from __future__ import annotations

from typing import Any

from drillfatigue.config import case_from_dict
from drillfatigue.dynamics.run.simulation import simulate
from drillfatigue.dynamics.run.model import straight_path


def given_tob_run(dt_s: float | None, implicit_bit_torque: bool = False) -> Any:
    """The run with step ``dt_s`` (None: the stable-step estimate's), 1.5 s, loads at 100 Hz."""
    cfg = case_from_dict({
        "string": {"components": [
            {"type": "collar", "od_m": 0.17145, "id_m": 0.0714, "length_m": 30.0, "n_segments": 3},
            {"type": "drill_pipe", "od_m": 0.127, "id_m": 0.1086, "length_m": 90.0,
             "n_segments": 9}]},
        "operation": {"bit_md_m": 120.0, "duration_s": 1.5, "rpm": 120.0, "rpm_ramp_s": 0.5,
                      "tob_Nm": 1500.0, "rop_m_per_s": 0.01, "lobe_amplitude_m": 0.0002},
        "solver": {"dt_s": dt_s, "implicit_bit_torque": implicit_bit_torque},
        "recording": {"loads_rate_hz": 100.0, "channels_rate_hz": 100.0},
    })
    return simulate(cfg, None, progress=False, path=straight_path(300.0))
