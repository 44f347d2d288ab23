"""Reference models for the rig boundaries (block, top drive), reused by tests.

``TorsionalWell`` and :func:`torsional_reference`: a torsional lumped model of a
drill string (pipe as N inertias on torsion springs, a BHA inertia with
Stribeck friction off bottom and, on bottom, the bit law) driven by a PI
top-drive speed controller, integrated by scipy's LSODA at tight
tolerances. It is written from the equations alone (its own PI with
conditional integration, its own friction), independent of the numba
kernels. :func:`torsional_with_kernels` integrates the same chain with the
kernels the simulator will call (``rig.top_drive_step``,
``bitrock.bit_response``) in a fixed-step semi-implicit Euler loop, as the
simulator's boundaries room will. :func:`stick_slip_metrics` measures
period, break-off torque and severity the same way on both.

:func:`single_mass_autodriller`: the block kernel in autodriller mode on a
single-mass axial model of the string (a lumped mass on the string spring,
standing on a rock spring-dashpot, mud drag, a rock face advancing at
``c WOB``), started in steady drilling at ``W0`` with a set-point step to
``W1``; its closed-form reference is ``rig.second_order_step``.

The well (stated here, not a published one): 2000 m of 5 in 19.5 lb/ft drill
pipe (J_p = 1.188e-5 m^4, G = 79.6 GPa, rho = 7850 kg/m^3) above 200 m of
6 3/4 in x 2.81 in collars (J = 8.23e-5 m^4, treated as rigid: 129 kg m^2),
in 1.2 SG mud; off-bottom friction of the BHA and lower string lumped at the
BHA: static 8 kN m, dynamic (Coulomb) 5 kN m, Stribeck speed 1 rad/s; the top
drive of :class:`drillfatigue.config.rig.TopDriveConfig` (932 kg m^2 on the
string side) with a stiff PI (Kp = 2e4 N m s/rad, about 70x the pipe impedance of 297 N m s/rad,
Ki = 4e4 N m/rad), 40 rpm after a 5 s ramp.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numba import njit
from scipy.integrate import solve_ivp

from drillfatigue.dynamics.bit import laws as BR
from drillfatigue.dynamics.top import rig as R

G_SHEAR = 79.6e9
RHO = 7850.0
JP_PIPE = math.pi / 32.0 * (0.127**4 - 0.1086**4)
JP_COLLAR = math.pi / 32.0 * (0.17145**4 - 0.0714**4)


@dataclass(frozen=True)
class TorsionalWell:
    """Parameters of the lumped torsional model (SI)."""

    pipe_length_m: float = 2000.0
    n_pipe: int = 10
    bha_inertia_kg_m2: float = RHO * JP_COLLAR * 200.0
    gj_Nm2: float = G_SHEAR * JP_PIPE
    pipe_inertia_per_m_kg_m: float = RHO * JP_PIPE
    mud_damping_Nms_per_rad_per_m: float = 0.05  # viscous torque per length per rad/s
    spring_damping_ratio: float = 0.02
    t_static_Nm: float = 8e3
    t_coulomb_Nm: float = 5e3
    omega_stribeck_rad_s: float = 1.0
    omega_reg_rad_s: float = 0.01  # tanh regularisation of the friction sign
    td_inertia_kg_m2: float = 10.5**2 * 8.0 + 50.0
    kp_Nms_per_rad: float = 2e4
    ki_Nm_per_rad: float = 4e4
    torque_limit_Nm: float = 50e3
    rpm: float = 40.0
    ramp_s: float = 5.0
    wob_N: float = 0.0  # > 0: on bottom, bit law of the bit section defaults

    @property
    def h(self) -> float:
        return self.pipe_length_m / self.n_pipe

    def inertias(self) -> np.ndarray:
        """Node inertias: pipe lumps 1..N (node N carries the BHA too)."""
        j = np.full(self.n_pipe, self.pipe_inertia_per_m_kg_m * self.h)
        j[-1] += self.bha_inertia_kg_m2
        return j

    def k(self) -> float:
        return self.gj_Nm2 / self.h

    def c_spring(self) -> float:
        return 2.0 * self.spring_damping_ratio * math.sqrt(self.k() * self.pipe_inertia_per_m_kg_m * self.h)

    def c_mud(self) -> float:
        return self.mud_damping_Nms_per_rad_per_m * self.h

    def bit_params(self) -> np.ndarray:
        from drillfatigue.config.bit import BitConfig
        return BR.pack_bit_params(BitConfig(model="yigit_christoforou"))[1]


def omega_set(t: float, w: TorsionalWell) -> tuple[float, float]:
    """Speed set-point (rad/s) and its rate: linear ramp to rpm over ramp_s, then held."""
    target = w.rpm * 2.0 * math.pi / 60.0
    if t < w.ramp_s:
        return target * t / w.ramp_s, target / w.ramp_s
    return target, 0.0


def friction_torque(omega: float, w: TorsionalWell) -> float:
    """Stribeck friction of the BHA (regularised sign), N m, resisting omega."""
    mag = w.t_coulomb_Nm + (w.t_static_Nm - w.t_coulomb_Nm) * math.exp(-abs(omega) / w.omega_stribeck_rad_s)
    return mag * math.tanh(omega / w.omega_reg_rad_s)


def torsional_reference(w: TorsionalWell, tuning: str = "pi", t_end: float = 60.0,
                        n_out: int = 60001) -> dict[str, np.ndarray]:
    """LSODA integration of the lumped model; returns ``t, omega_bit, omega_top, torque_surface``.

    State: ``[phi_td, omega_td, z (PI integral), phi_1..phi_N, omega_1..omega_N]``.
    ``tuning``: ``pi`` (PI top drive with its inertia) or ``stiff`` (speed imposed).
    """
    n = w.n_pipe
    jn = w.inertias()
    k, cs, cm = w.k(), w.c_spring(), w.c_mud()
    bp = w.bit_params()
    out2 = np.empty(2)

    def drive(t: float, y: np.ndarray) -> tuple[float, float, float, float]:
        ws, wr = omega_set(t, w)
        if tuning == "stiff":
            return ws, wr, 0.0, 0.0
        e = ws - y[1]
        u = w.kp_Nms_per_rad * e + w.ki_Nm_per_rad * y[2]
        zdot = e
        if (u > w.torque_limit_Nm and e > 0) or (u < -w.torque_limit_Nm and e < 0):
            zdot = 0.0
        return y[1], 0.0, min(max(u, -w.torque_limit_Nm), w.torque_limit_Nm), zdot

    def rhs(t: float, y: np.ndarray) -> np.ndarray:
        phi = y[3: 3 + n]
        om = y[3 + n:]
        w_td, _, u, zdot = drive(t, y)
        phi_td = y[0]
        up = np.concatenate([[phi_td], phi[:-1]])
        wup = np.concatenate([[w_td], om[:-1]])
        t_el = k * (up - phi) + cs * (wup - om)  # torque carried by each element (top first)
        acc = t_el.copy()
        acc[:-1] -= t_el[1:]
        acc -= cm * om
        acc[-1] -= friction_torque(om[-1], w)
        if w.wob_N > 0.0:
            BR.bit_response(BR.YIGIT_CHRISTOFOROU, bp, w.wob_N, om[-1], out2)
            acc[-1] -= out2[0]
        dy = np.empty_like(y)
        if tuning == "stiff":
            ws, wr = omega_set(t, w)
            dy[0], dy[1], dy[2] = ws, wr, 0.0
        else:
            dy[0] = y[1]
            dy[1] = (u - t_el[0]) / w.td_inertia_kg_m2
            dy[2] = zdot
        dy[3: 3 + n] = om
        dy[3 + n:] = acc / jn
        return dy

    y0 = np.zeros(3 + 2 * n)
    t_eval = np.linspace(0.0, t_end, n_out)
    sol = solve_ivp(rhs, (0.0, t_end), y0, method="LSODA", t_eval=t_eval, rtol=1e-7, atol=1e-9,
                    max_step=0.01)
    assert sol.success, sol.message
    y = sol.y
    om_td = y[1] if tuning == "pi" else np.array([omega_set(t, w)[0] for t in sol.t])
    phi_td = y[0]
    t_top = k * (phi_td - y[3]) + cs * (om_td - y[3 + n])
    if tuning == "pi":
        e = np.array([omega_set(t, w)[0] for t in sol.t]) - y[1]
        torque = np.clip(w.kp_Nms_per_rad * e + w.ki_Nm_per_rad * y[2], -w.torque_limit_Nm, w.torque_limit_Nm)
    else:
        torque = t_top + w.td_inertia_kg_m2 * np.array([omega_set(t, w)[1] for t in sol.t])
    return {"t": sol.t, "omega_bit": y[-1], "omega_top": om_td, "torque_surface": torque}


@njit(cache=True)
def _kernel_loop(mode, tdp, jn, k, cs, cm, ts, tc, wstr, wreg, wob, bp, target, ramp, dt, n_steps,
                 every, out):
    n = jn.shape[0]
    phi = np.zeros(n)
    om = np.zeros(n)
    s = np.zeros(R.N_TD_S)
    t_el = np.zeros(n)
    o2 = np.zeros(2)
    j = 0
    for step in range(n_steps):
        t = step * dt
        if t < ramp:
            ws = target * t / ramp
            wr = target / ramp
        else:
            ws = target
            wr = 0.0
        # element torques from the current state (top element attached to the quill)
        t_el[0] = k * (s[R.TS_PHI] - phi[0]) + cs * (s[R.TS_OMEGA] - om[0])
        for i in range(1, n):
            t_el[i] = k * (phi[i - 1] - phi[i]) + cs * (om[i - 1] - om[i])
        R.top_drive_step(mode, tdp, s, ws, wr, t_el[0], dt)
        for i in range(n):
            a = t_el[i] - cm * om[i]
            if i < n - 1:
                a -= t_el[i + 1]
            else:
                mag = tc + (ts - tc) * math.exp(-abs(om[i]) / wstr)
                a -= mag * math.tanh(om[i] / wreg)
                if wob > 0.0:
                    BR.bit_response(BR.YIGIT_CHRISTOFOROU, bp, wob, om[i], o2)
                    a -= o2[0]
            om[i] += dt * a / jn[i]
        for i in range(n):
            phi[i] += dt * om[i]
        if (step + 1) % every == 0:
            out[j, 0] = t + dt
            out[j, 1] = om[n - 1]
            out[j, 2] = s[R.TS_OMEGA]
            out[j, 3] = s[R.TS_T]
            j += 1
    return j


def torsional_with_kernels(w: TorsionalWell, tuning: str = "pi", t_end: float = 60.0, dt: float = 1e-4,
                           kp: float | None = None, ki: float | None = None) -> dict[str, np.ndarray]:
    """The same chain stepped with ``rig.top_drive_step`` (fixed step, semi-implicit Euler)."""
    mode = R.TOP_DRIVE_STIFF if tuning == "stiff" else R.TOP_DRIVE_PI
    tdp = np.zeros(R.N_TD_P)
    tdp[R.TP_J] = w.td_inertia_kg_m2
    tdp[R.TP_KP] = w.kp_Nms_per_rad if kp is None else kp
    tdp[R.TP_KI] = w.ki_Nm_per_rad if ki is None else ki
    tdp[R.TP_TMAX] = w.torque_limit_Nm
    n_steps = int(round(t_end / dt))
    every = max(1, int(round(1e-3 / dt)))
    out = np.zeros((n_steps // every + 1, 4))
    m = _kernel_loop(mode, tdp, w.inertias(), w.k(), w.c_spring(), w.c_mud(), w.t_static_Nm,
                     w.t_coulomb_Nm, w.omega_stribeck_rad_s, w.omega_reg_rad_s, w.wob_N, w.bit_params(),
                     w.rpm * 2.0 * math.pi / 60.0, w.ramp_s, dt, n_steps, every, out)
    out = out[:m]
    return {"t": out[:, 0], "omega_bit": out[:, 1], "omega_top": out[:, 2], "torque_surface": out[:, 3]}


def stick_slip_metrics(res: dict[str, np.ndarray], omega_target: float, t_from: float) -> dict[str, float]:
    """Stick-slip period (s), break-off torque (N m), severity, stuck fraction, from ``t >= t_from``.

    A slip starts where the bit speed rises through half the target after
    having been below 10 % of it (stuck); the period is the median time
    between slip starts; the break-off torque is the median of the largest
    surface torque of each cycle; the severity is (max - min) / mean bit speed;
    the stuck fraction is the share of the (evenly spaced) samples with the bit's
    speed below 10 % of the target in magnitude.
    """
    t = res["t"]
    sel = t >= t_from
    t, wb, tq = t[sel], res["omega_bit"][sel], res["torque_surface"][sel]
    starts = []
    armed = False
    for i in range(1, t.size):
        if wb[i] < 0.1 * omega_target:
            armed = True
        if armed and wb[i - 1] < 0.5 * omega_target <= wb[i]:
            starts.append(i)
            armed = False
    out = {"severity": float((wb.max() - wb.min()) / max(abs(wb.mean()), 1e-12)),
           "n_cycles": float(max(len(starts) - 1, 0)), "period_s": math.nan, "break_off_Nm": math.nan,
           "stuck_fraction": float(np.mean(np.abs(wb) < 0.1 * omega_target))}
    if len(starts) >= 3:
        st = np.array(starts)
        out["period_s"] = float(np.median(np.diff(t[st])))
        peaks = [tq[a:b].max() for a, b in zip(st[:-1], st[1:], strict=True)]
        out["break_off_Nm"] = float(np.median(peaks))
    return out


# --- autodriller on a single-mass string ---------------------------------------------------

G = 9.80665
M = 40e3  # kg
KS = 7e5  # N/m: 1000 m of 5 in drill pipe, EA/L
KR = 5e7  # N/m rock contact
CR = 2.0 * 0.2 * math.sqrt(KR * M)  # 20 % of critical, the rig config's rock damping default
K_EFF = 1.0 / (1.0 / KS + 1.0 / KR)
CM = 2.0 * 0.2 * math.sqrt(K_EFF * M)  # mud drag on the mass: 20 % of critical of the axial mode
C_ROP = (20.0 / 3600.0) / 1e5  # 20 m/h at 100 kN
KP, KI = 5.7e-7, 5.7e-8
W0, W1 = 50e3, 80e3


def single_mass_autodriller(mode: int, ts: float, kp: float = KP, ki: float = KI, t_end: float = 60.0,
              dt: float = 1e-3) -> tuple[np.ndarray, np.ndarray]:
    v0 = C_ROP * W0
    p = np.zeros(R.N_BLOCK_P)
    p[R.BP_VMAX], p[R.BP_AMAX], p[R.BP_TRAVEL] = 1.5, 0.5, 1e3
    p[R.BP_WOBSET], p[R.BP_KP], p[R.BP_KI], p[R.BP_TS] = W1, kp, ki, ts
    p[R.BP_HOFF] = M * G  # the autodriller's zero: the off-bottom hook load
    p[R.BP_ROPLIM] = 1.0
    s = R.new_block_state(10.0, v0)
    s[R.BS_I] = v0 / ki  # steady drilling at W0: the integral holds the block at the ROP
    s[R.BS_VCMD] = v0
    # equilibrium at W0: rock at 0, mass W0/KR into it, string stretched by (M g - W0)/KS
    r = 0.0
    y = W0 / KR
    x0 = s[R.BS_X]
    yd = v0
    off = y - x0 - (M * G - W0 - CM * yd) / KS  # so that the mass is in equilibrium at t = 0
    n = int(round(t_end / dt))
    t = np.empty(n)
    wob = np.empty(n)
    for k in range(n):
        xb = s[R.BS_X]
        h = KS * (y - xb - off)
        w = max(0.0, KR * (y - r) + CR * (yd - C_ROP * KR * (y - r)))
        R.block_step(mode, p, s, w, h, dt)
        yd += dt * (M * G - h - w - CM * yd) / M
        y += dt * yd
        r += dt * C_ROP * w
        t[k] = (k + 1) * dt
        wob[k] = w
    return t, wob
