"""Off-bottom torsional stick-slip with a PI top drive, driven by wall friction (docs/rig.md).

The well (stated here, not a published one): a straight hole of 8 1/2 in inclined at 30 deg,
2000 m of 5 in x 4.276 in drill pipe (no tool joints: the pipe touches the wall with its body,
r = 63.5 mm) above 200 m of 6 3/4 in x 2.81 in collars (r = 85.7 mm), steel 7850 kg/m^3,
G = 79.6 GPa, in 1.2 SG mud; the bit 10 m off bottom, the block held (the string hangs from
it); the default wall friction (``tanh_exp``: mu_s 0.35, mu_d 0.25, v_t 1 mm/s, v_s 50 mm/s);
the default top drive (932 kg m^2 on the string side) with a stiff PI (Kp = 2e4 N m s/rad,
Ki = 4e4 N m/rad), 40 rpm after a 5 s ramp; torsional mud drag 0.05 N m s/rad per m, 2 % of
critical damping in the joints. The only velocity-weakening torque is the wall friction's
Stribeck decay from mu_s to mu_d: the drag that makes the string stick and slip.

Reference (written here from the equations, independent of the simulator's code): a
torsional lumped chain of 20 pipe lumps of 100 m and one collar lump, each lump carrying the
wall friction torque of its length, ``r N mu(r omega) / sqrt(1 + mu^2)`` with
``N = (rho_s - rho_m) g A L sin I`` (the buoyed weight's component across a straight hole) and
``mu`` the tanh-exponential law of the friction section. The ``1/sqrt(1 + mu^2)`` is the climb
of a turning pipe up the low side of the hole: it rolls up until gravity's tangential
component balances the friction, ``tan(phi) = mu``, so the wall force is ``W cos(phi)`` and
the friction torque ``W r sin(phi)`` (without it the reference's break-off torque is 4 %
higher). The PI top drive with its inertia and conditional-integration anti-windup is written
again here. LSODA at rtol 1e-6.

Bounds of the issue: break-off torque within 10 % and stick-slip period within 20 % of the
reference. Measured (cycles after 20 s): simulator 4.12 s and 8.29 kN m, reference 4.22 s and
8.82 kN m; the static wall torque is 8.18 kN m. Halving the reference's lumps (10) changes its
break-off torque by 0.6 %, so the lumping is converged. The remaining 6 % on the break-off
torque is, as far as measured, the lateral motion the reference leaves out (the pipe's climb
angle follows the stick and slip with the lateral mud drag's lag instead of sitting at
``atan(mu)``).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from drillfatigue.config import case_from_dict
from drillfatigue.dynamics.core import layout as L
from drillfatigue.dynamics.run.model import advance_model, build_model, straight_path

from testkit.rig_references import stick_slip_metrics

G = 9.81
RHO_S = 7850.0
RHO_M = 1200.0
G_SHEAR = 79.6e9
PIPE_OD, PIPE_ID, PIPE_L = 0.127, 0.1086, 2000.0
COLLAR_OD, COLLAR_ID, COLLAR_L = 0.17145, 0.0714, 200.0
INC_DEG = 30.0
MU_S, MU_D, V_T, V_S = 0.35, 0.25, 1e-3, 0.05
TD_INERTIA = 10.5**2 * 8.0 + 50.0  # the rig section's default top drive, string side
KP, KI, T_MAX = 2e4, 4e4, 50e3
RPM, RAMP_S = 40.0, 5.0
MUD_TORSION = 0.05  # N m s/rad per m
ZETA = 0.02
T_END, T_FROM = 60.0, 20.0


def _omega_set(t: float) -> float:
    target = RPM * math.pi / 30.0
    return target * t / RAMP_S if t < RAMP_S else target


def _wall_mu(v: np.ndarray) -> np.ndarray:
    """tanh-exponential wall friction coefficient with the climb factor, signed like v."""
    av = np.abs(v)
    mu = np.tanh(av / V_T) * (MU_D + (MU_S - MU_D) * np.exp(-av / V_S))
    return np.sign(v) * mu / np.sqrt(1.0 + mu * mu)


def lumped_reference(n_pipe: int = 20) -> tuple[dict[str, np.ndarray], float]:
    """Torsional chain under wall friction; returns the traces and the static wall torque (N m)."""
    a_p = math.pi / 4.0 * (PIPE_OD**2 - PIPE_ID**2)
    j_p = math.pi / 32.0 * (PIPE_OD**4 - PIPE_ID**4)
    a_c = math.pi / 4.0 * (COLLAR_OD**2 - COLLAR_ID**2)
    j_c = math.pi / 32.0 * (COLLAR_OD**4 - COLLAR_ID**4)
    h = PIPE_L / n_pipe
    n = n_pipe + 1
    inertia = np.full(n, RHO_S * j_p * h)
    inertia[-1] = RHO_S * j_c * COLLAR_L
    k = np.full(n, G_SHEAR * j_p / h)
    k[0] = G_SHEAR * j_p / (0.5 * h)  # rotary to the first lump's centre
    k[-1] = 1.0 / (0.5 * h / (G_SHEAR * j_p) + 0.5 * COLLAR_L / (G_SHEAR * j_c))
    c_spring = 2.0 * ZETA * np.sqrt(k * np.minimum(inertia, np.r_[inertia[0], inertia[:-1]]))
    c_mud = MUD_TORSION * np.r_[np.full(n_pipe, h), COLLAR_L]
    radius = np.r_[np.full(n_pipe, PIPE_OD / 2.0), COLLAR_OD / 2.0]
    sin_i = math.sin(math.radians(INC_DEG))
    wall = (RHO_S - RHO_M) * G * sin_i * np.r_[np.full(n_pipe, a_p * h), a_c * COLLAR_L]

    def rhs(t: float, y: np.ndarray) -> np.ndarray:
        phi, om = y[3: 3 + n], y[3 + n:]
        e = _omega_set(t) - y[1]
        u = KP * e + KI * y[2]
        zdot = 0.0 if (u > T_MAX and e > 0.0) or (u < -T_MAX and e < 0.0) else e
        u = min(max(u, -T_MAX), T_MAX)
        t_el = k * (np.r_[y[0], phi[:-1]] - phi) + c_spring * (np.r_[y[1], om[:-1]] - om)
        acc = t_el.copy()
        acc[:-1] -= t_el[1:]
        acc -= c_mud * om + radius * wall * _wall_mu(radius * om)
        dy = np.empty_like(y)
        dy[0], dy[1], dy[2] = y[1], (u - t_el[0]) / TD_INERTIA, zdot
        dy[3: 3 + n] = om
        dy[3 + n:] = acc / inertia
        return dy

    t_eval = np.linspace(0.0, T_END, int(T_END * 200) + 1)
    sol = solve_ivp(rhs, (0.0, T_END), np.zeros(3 + 2 * n), method="LSODA", t_eval=t_eval,
                    rtol=1e-6, atol=1e-8, max_step=0.01)
    assert sol.success, sol.message
    e = np.array([_omega_set(t) for t in sol.t]) - sol.y[1]
    torque = np.clip(KP * e + KI * sol.y[2], -T_MAX, T_MAX)
    static = float((radius * wall).sum()) * MU_S / math.sqrt(1.0 + MU_S**2)
    return {"t": sol.t, "omega_bit": sol.y[-1], "torque_surface": torque}, static


def simulate() -> dict[str, np.ndarray]:
    cfg = case_from_dict({
        "string": {"components": [
            {"type": "collar", "od_m": COLLAR_OD, "id_m": COLLAR_ID, "length_m": COLLAR_L,
             "n_segments": 1},
            {"type": "drill_pipe", "od_m": PIPE_OD, "id_m": PIPE_ID, "length_m": PIPE_L,
             "n_segments": 10}]},
        "operation": {"duration_s": T_END, "bit_md_m": 2210.0, "top_md_m": 10.0, "rpm": RPM,
                      "rpm_ramp_s": RAMP_S, "bit_on_bottom": False, "top_axial": "fixed",
                      "mud_density_kg_per_m3": RHO_M,
                      "mud_damping_torsional_N_m_s_per_m": MUD_TORSION},
        "friction": {"model": "tanh_exp", "mu_static": MU_S, "mu_dynamic": MU_D,
                     "v_t_m_per_s": V_T, "v_s_m_per_s": V_S},
        "bit": {"model": "yigit_christoforou"},
        "solver": {"relax_s": 0.5, "joint_damping_ratio": ZETA, "boundary_damping_ratio": ZETA},
        "rig": {"block_mode": "held", "rock": {"lobe_amplitude_m": 0.0},
                "top_drive": {"tuning": "pi", "kp_Nm_s_per_rad": KP, "ki_Nm_per_rad": KI,
                              "torque_limit_Nm": T_MAX}},
        "recording": {"loads_rate_hz": 10.0, "channels_rate_hz": 200.0, "kinematics_rate_hz": 1.0},
    })
    model, state = build_model(cfg, straight_path(2400.0, inclination_deg=INC_DEG))
    every = max(1, round(0.005 / model.dt))
    ch = advance_model(model, state, round(T_END / model.dt), every=every)["channels"]
    return {"t": ch[:, 0], "omega_bit": ch[:, 1 + L.H_BITRPM] * math.pi / 30.0,
            "torque_surface": ch[:, 1 + L.H_TSURF], "wob": ch[:, 1 + L.H_WOB]}


def test_off_bottom_stick_slip_from_wall_friction_matches_the_lumped_reference() -> None:
    sim = simulate()
    assert np.abs(sim["wob"]).max() == 0.0  # off bottom all along: no bit torque
    target = RPM * math.pi / 30.0
    got = stick_slip_metrics(sim, target, T_FROM)
    ref_traces, static = lumped_reference()
    ref = stick_slip_metrics(ref_traces, target, T_FROM)
    print(f"off-bottom stick-slip: simulator {got}, reference {ref}, static wall torque {static:.0f} N m")
    assert ref["n_cycles"] >= 3 and got["n_cycles"] >= 3, (ref, got)
    assert got["break_off_Nm"] == pytest.approx(ref["break_off_Nm"], rel=0.10), (ref, got)
    assert got["period_s"] == pytest.approx(ref["period_s"], rel=0.20), (ref, got)
    # to break free the top drive has to carry at least the static wall friction
    assert got["break_off_Nm"] > static and ref["break_off_Nm"] > static
