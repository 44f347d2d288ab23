"""One deep deviated well off bottom, run by the simulator and by the distributed wave model.

The well (stated here, not a published one): a straight 8 1/2 in hole inclined at
60 deg (the tangent of Aarsnes & Shor's synthetic Well A, J. Petrol. Sci. Eng. 163
(2018) 712-721, Fig. 4) from 10 m below the rotary; 2800 m of 5 in x 4.276 in drill
pipe (body contact, no tool joints: r = 63.5 mm) over 200 m of 6 3/4 in x 2.81 in
collars (r = 85.7 mm), bit 10 m off bottom at MD 3010 m, the block held; steel 7850
kg/m^3, G = 79.6 GPa, 1.2 SG mud; wall friction mu_s 0.35, mu_d 0.25 with the law
named by the caller; torsional mud drag per length as given (the default 0.05
N m s/rad per m); 2 % of critical damping in the simulator's joints; the default top
drive (932 kg m^2 on the string side) with a stiff PI (Kp = 2e4 N m s/rad, Ki = 4e4
N m/rad, 50 kN m limit) turning to the set speed over 5 s. No build section: the
reference's normal force is the buoyed weight across the hole, and a build would add
the tension times the curvature, which rigid segments of 50 m cannot follow (their
chords would cut the bend by metres).

Segments of 50 m for pipe and collars alike. With 200 m pipe segments and the collars as
one rigid body the simulator's stick-slip is distorted (surface-torque spikes to
-13 kN m as the top segment lets go, the bit stuck 43 % of the time against 31 %);
with the collars one 200 m body the stuck collar rocks in the hole as a rolling
pendulum at about 2.5 Hz, which the bit speed shows as +-10 rpm while the wall holds it
(docs/rig.md#off-bottom-stick-slip-and-the-stick-band).
"""

from __future__ import annotations

import math
from dataclasses import replace
from typing import Any

import numpy as np

from drillfatigue.config import case_from_dict
from drillfatigue.dynamics.core import layout as L
from drillfatigue.dynamics.run.model import advance_model, build_model, straight_path

from testkit.rig_references import stick_slip_metrics
from testkit.torsional_wave import Section, WaveWell, simulate_wave

INC_DEG = 60.0
PIPE = Section(2800.0, 0.127, 0.1086)
COLLAR = Section(200.0, 0.17145, 0.0714)
SEGMENT_M = 50.0
MU_S, MU_D = 0.35, 0.25
KP, KI, T_MAX = 2e4, 4e4, 50e3
RAMP_S = 5.0
T_FROM_S = 20.0  # cycles are measured after the start-up


def wave_well(law: str = "tanh_exp", band_m_per_s: float = 0.095, damping: float = 0.05,
              rpm: float = 40.0) -> WaveWell:
    """The well for :func:`testkit.torsional_wave.simulate_wave`."""
    return WaveWell(sections=(PIPE, COLLAR), inclination_deg=INC_DEG, mud_damping_Nms_per_rad_per_m=damping,
                    law=law, mu_s=MU_S, mu_d=MU_D, v_band_m_per_s=band_m_per_s, kp_Nms_per_rad=KP,
                    ki_Nm_per_rad=KI, torque_limit_Nm=T_MAX, rpm=rpm, ramp_s=RAMP_S)


def case_dict(law: str = "tanh_exp", band_m_per_s: float = 0.095, damping: float = 0.05, rpm: float = 40.0,
              t_end_s: float = 50.0, segment_m: float = SEGMENT_M) -> dict[str, Any]:
    """The simulator's case of the same well."""
    friction: dict[str, Any] = {"model": law, "mu_static": MU_S, "mu_dynamic": MU_D}
    if law == "stick_band":
        friction["stick_band_m_per_s"] = band_m_per_s
    return {
        "string": {"components": [
            {"type": "collar", "od_m": COLLAR.od_m, "id_m": COLLAR.id_m, "length_m": COLLAR.length_m,
             "n_segments": max(1, round(COLLAR.length_m / segment_m))},
            {"type": "drill_pipe", "od_m": PIPE.od_m, "id_m": PIPE.id_m, "length_m": PIPE.length_m,
             "n_segments": max(1, round(PIPE.length_m / segment_m))}]},
        "operation": {"duration_s": t_end_s, "bit_md_m": PIPE.length_m + COLLAR.length_m + 10.0,
                      "top_md_m": 10.0, "rpm": rpm, "rpm_ramp_s": RAMP_S, "bit_on_bottom": False,
                      "top_axial": "fixed", "mud_density_kg_per_m3": 1200.0,
                      "mud_damping_torsional_N_m_s_per_m": damping},
        "friction": friction,
        "bit": {"model": "yigit_christoforou"},
        "solver": {"relax_s": 0.5, "joint_damping_ratio": 0.02, "boundary_damping_ratio": 0.02},
        "rig": {"block_mode": "held", "rock": {"lobe_amplitude_m": 0.0},
                "top_drive": {"tuning": "pi", "kp_Nm_s_per_rad": KP, "ki_Nm_per_rad": KI,
                              "torque_limit_Nm": T_MAX}},
        "recording": {"loads_rate_hz": 10.0, "channels_rate_hz": 200.0, "kinematics_rate_hz": 1.0},
    }


def simulate_case(t_end_s: float = 50.0, **kw: Any) -> dict[str, np.ndarray]:
    """Simulator run of :func:`case_dict`: ``t, omega_bit (rad/s), torque_surface (N m), wob (N)``."""
    cfg = case_from_dict(case_dict(t_end_s=t_end_s, **kw))
    length = PIPE.length_m + COLLAR.length_m
    model, state = build_model(cfg, straight_path(length + 600.0, inclination_deg=INC_DEG))
    every = max(1, round(0.005 / model.dt))
    ch = advance_model(model, state, round(t_end_s / model.dt), every=every)["channels"]
    return {"t": ch[:, 0], "omega_bit": ch[:, 1 + L.H_BITRPM] * math.pi / 30.0,
            "torque_surface": ch[:, 1 + L.H_TSURF], "wob": ch[:, 1 + L.H_WOB]}


def simulate_reference(t_end_s: float = 50.0, dx_m: float = 10.0, **kw: Any) -> dict[str, np.ndarray]:
    """Distributed wave model run of :func:`wave_well`, cells of at most ``dx_m``."""
    return simulate_wave(replace(wave_well(**kw), dx_m=dx_m), t_end_s)


def metrics(res: dict[str, np.ndarray], rpm: float) -> dict[str, float]:
    """Period, break-off torque, stuck fraction (:func:`rig_references.stick_slip_metrics`)."""
    return stick_slip_metrics(res, rpm * math.pi / 30.0, T_FROM_S)
